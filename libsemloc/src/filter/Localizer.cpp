/* semloc — Localizer: the frames it accepts, the initial cloud, the steps (its options are in
 * LocalizerOptions.cpp). */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/filter/Localizer.h>
#include <semloc/filter/MotionModelRegistry.h>
#include <semloc/filter/ParallelExecutor.h>
#include <semloc/models/SensorModelRegistry.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <limits>
#include <string_view>

#include "filter/SensorModels.h"

namespace semloc
{
using mrpt::bayes::CParticleFilter;

namespace
{
mrpt::obs::CActionRobotMovement2D::TMotionModelOptions odometryModel(const Localizer::TOptions& o)
{
    const MotionModelConfig model(o.motion_model);
    if (model.rederives())
    {
        return model.gaussian();  // [MotionModel] source = gaussian: every increment's noise
    }
    // pf-localization's model of the odometry of observations-only rawlogs.
    mrpt::obs::CActionRobotMovement2D::TMotionModelOptions m;
    m.modelSelection = mrpt::obs::CActionRobotMovement2D::mmGaussian;
    m.gaussianModel.minStdXY = o.odometry_min_std_xy;
    m.gaussianModel.minStdPHI = mrpt::DEG2RAD(o.odometry_min_std_phi_deg);
    return m;
}

/** A range reading no sensor can return: NaN, +-inf, negative, beyond the scan's maxRange
 *  (or any reading of a scan whose maxRange is itself not a positive number). */
bool impossibleRange(float z, float maxRange)
{
    return !std::isfinite(z) || z < 0 || !(maxRange > 0) || !std::isfinite(maxRange) ||
           z > maxRange;
}

/** A copy of a scan without the cached points map the original may hold (a copy would
 *  share it, and it holds the beams being made invalid). */
struct UncachedScan : public mrpt::obs::CObservation2DRangeScan
{
    explicit UncachedScan(const mrpt::obs::CObservation2DRangeScan& scan)
        : mrpt::obs::CObservation2DRangeScan(scan)
    {
        m_cachedMap.reset();
    }
};

/** `sf`, or in `copy` (true then) the same frame without the observations
 *  Localizer::invalidObservation() rejects (their number added to `invalid`) and with every
 *  valid beam of impossible range made invalid (their number added to `beams`). */
bool withValidObservations(const mrpt::obs::CSensoryFrame& sf, const mrpt::maps::CMetricMap& map,
                           mrpt::obs::CSensoryFrame& copy, size_t& invalid, size_t& beams)
{
    bool replaced = false;
    auto replace = [&](size_t i)
    {
        if (!replaced)
        {
            for (size_t j = 0; j < i; j++)
            {
                copy.insert(sf.getObservationByIndex(j));
            }
            replaced = true;
        }
    };
    for (size_t i = 0; i < sf.size(); i++)
    {
        auto obs = sf.getObservationByIndex(i);
        if (obs && !Localizer::invalidObservation(*obs, map).empty())
        {
            invalid++;
            replace(i);
            continue;
        }
        if (const auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs))
        {
            const size_t n = scan->getScanSize();
            size_t bad = 0;
            for (size_t k = 0; k < n; k++)
            {
                bad += scan->getScanRangeValidity(k) &&
                       impossibleRange(scan->getScanRange(k), scan->maxRange);
            }
            if (bad > 0)
            {
                auto fixed = std::make_shared<UncachedScan>(*scan);
                for (size_t k = 0; k < n; k++)
                {
                    if (impossibleRange(fixed->getScanRange(k), fixed->maxRange))
                    {
                        fixed->setScanRangeValidity(k, false);
                    }
                }
                beams += bad;
                obs = fixed;
                replace(i);
            }
        }
        if (replaced)
        {
            copy.insert(obs);
        }
    }
    return replaced;
}

/** `acts`, or in `copy` its 2D movement of least uncertainty marked so that MRPT's
 *  CActionCollection::getBestMovementEstimation() returns it. That function, which every
 *  prediction step calls (MRPT's and CParallelMonteCarloLocalization2D's), ignores a 2D
 *  movement whose covariance determinant is 1e3 or more (odometry with a few metres or tens
 *  of degrees of noise, or a long step) unless it is a scan-matching estimate, which it
 *  returns at once: such odometry would look like none. The mark changes nothing else of
 *  the prediction: the movement's pose PDF is what the filter samples. */
const mrpt::obs::CActionCollection& withUsableMovement(const mrpt::obs::CActionCollection& acts,
                                                       mrpt::obs::CActionCollection& copy)
{
    if (acts.getBestMovementEstimation())
    {
        return acts;
    }
    const mrpt::obs::CActionRobotMovement2D* best = nullptr;
    double bestDet = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < acts.size(); k++)
    {
        const auto* m = dynamic_cast<const mrpt::obs::CActionRobotMovement2D*>(&acts.get(k));
        if (m && m->poseChange)
        {
            const double det = m->poseChange->getCovariance().det();
            if (std::isfinite(det) && det < bestDet)
            {
                best = m;
                bestDet = det;
            }
        }
    }
    if (!best)
    {
        return acts;  // no 2D movement (a 3D one, or none): MRPT's own handling
    }
    mrpt::obs::CActionRobotMovement2D marked(*best);
    marked.estimationMethod = mrpt::obs::CActionRobotMovement2D::emScan2DMatching;
    copy.clear();
    copy.insert(marked);
    return copy;
}

