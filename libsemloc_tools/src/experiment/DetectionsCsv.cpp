/* semloc — detections.csv: what each semantic detection of a run did to the weights. */
#include "experiment/DetectionsCsv.h"

#include <mrpt/core/bits_math.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPose3D.h>
#include <semloc/observation/CObservationSemantic.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <limits>

namespace semloc::detail
{
namespace
{
std::string num(double v)
{
    return mrpt::format("%.9g", v);
}
}  // namespace

DetectionsCsv::DetectionsCsv(const std::string& path, const CSemanticMap& map)
    : m_path(path), m_out(path, std::ios::binary), m_map(map)
{
    m_out << "step,t,k,label,range_m,bearing_deg,est_object,est_d2,est_gain,gt_object,gt_d2,"
             "gt_gain\n";
    if (!m_out)
    {
        THROW_EXCEPTION("cannot write '" + m_path + "': " + std::strerror(errno));
    }
}

std::string DetectionsCsv::explain(const CObservationSemantic& obs, size_t k,
                                   const mrpt::math::TPose2D& pose) const
{
    const TSemanticDetection& d = obs.detections[k];
    const auto& lo = m_map.likelihoodOptions;
    const double sr = lo.detector.sigma_range_m, sb = mrpt::DEG2RAD(lo.detector.sigma_bearing_deg);
    const auto candidates = m_map.candidatesOf(obs, d);
    std::string object;
    double best = std::numeric_limits<double>::infinity();
    for (const auto& v : m_map.objectsInView(obs, mrpt::poses::CPose3D(pose)))
    {
        if (std::find(candidates.begin(), candidates.end(), v.index) == candidates.end())
        {
            continue;
        }
        const double er = (d.range_m - v.range_m) / sr;
        const double eb = mrpt::math::wrapToPi(d.bearing_rad - v.bearing_rad) / sb;
        if (er * er + eb * eb < best)
        {
            best = er * er + eb * eb;
            object = std::to_string(m_map.objects()[v.index].id);
        }
    }
    CObservationSemantic without = obs;
    without.detections.erase(without.detections.begin() + static_cast<ptrdiff_t>(k));
    const double gain =
        m_map.computeLogLikelihood(obs, pose) - m_map.computeLogLikelihood(without, pose);
    return object + "," + (object.empty() ? std::string() : num(best)) + "," + num(gain);
}

void DetectionsCsv::add(const TStepRecord& r, const mrpt::obs::CSensoryFrame& sf)
{
    const auto obs = sf.getObservationByClass<CObservationSemantic>();
    if (!obs)
    {
        return;
    }
    const std::string prefix =
        std::to_string(r.step) + "," + (std::isnan(r.t) ? "" : mrpt::format("%.6f", r.t)) + ",";
    std::string rows;
    for (size_t k = 0; k < obs->detections.size(); k++)
    {
        const TSemanticDetection& d = obs->detections[k];
        if (m_map.candidatesOf(*obs, d).empty())
        {
            continue;  // not used by the likelihood (invalid, out of coverage, unknown label)
        }
        rows += prefix + std::to_string(k) + "," + d.label + "," + num(d.range_m) + "," +
                num(mrpt::RAD2DEG(d.bearing_rad)) + "," + explain(*obs, k, r.est) + "," +
                (r.gt ? explain(*obs, k, *r.gt) : std::string(",,")) + "\n";
    }
    m_out << rows;
}

void DetectionsCsv::finish()
{
    m_out.close();
    if (!m_out)
    {
        THROW_EXCEPTION("cannot write '" + m_path + "' (disk full?)");
    }
}
}  // namespace semloc::detail
