/* semloc — what the semantic model asks of the filter (BatchLikelihood's hooks): its detection
 * counts, its detector's outages, its likelihood with no object in view, its look-alike
 * memory and the poses a detection places. */
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/models/semantic/DetectionPoseSampler.h>
#include <semloc/models/semantic/LookAlikeMemory.h>
#include <semloc/observation/CObservationSemantic.h>

namespace semloc
{
namespace
{
/** The look-alike memory of one semantic map, on the filter's side: the clutter factors of
 *  each remembered observation's detections are its context. */
class FilterLookAlikes final : public BatchLikelihood::Memory
{
public:
    explicit FilterLookAlikes(const CSemanticMap& map) : m_map(map) {}

    void remember(const mrpt::obs::CObservation& obs, const mrpt::math::TPose2D& odometry,
                  std::vector<double>& context, double& logLikWithoutMap) override
    {
        m_memory.note(static_cast<const CObservationSemantic&>(obs), m_map, odometry, context);
        for (const double f : context)
        {
            logLikWithoutMap += f;  // the same densities with no object in view
        }
    }

private:
    const CSemanticMap& m_map;
    LookAlikeMemory m_memory;
};

bool probabilistic(const CSemanticMap& map)
{
    return map.likelihoodOptions.model == CSemanticMap::Model::Probabilistic;
}
}  // namespace

BatchLikelihood::TObservationPlan CSemanticMap::plan(const mrpt::obs::CObservation& obs) const
{
    TObservationPlan p;
    const auto& lo = likelihoodOptions;
    const auto* detections = dynamic_cast<const CObservationSemantic*>(&obs);
    if (detections)
    {
        const auto c = check(*detections);
        p.checked = true;
        p.invalid = c.invalid;
        p.unknown = c.unknown;
        // Silent: nothing of the map's objects reported. Detections of what the map does not
        // know (other vehicles, divers) weigh every pose alike, so a frame of them only is,
        // for the map's objects, an empty one: a view blocked by them is not evidence against
        // the poses that should see objects, scan after scan.
        p.silent = c.used == 0 && c.invalid == 0;
        p.logLikWithoutMap = logLikelihoodWithoutObjects(*detections, &p.readingsWithoutMap);
        p.remembered = lo.lookalike.lookalike_persistence > 0 && probabilistic(*this);
    }
    else if (const auto* br = dynamic_cast<const mrpt::obs::CObservationBearingRange*>(&obs))
    {
        p.silent = br->sensedData.empty();
        p.logLikWithoutMap = logLikelihoodWithoutObjects(*br, &p.readingsWithoutMap);
    }
    if (lo.outage.outage_every_s > 0 && probabilistic(*this))
    {
        p.outage_every_s = lo.outage.outage_every_s;
        p.outage_mean_s = lo.outage.outage_mean_s;
    }
    return p;
}

std::unique_ptr<BatchLikelihood::Memory> CSemanticMap::newMemory() const
{
    return std::make_unique<FilterLookAlikes>(*this);
}

void CSemanticMap::logLikelihoodsRemembering(const mrpt::obs::CObservation& obs,
                                             const std::vector<double>& context,
                                             const mrpt::math::TPose2D* poses, size_t n,
                                             double* out) const
{
    computeLogLikelihoods(static_cast<const CObservationSemantic&>(obs), poses, n, out,
                          context.data());
}

std::unique_ptr<BatchLikelihood::PoseProposal> CSemanticMap::proposal(
    const mrpt::obs::CSensoryFrame& sf) const
{
    const auto obs = sf.getObservationByClass<CObservationSemantic>();
    if (!obs)
    {
        return nullptr;
    }
    auto sampler = std::make_unique<DetectionPoseSampler>(*this, *obs);
    if (sampler->empty())
    {
        return nullptr;  // nothing the map can place
    }
    return sampler;
}

std::string CSemanticMap::needsStandardProposal() const
{
    return likelihoodOptions.outage.outage_every_s > 0
               ? "the semantic map's outage_every_s > 0 (detector outage model)"
               : "";
}

size_t CSemanticMap::approximations() const
{
    return associationsApproximated();
}

}  // namespace semloc