bool finiteSensorPose(const mrpt::poses::CPose3D& p)
{
    return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()) &&
           std::isfinite(p.yaw()) && std::isfinite(p.pitch()) && std::isfinite(p.roll());
}

/** MRPT's warnings (e.g. CParallelMonteCarloLocalization2D's re-initializations) on stderr:
 *  MRPT's console output prints every level but errors on stdout. */
void toStderr(std::string_view msg, mrpt::system::VerbosityLevel level, std::string_view logger,
              mrpt::Clock::time_point)
{
    const char* what = level >= mrpt::system::LVL_ERROR  ? "error"
                       : level == mrpt::system::LVL_WARN ? "warning"
                                                         : "info";
    std::cerr << "[" << what << "|" << logger << "] " << msg;
    if (msg.empty() || msg.back() != '\n')
    {
        std::cerr << '\n';
    }
    std::cerr.flush();
}
/** The options that need particular maps in [MetricMap]. */
void checkAgainstMaps(const Localizer::TOptions& o, const mrpt::maps::CMultiMetricMap& map)
{
    const auto models = detail::sensorModels(map);
    if (o.init_PDF_mode == Localizer::InitMode::FromDetections &&
        std::none_of(models.begin(), models.end(), [](const auto* m) { return m->proposes(); }))
    {
        THROW_EXCEPTION(
            "init_PDF_mode = 3 (from the first detections) needs a semanticMap in "
            "[MetricMap] (or another map that proposes poses from its observations)");
    }
    if (o.recovery.trigger == RecoveryTrigger::Evidence && !weighsWithoutMaps(map))
    {
        THROW_EXCEPTION(
            "[Recovery] trigger = evidence weighs the semantic detections against "
            "the map with no object in view: it needs semantic maps only in [MetricMap] (amcl "
            "works with any map)");
    }
    if (o.pf.PF_algorithm != mrpt::bayes::CParticleFilter::pfStandardProposal)
    {
        for (const auto* m : models)
        {
            if (const auto why = m->needsStandardProposal(); !why.empty())
            {
                THROW_EXCEPTION(why + " needs [PF_options] PF_algorithm = 0 (pfStandardProposal)");
            }
        }
    }
}
}  // namespace

bool weighsWithoutMaps(const mrpt::maps::CMultiMetricMap& map)
{
    return !map.maps.empty() && std::all_of(map.maps.begin(), map.maps.end(),
                                            [](const auto& m)
                                            {
                                                const auto* model =
                                                    dynamic_cast<const BatchLikelihood*>(m.get());
                                                return model && model->weighsWithoutMap();
                                            });
}

std::string Localizer::invalidObservation(const mrpt::obs::CObservation& obs,
                                          const mrpt::maps::CMetricMap& map)
{
    mrpt::poses::CPose3D pose;
    obs.getSensorPose(pose);
    if (!finiteSensorPose(pose))
    {
        return "its sensorPose is not finite";
    }
    if (std::max({std::abs(pose.x()), std::abs(pose.y()), std::abs(pose.z())}) > kMaxSensorOffset_m)
    {
        return mrpt::format("its sensorPose (%g, %g, %g) is more than %g m from the vehicle",
                            pose.x(), pose.y(), pose.z(), kMaxSensorOffset_m);
    }
    if (const auto* scan = dynamic_cast<const mrpt::obs::CObservation2DRangeScan*>(&obs))
    {
        if (!std::isfinite(scan->aperture) || scan->aperture < 0)
        {
            return mrpt::format("its aperture %g is not a finite angle >= 0",
                                static_cast<double>(scan->aperture));
        }
        if (scan->getScanSize() == 0)
        {
            return "it has no beam";
        }
    }
    for (const auto& kind : SensorModelRegistry::kinds())
    {
        if (auto why = kind->invalidObservation(obs, map); !why.empty())
        {
            return why;
        }
    }
    return "";
}

