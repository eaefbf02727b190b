/* semloc — RunDetectorBound: the detector's Cramér–Rao bound of a localization run. */
#include "experiment/RunDetectorBound.h"

#include <mrpt/core/bits_math.h>

#include <Eigen/Dense>

#include <cmath>
#include <limits>

namespace semloc::detail
{
namespace
{
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/** True when the map's objects are the world's, in its order, at their centres. */
bool sameObjects(const CSemanticMap& map, const World& world)
{
    const auto& objects = map.objects();
    if (objects.size() != world.objects.size())
    {
        return false;
    }
    for (size_t i = 0; i < objects.size(); i++)
    {
        const auto& w = world.objects[i];
        if (objects[i].id != w.id || objects[i].x != w.center.x || objects[i].y != w.center.y)
        {
            return false;
        }
    }
    return true;
}

/** The Gaussian of the increment `move` carries (at the measured increment). */
mrpt::poses::CPosePDFGaussian carried(const mrpt::obs::CActionRobotMovement2D& move)
{
    const auto [cov, mean] = move.poseChange->getCovarianceAndMean();
    return mrpt::poses::CPosePDFGaussian(mean, cov);
}
}  // namespace

mrpt::math::CMatrixDouble33 incrementCovariance(const mrpt::obs::CActionRobotMovement2D& move,
                                                const mrpt::poses::CPose2D& trueIncrement)
{
    using mrpt::obs::CActionRobotMovement2D;
    const mrpt::math::CMatrixDouble33 cov = move.poseChange->getCovariance();
    const auto& model = move.motionModelConfiguration;
    if (model.modelSelection != CActionRobotMovement2D::mmGaussian)
    {
        return cov;  // Thrun's model draws samples (from the filter's generator): not redone
    }
    CActionRobotMovement2D again;
    again.computeFromOdometry(move.rawOdometryIncrementReading, model);
    const mrpt::math::CMatrixDouble33 redone = again.poseChange->getCovariance();
    const double scale = cov.asEigen().norm();
    if (!(std::isfinite(scale) && (redone.asEigen() - cov.asEigen()).norm() <= 1e-6 * scale))
    {
        return cov;  // not that model's: the rawlog's own noise
    }
    again.computeFromOdometry(trueIncrement, model);
    return again.poseChange->getCovariance();
}

RunDetectorBound::RunDetectorBound(const LocalizationMap& maps, const Localizer::TOptions& filter)
    : m_maps(maps.map), m_recursion(filter.motion_model.headingDrift())
{
    m_map = m_maps ? m_maps->mapByClass<CSemanticMap>() : nullptr;
    if (m_map && m_map->isEmpty())
    {
        m_map.reset();
    }
    if (m_map && maps.world && !maps.world->outlineSegments().empty() &&
        sameObjects(*m_map, *maps.world))
    {
        m_sight.emplace(*maps.world, SemanticDetectorModel::TOptions());
    }
}

void RunDetectorBound::add(const TStepRecord& r, const mrpt::obs::CSensoryFrame& sf,
                           const mrpt::obs::CActionRobotMovement2D* movement,
                           const RunMetrics& soFar)
{
    if (!m_map)
    {
        return;
    }
    if (movement && !movement->poseChange)
    {
        movement = nullptr;  // no pose change: no movement to predict by
    }
    if (!r.gt)
    {
        // Left out: its movement joins the increment to the next step with ground truth.
        if (m_recursion.started())
        {
            if (!movement)
            {
                m_lost = true;
            }
            else if (!m_lost)
            {
                m_span = m_span ? *m_span + carried(*movement) : carried(*movement);
            }
        }
        return;
    }
    moveTo(*r.gt, r, movement);
    update(*r.gt, sf);
    const double b = m_recursion.bound().mean_err_xy_m;
    if (soFar.converged && soFar.convergence_step == static_cast<long>(r.step))
    {
        // A new candidate of the convergence step (the final one is one of them).
        m_convStep = soFar.convergence_step;
        m_sumSince = 0;
        m_countSince = 0;
    }
    m_sum += b;
    m_count++;
    m_sumSince += b;
    m_countSince++;
}

void RunDetectorBound::moveTo(const mrpt::math::TPose2D& pose, const TStepRecord& r,
                              const mrpt::obs::CActionRobotMovement2D* movement)
{
    if (!m_recursion.started() || m_lost || !movement)
    {
        m_recursion.restart(pose);
    }
    else
    {
        const mrpt::poses::CPose2D u =
            mrpt::poses::CPose2D(pose) - mrpt::poses::CPose2D(m_recursion.pose());
        const mrpt::math::CMatrixDouble33 cov =
            m_span ? (*m_span + carried(*movement)).cov : incrementCovariance(*movement, u);
        const double dt = r.t - m_lastT;
        m_recursion.predict(pose, cov, std::isfinite(dt) ? dt : 0.0);
    }
    m_span.reset();
    m_lost = false;
    m_lastT = r.t;
}

void RunDetectorBound::update(const mrpt::math::TPose2D& pose, const mrpt::obs::CSensoryFrame& sf)
{
    const auto& opt = m_map->likelihoodOptions;
    const mrpt::poses::CPose3D vehicle(pose);
    for (const auto& o : sf)
    {
        const auto* obs = dynamic_cast<const CObservationSemantic*>(o.get());
        if (!obs || !Localizer::invalidObservation(*obs, *m_maps).empty())
        {
            continue;
        }
        const double R = opt.maxRange(*obs), fov = opt.fieldOfView(*obs);
        TDetectorBoundSensor sensor;
        sensor.sigma_range_m = opt.detector.sigma_range_m;
        sensor.sigma_bearing_rad = mrpt::DEG2RAD(opt.detector.sigma_bearing_deg);
        sensor.detectionProbability = [&opt, R, fov](double rho, double theta)
        { return opt.detectionProbability(rho, R, theta, fov); };
        sensor.sensorPose = obs->sensorPose;
        const mrpt::poses::CPose3D s = vehicle + obs->sensorPose;
        std::vector<mrpt::math::TPoint2D> visible;
        for (const auto& v : m_map->objectsInView(*obs, vehicle))
        {
            if (!m_sight || m_sight->inLineOfSight({s.x(), s.y()}, v.index))
            {
                visible.emplace_back(m_map->objects()[v.index].x, m_map->objects()[v.index].y);
            }
        }
        m_recursion.update(visible, sensor);
    }
}

double RunDetectorBound::mean() const
{
    return m_count > 0 ? m_sum / static_cast<double>(m_count) : kNaN;
}

double RunDetectorBound::meanAfterConvergence(const RunMetrics& m) const
{
    if (!m.converged || m.convergence_step != m_convStep || m_countSince == 0)
    {
        return kNaN;
    }
    return m_sumSince / static_cast<double>(m_countSince);
}

}  // namespace semloc::detail
