/* semloc — CSemanticMap's likelihood entry points: the observation's detections prepared
 * once per call, then the fast kernels over blocks of particles. */
#include <semloc/models/semantic/CSemanticMap.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "math/FastMath.h"
#include "models/semantic/LabelIndex.h"
#include "models/semantic/SemanticAssociation.h"
#include "models/semantic/SemanticIndex.h"
#include "models/semantic/SemanticLikelihoodKernels.h"
#include "models/semantic/SemanticLikelihoodState.h"

using mrpt::math::TPose2D;

namespace semloc
{
namespace
{
using semantic::Scratch;

/** This thread's scratch. The thread-local holds a pointer only: the static TLS of a library
 *  dlopen'ed by an MRPT app (rawlog-edit -p libsemloc.so) must stay within the few hundred
 *  bytes glibc keeps for it, whatever the size of Scratch. */
Scratch& scratch()
{
    thread_local std::unique_ptr<Scratch> s;
    if (!s)
    {
        s = std::make_unique<Scratch>();
    }
    return *s;
}

/** What a likelihood call knows of the sensor, fixed for all particles of a step. */
struct Sensor
{
    bool usable = false;  // false: nothing to score, every particle gets 0
    double R = 0, fov = 0, ox = 0, oy = 0, oyaw = 0;
};

Sensor sensorOf(double R, double fov, const mrpt::poses::CPose3D& onVehicle)
{
    Sensor s;
    s.R = R;
    s.fov = fov;
    s.usable = R > 0 && std::isfinite(R) && fov > 0 && std::isfinite(fov);
    s.ox = onVehicle.x();
    s.oy = onVehicle.y();
    s.oyaw = onVehicle.yaw();
    return s;
}

/** Wraps a bearing into [-pi, pi] (detectors may report [0, 2pi)). */
double wrapBearing(double b)
{
    return (b >= -M_PI && b <= M_PI) ? b : std::remainder(b, 2 * M_PI);
}

/** Fills sc.dets with the detections the likelihood uses (once per observation). */
Sensor prepare(const CObservationSemantic& obs, const CSemanticMap::TLikelihoodOptions& lo,
               const CSemanticMap::Index& ix, const LabelIndex& labels, Scratch& sc,
               const double* clutterLogFactors = nullptr)
{
    const double R = lo.detector.max_range_m > 0 ? lo.detector.max_range_m : obs.maxRange_m;
    const double fov = lo.detector.fov_deg > 0 ? lo.detector.fov_deg * M_PI / 180.0 : obs.fov_rad;
    const Sensor s = sensorOf(R, fov, obs.sensorPose);
    sc.dets.clear();
    if (!s.usable)
    {
        return s;
    }
    for (const auto& d : obs.detections)
    {
        if (!CObservationSemantic::isValid(d, R, fov) || d.confidence < lo.detector.min_confidence)
        {
            continue;
        }
        int32_t fixed = -1;
        if (d.object_id >= 0)
        {
            const auto it = ix.idToSorted.find(d.object_id);
            fixed = it == ix.idToSorted.end() ? -1 : it->second;
        }
        const int32_t label = labels.find(d.label);
        if (fixed < 0 && label < 0)
        {
            continue;  // unknown to the map: a constant factor at every particle
        }
        sc.dets.push_back(semantic::makeDet(lo.correctedRange(d.range_m, d.bearing_rad, R, fov),
                                            d.bearing_rad, label, fixed));
        if (clutterLogFactors)
        {
            // The look-alike persistence's clutter density, kappa e^factor (factor >= 0).
            sc.dets.back().clutterShift = clutterLogFactors[&d - obs.detections.data()];
        }
    }
    return s;
}

Sensor prepare(const mrpt::obs::CObservationBearingRange& obs,
               const CSemanticMap::TLikelihoodOptions& lo, const CSemanticMap::Index& ix,
               const LabelIndex& /*labels*/, Scratch& sc,
               const double* /*clutterLogFactors*/ = nullptr)
{
    const double R = lo.detector.max_range_m > 0 ? lo.detector.max_range_m : obs.maxSensorDistance;
    double fov = lo.detector.fov_deg > 0 ? lo.detector.fov_deg * M_PI / 180.0
                                         : static_cast<double>(obs.fieldOfView_yaw);
    if (fov == 0)
    {
        fov = 2 * M_PI;  // MRPT leaves it 0 when the sensor has no FOV limit
    }
    const Sensor s = sensorOf(R, fov, obs.sensorLocationOnRobot);
    sc.dets.clear();
    if (!s.usable)
    {
        return s;
    }
    for (const auto& m : obs.sensedData)
    {
        const double r = m.range, b = m.yaw;
        if (!(r >= 0 && r <= R) || !(std::abs(b) <= 4 * M_PI) ||
            std::abs(wrapBearing(b)) > 0.5 * fov + 1e-9)
        {
            continue;
        }
        int32_t fixed = -1;
        if (m.landmarkID >= 0)
        {
            const auto it = ix.idToSorted.find(m.landmarkID);
            if (it == ix.idToSorted.end())
            {
                continue;  // an id the map does not have
            }
            fixed = it->second;
        }
        sc.dets.push_back(semantic::makeDet(lo.correctedRange(r, b, R, fov), b, -1, fixed));
    }
    return s;
}
/** The model's constants for a usable sensor `s` (cached in sc.consts). */
semantic::ModelConsts modelConsts(const CSemanticMap::TLikelihoodOptions& lo,
                                  const CSemanticMap::Index& ix, size_t nLabels, const Sensor& s,
                                  Scratch& sc)
{
    return semantic::cachedModelConsts(lo, nLabels, s.R, s.fov,
                                       {ix.maxSigma, ix.minExist, !ix.classRow.empty()}, sc.consts);
}
}  // namespace

template <typename OBS>
void CSemanticMap::likelihoodsOf(const OBS& obs, const TPose2D* poses, size_t n, double* out,
                                 const double* clutterLogFactors) const
{
    Scratch& sc = scratch();
    const Sensor s = prepare(obs, likelihoodOptions, *m_index, *m_labels, sc, clutterLogFactors);
    const size_t nLabels = m_labels->size();
    const semantic::ModelConsts k = s.usable
                                        ? modelConsts(likelihoodOptions, *m_index, nLabels, s, sc)
                                        : semantic::ModelConsts();
    semantic::planPairsOnce(sc, *m_index, nLabels, k);
    if (!s.usable)
    {
        std::fill(out, out + n, 0.0);  // nothing usable: uninformative, the same everywhere
        return;
    }
    // The sensor geometry of every particle of a block first (independent short chains the
    // CPU overlaps across particles), then the matching, which reads it.
    sc.vis = detail::visTableFor(*m_index, s.R, s.fov, sc.visHandle);
    constexpr size_t kBlock = 256;
    semantic::Geom geoms[kBlock];
    const semantic::GeomConsts gc = semantic::geomConsts(sc.trig, s.ox, s.oy, s.oyaw, s.R, s.fov);
    for (size_t i0 = 0; i0 < n; i0 += kBlock)
    {
        const size_t m = std::min(kBlock, n - i0);
        // The headings' sin and cos two at a time (the same bits as one at a time).
        detail::forEachSinCos(
            m, [&](size_t i) { return poses[i0 + i].phi; },
            [&](size_t i, double sp, double cp)
            { geoms[i] = semantic::makeGeom(gc, poses[i0 + i], sp, cp); });
        if (likelihoodOptions.model == Model::Paper)
        {
            semantic::scorePaperBlock(*m_index, k, sc, geoms, poses + i0, m, out + i0);
            continue;
        }
        semantic::scoreProbabilisticBlock(*m_index, likelihoodOptions, k, sc, geoms, poses + i0, m,
                                          out + i0);
    }
    if (sc.approximated > 0)
    {
        m_approximated += sc.approximated;
        sc.approximated = 0;
    }
}

template <typename OBS>
double CSemanticMap::withoutObjects(const OBS& obs, size_t* used) const
{
    Scratch& sc = scratch();
    const Sensor s = prepare(obs, likelihoodOptions, *m_index, *m_labels, sc);
    const size_t l = s.usable ? sc.dets.size() : 0;
    if (used != nullptr)
    {
        *used = l;
    }
    if (!s.usable)
    {
        return 0;
    }
    const semantic::ModelConsts k =
        modelConsts(likelihoodOptions, *m_index, m_labels->size(), s, sc);
    // What the kernels give when no object is in view: every detection unmatched.
    return likelihoodOptions.model == Model::Paper
               ? static_cast<double>(l) * k.logPu
               : -k.lambda + static_cast<double>(l) * k.logKappa;
}

double CSemanticMap::logLikelihoodWithoutObjects(const CObservationSemantic& obs,
                                                 size_t* used) const
{
    return withoutObjects(obs, used);
}

double CSemanticMap::logLikelihoodWithoutObjects(const mrpt::obs::CObservationBearingRange& obs,
                                                 size_t* used) const
{
    return withoutObjects(obs, used);
}

double CSemanticMap::computeLogLikelihood(const CObservationSemantic& obs,
                                          const TPose2D& pose) const
{
    double ll = 0;
    likelihoodsOf(obs, &pose, 1, &ll);
    return ll;
}

double CSemanticMap::computeLogLikelihood(const mrpt::obs::CObservationBearingRange& obs,
                                          const TPose2D& pose) const
{
    double ll = 0;
    likelihoodsOf(obs, &pose, 1, &ll);
    return ll;
}

void CSemanticMap::computeLogLikelihoods(const CObservationSemantic& obs, const TPose2D* poses,
                                         size_t n, double* out) const
{
    likelihoodsOf(obs, poses, n, out);
}

void CSemanticMap::computeLogLikelihoods(const CObservationSemantic& obs, const TPose2D* poses,
                                         size_t n, double* out,
                                         const double* clutterLogFactors) const
{
    likelihoodsOf(obs, poses, n, out, clutterLogFactors);
}

double CSemanticMap::clutterDensity(const CObservationSemantic& obs) const
{
    const double R = likelihoodOptions.maxRange(obs);
    const double fov = std::min(likelihoodOptions.fieldOfView(obs), 2 * M_PI);
    const double labels = static_cast<double>(std::max<size_t>(1, m_labels->size()));
    return R > 0 && fov > 0 ? likelihoodOptions.probabilistic.clutter_per_scan / (R * fov * labels)
                            : 0.0;
}

void CSemanticMap::computeLogLikelihoods(const mrpt::obs::CObservationBearingRange& obs,
                                         const TPose2D* poses, size_t n, double* out) const
{
    likelihoodsOf(obs, poses, n, out);
}

bool CSemanticMap::uses(const mrpt::obs::CObservation& obs) const
{
    return dynamic_cast<const CObservationSemantic*>(&obs) != nullptr ||
           dynamic_cast<const mrpt::obs::CObservationBearingRange*>(&obs) != nullptr;
}

void CSemanticMap::logLikelihoods(const mrpt::obs::CObservation& obs, const TPose2D* poses,
                                  size_t n, double* out) const
{
    if (const auto* s = dynamic_cast<const CObservationSemantic*>(&obs))
    {
        likelihoodsOf(*s, poses, n, out);
    }
    else if (const auto* br = dynamic_cast<const mrpt::obs::CObservationBearingRange*>(&obs))
    {
        likelihoodsOf(*br, poses, n, out);
    }
    else
    {
        std::fill_n(out, n, 0.0);  // not used: no term (uses() is false)
    }
}

CSemanticMap::TObservationCheck CSemanticMap::check(const CObservationSemantic& obs) const
{
    TObservationCheck c;
    for (const auto& d : obs.detections)
    {
        if (!isUsable(obs, d))
        {
            c.invalid++;
        }
        else if (m_labels->find(d.label) < 0 &&
                 (d.object_id < 0 || !m_index->idToSorted.count(d.object_id)))
        {
            c.unknown++;
        }
        else
        {
            c.used++;
        }
    }
    return c;
}

bool CSemanticMap::isUsable(const CObservationSemantic& obs, const TSemanticDetection& d) const
{
    const auto& lo = likelihoodOptions;
    const double R = lo.detector.max_range_m > 0 ? lo.detector.max_range_m : obs.maxRange_m;
    const double fov = lo.detector.fov_deg > 0 ? lo.detector.fov_deg * M_PI / 180.0 : obs.fov_rad;
    return CObservationSemantic::isValid(d, R, fov) && d.confidence >= lo.detector.min_confidence;
}

std::vector<size_t> CSemanticMap::candidatesOf(const CObservationSemantic& obs,
                                               const TSemanticDetection& d) const
{
    std::vector<size_t> out;
    if (!isUsable(obs, d))
    {
        return out;
    }
    // As the likelihood associates: by id when the map knows it, else by label.
    if (d.object_id >= 0 && m_index->idToSorted.count(d.object_id))
    {
        for (size_t i = 0; i < m_objects.size(); i++)
        {
            if (m_objects[i].id == d.object_id)
            {
                out.push_back(i);
            }
        }
        return out;
    }
    for (size_t i = 0; i < m_objects.size(); i++)
    {
        if (m_objects[i].label == d.label)
        {
            out.push_back(i);
        }
    }
    return out;
}

bool CSemanticMap::internal_canComputeObservationLikelihood(
    const mrpt::obs::CObservation& obs) const
{
    return dynamic_cast<const CObservationSemantic*>(&obs) != nullptr ||
           dynamic_cast<const mrpt::obs::CObservationBearingRange*>(&obs) != nullptr;
}

double CSemanticMap::internal_computeObservationLikelihood(
    const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& takenFrom) const
{
    const TPose2D pose(takenFrom.x(), takenFrom.y(), takenFrom.yaw());
    if (const auto* o = dynamic_cast<const CObservationSemantic*>(&obs))
    {
        return computeLogLikelihood(*o, pose);
    }
    if (const auto* br = dynamic_cast<const mrpt::obs::CObservationBearingRange*>(&obs))
    {
        return computeLogLikelihood(*br, pose);
    }
    return 0;
}
}  // namespace semloc