// ------------------------------------------------------------------ localizer

Localizer::Localizer(const TOptions& options, mrpt::maps::CMultiMetricMap::Ptr map,
                     const World* world)
    : mrpt::system::COutputLogger("Localizer"),
      m_options(options),
      m_map(std::move(map)),
      m_executor(std::make_shared<ParallelExecutor>(options.effectiveThreads())),
      m_pdf(std::make_unique<CParallelMonteCarloLocalization2D>())
{
    ASSERTMSG_(m_map, "Localizer: no map");
    for (mrpt::system::COutputLogger* logger :
         {static_cast<mrpt::system::COutputLogger*>(this),
          static_cast<mrpt::system::COutputLogger*>(&m_pf),
          static_cast<mrpt::system::COutputLogger*>(m_pdf.get())})
    {
        logger->logging_enable_console_output = false;
        logger->logRegisterCallback(toStderr);
    }
    const auto& o = m_options;
    m_pf.m_options = o.pf;
    m_pf.m_options.sampleSize = static_cast<unsigned>(o.particles_count);
    m_pdf->options.metricMap = m_map;
    m_pdf->options.KLD_params = o.kld;
    m_pdf->setExecutor(m_executor);
    m_pdf->setRecoveryOptions(o.recovery);
    m_pdf->setFreeSpacePrior(o.free_space_prior);
    m_pdf->setKldAtResampling(o.kld_at_resampling);
    // [MotionModel] kind, with the section's options (odometry: its heading drift).
    m_pdf->setMotionModel(MotionModelRegistry::create(o.motion_model));

    TSamplingArea area;
    area.x_min = o.init_PDF_min_x;
    area.x_max = o.init_PDF_max_x;
    area.y_min = o.init_PDF_min_y;
    area.y_max = o.init_PDF_max_y;
    area.yaw_min = mrpt::DEG2RAD(o.init_PDF_min_yaw_deg);
    area.yaw_max = mrpt::DEG2RAD(o.init_PDF_max_yaw_deg);
    const auto grid = m_map->mapByClass<mrpt::maps::COccupancyGridMap2D>();
    if (world)
    {
        m_freeSpace = std::make_shared<FreeSpaceSampler>(FreeSpaceSampler::FromWorld(*world));
        m_initSpace = std::make_shared<FreeSpaceSampler>(FreeSpaceSampler::FromWorld(*world, area));
    }
    else if (grid)
    {
        m_freeSpace = std::make_shared<FreeSpaceSampler>(FreeSpaceSampler::FromGrid(*grid));
        m_initSpace = std::make_shared<FreeSpaceSampler>(FreeSpaceSampler::FromGrid(*grid, area));
    }
    else if (area.hasBox())
    {
        m_freeSpace = m_initSpace =
            std::make_shared<FreeSpaceSampler>(FreeSpaceSampler::FromBox(area));
    }
    if (o.init_PDF_mode == InitMode::Box && !area.hasBox())
    {
        THROW_EXCEPTION("init_PDF_mode = 1 (uniform in a box) needs a non-empty init_PDF box");
    }
    if (!m_freeSpace &&
        (o.init_PDF_mode == InitMode::FreeSpace || o.init_PDF_mode == InitMode::FromDetections))
    {
        THROW_EXCEPTION("init_PDF_mode = " + std::to_string(static_cast<int>(o.init_PDF_mode)) +
                        " (uniform over the free space) needs a world (map_file *.yaml), an "
                        "occupancyGrid map or an init_PDF_min/max_x/y box");
    }
    checkAgainstMaps(o, *m_map);
    m_pdf->setFreeSpaceSampler(m_freeSpace);
    m_pdf->prepareLikelihood();

    // A fresh generator, not randomize(seed): randomize() re-seeds the Mersenne twister but
    // keeps std::normal_distribution's cached second value, so the first Gaussian draw of a
    // second filter in the same process depended on the draws of the one before.
    mrpt::random::getRandomGenerator() = mrpt::random::CRandomGenerator(o.seed);
    reset();
}

Localizer::~Localizer() = default;

void Localizer::reset()
{
    const auto& o = m_options;
    const auto M = static_cast<size_t>(o.particles_count);
    auto& rng = mrpt::random::getRandomGenerator();
    m_seededFromDetections = false;
    m_initializedFromDetections = 0;
    m_pdf->resetDetectorOutage();
    m_pdf->resetRecoveryTrigger();
    // The maps count for every user: this filter's share is what it adds from here.
    m_approximatedBefore = associationsApproximatedNow();
    switch (o.init_PDF_mode)
    {
        case InitMode::FreeSpace:
        case InitMode::FromDetections:
        {
            auto& parts = m_pdf->m_particles;
            parts.resize(M);
            for (auto& p : parts)
            {
                p.d = m_initSpace->draw(rng);
                p.log_w = 0;
            }
            break;
        }
        case InitMode::Box:
            m_pdf->resetUniform(o.init_PDF_min_x, o.init_PDF_max_x, o.init_PDF_min_y,
                                o.init_PDF_max_y, mrpt::DEG2RAD(o.init_PDF_min_yaw_deg),
                                mrpt::DEG2RAD(o.init_PDF_max_yaw_deg), static_cast<int>(M));
            break;
        case InitMode::Gaussian:
        {
            auto& parts = m_pdf->m_particles;
            parts.resize(M);
            const double sYaw = mrpt::DEG2RAD(o.init_PDF_std_yaw_deg);
            for (auto& p : parts)
            {
                const double x = o.init_PDF_mean_x + rng.drawGaussian1D(0, o.init_PDF_std_xy);
                const double y = o.init_PDF_mean_y + rng.drawGaussian1D(0, o.init_PDF_std_xy);
                const double phi =
                    mrpt::DEG2RAD(o.init_PDF_mean_yaw_deg) + rng.drawGaussian1D(0, sYaw);
                p.d = mrpt::math::TPose2D(x, y, mrpt::math::wrapToPi(phi));
                p.log_w = 0;
            }
            break;
        }
    }
    m_pdf->resetMotionState();
    m_odometryDelay = OdometryDelay(o.motion_model.odometry_delay_s);
    m_last = TStepInfo();
    m_last.particles = m_pdf->size();
}

void Localizer::step(const mrpt::obs::CActionCollection& action, const mrpt::obs::CSensoryFrame& sf)
{
    mrpt::obs::CSensoryFrame checked;
    const bool replaced =
        withValidObservations(sf, *m_map, checked, m_observationsInvalid, m_beamsInvalid);
    mrpt::obs::CActionCollection rederived, marked, delayed;
    const mrpt::obs::CActionCollection& acts = m_odometryDelay.apply(
        withUsableMovement(MotionModelConfig(m_options.motion_model).apply(action, rederived),
                           marked),
        sf, delayed);
    m_lastMovement.reset();
    if (const auto move = acts.getBestMovementEstimation())
    {
        m_lastMovement = *move;
    }
    // The standard proposal resamples inside its step and keeps the ESS before it; asking
    // executeOn for TParticleFilterStats there would read 1 and cost two exp() and two
    // virtual calls per particle (its weight variance). The other algorithms run MRPT's
    // step: their ESS comes from the stats.
    if (m_options.init_PDF_mode == InitMode::FromDetections && !m_seededFromDetections)
    {
        seedFromDetections(acts, replaced ? checked : sf);
    }
    const bool ours = m_pf.m_options.PF_algorithm == CParticleFilter::pfStandardProposal;
    CParticleFilter::TParticleFilterStats stats;
    const auto t0 = std::chrono::steady_clock::now();
    m_pf.executeOn(*m_pdf, &acts, replaced ? &checked : &sf, ours ? nullptr : &stats);
    const auto t1 = std::chrono::steady_clock::now();
    m_last.update_us = std::chrono::duration<double, std::micro>(t1 - t0).count();
    m_last.ess_before_resampling = ours ? m_pdf->essBeforeResampling() : stats.ESS_beforeResample;
    m_last.particles = m_pdf->size();
    m_steps++;
}

double Localizer::headingDriftDegPerMin() const
{
    return m_pdf->headingDriftRate() / kRadPerSecondPerDegPerMinute;
}

void Localizer::seedFromDetections(const mrpt::obs::CActionCollection& action,
                                   const mrpt::obs::CSensoryFrame& sf)
{
    const auto sampler = detail::poseProposal(sf, m_map.get());
    if (!sampler)
    {
        return;  // nothing the maps can place: wait for the next frame
    }
    m_seededFromDetections = true;
    // A pose q drawn for the detection's time is placed at q (+) increment^-1: this step's
    // prediction moves it by the increment (with its noise) to about q before the frame
    // weighs it.
    mrpt::poses::CPose2D back;
    if (const auto move = action.getBestMovementEstimation())
    {
        back = -move->poseChange->getMeanVal();
    }
    auto& rng = mrpt::random::getRandomGenerator();
    size_t drawn = 0;
    for (auto& p : m_pdf->m_particles)
    {
        p.log_w = 0;
        if (rng.drawUniform(0.0, 1.0) >= m_options.init_PDF_from_detections)
        {
            continue;  // stays where the uniform start put it
        }
        for (int tries = 0; tries < 10; tries++)
        {
            const mrpt::math::TPose2D q = sampler->draw(rng);
            if (m_initSpace->contains(q.x, q.y))
            {
                p.d = (mrpt::poses::CPose2D(q) + back).asTPose();
                drawn++;
                break;
            }
        }
    }
    m_initializedFromDetections = drawn;
    // The seeded particles are the initial cloud: they keep the states drawn with it.
    m_pdf->adoptParticles();
}

void Localizer::setOdometry(const mrpt::obs::CObservationOdometry& odo)
{
    m_pendingOdometry = odo.odometry;
    if (!m_lastOdometry)
    {
        m_lastOdometry = odo.odometry;  // the reference of the first increment
    }
}

void Localizer::step(const mrpt::obs::CSensoryFrame& sf)
{
    mrpt::poses::CPose2D increment;
    if (m_pendingOdometry && m_lastOdometry)
    {
        increment = *m_pendingOdometry - *m_lastOdometry;
        m_lastOdometry = m_pendingOdometry;
    }
    mrpt::obs::CActionRobotMovement2D act;
    act.computeFromOdometry(increment, odometryModel(m_options));
    mrpt::obs::CActionCollection acts;
    acts.insert(act);
    step(acts, sf);
}

size_t Localizer::associationsApproximatedNow() const
{
    size_t n = 0;
    for (const auto* m : detail::sensorModels(*m_map))
    {
        n += m->approximations();
    }
    return n;
}

SensoryFrameLikelihood::TStats Localizer::likelihoodStats() const
{
    auto s = m_pdf->likelihoodStats();
    s.beams_invalid = m_beamsInvalid;
    s.observations_invalid = m_observationsInvalid;
    s.associations_approximated = associationsApproximatedNow() - m_approximatedBefore;
    return s;
}

mrpt::poses::CPose2D Localizer::mean() const
{
    return m_pdf->getMeanVal();
}

double Localizer::varianceXY() const
{
    const auto [cov, mean] = m_pdf->getCovarianceAndMean();
    (void)mean;
    return cov(0, 0) + cov(1, 1);
}

TStepRecord Localizer::lastStepRecord(const mrpt::obs::CSensoryFrame& sf) const
{
    TStepRecord r;
    r.step = m_steps > 0 ? m_steps - 1 : 0;
    r.t = std::numeric_limits<double>::quiet_NaN();
    if (sf.size() > 0 && sf.getObservationByIndex(0)->timestamp != INVALID_TIMESTAMP)
    {
        r.t = mrpt::Clock::toDouble(sf.getObservationByIndex(0)->timestamp);
    }
    const auto [cov, poseCov, mean] = m_pdf->covariancesAndMean();
    r.est = mean.asTPose();
    r.var_xy = cov(0, 0) + cov(1, 1);
    r.setPoseCovariance(poseCov);
    r.ess = m_last.ess_before_resampling;
    r.n_particles = m_last.particles;
    r.update_us = m_last.update_us;
    return r;
}

size_t Localizer::threads() const
{
    return m_executor->threads();
}

std::string Localizer::freeSpaceDescription() const
{
    return m_freeSpace ? m_freeSpace->description() : "none";
}

}  // namespace semloc
