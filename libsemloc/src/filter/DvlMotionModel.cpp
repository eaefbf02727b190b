/* semloc — DvlMotionModel: body-frame increments with noise a share of the distance. */
#include <mrpt/core/exceptions.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/filter/DvlMotionModel.h>

#include <algorithm>
#include <cmath>

#include "filter/MotionSampling.h"

namespace semloc
{
namespace
{
constexpr double kDeg = M_PI / 180;

/** The step's increment: the raw odometry reading, else the pose change's mean. */
mrpt::math::TPose2D incrementOf(const mrpt::obs::CActionCollection& actions)
{
    const auto move = actions.getBestMovementEstimation();
    if (!move)
    {
        THROW_EXCEPTION(
            "[MotionModel] kind = dvl: the step has no CActionRobotMovement2D (the DVL's "
            "body-frame increment)");
    }
    const auto& raw = move->rawOdometryIncrementReading;
    const bool hasRaw = move->estimationMethod == mrpt::obs::CActionRobotMovement2D::emOdometry &&
                        (raw.x() != 0 || raw.y() != 0 || raw.phi() != 0);
    mrpt::math::TPose2D u;
    if (hasRaw || !move->poseChange)
    {
        u = raw.asTPose();
    }
    else
    {
        u = move->poseChange->getMeanVal().asTPose();
    }
    if (!std::isfinite(u.x) || !std::isfinite(u.y) || !std::isfinite(u.phi))
    {
        THROW_EXCEPTION("[MotionModel] kind = dvl: the step's increment is not finite");
    }
    return u;
}
}  // namespace

void DvlMotionModel::prepare(const TMotionStep& step, mrpt::random::CRandomGenerator& rng)
{
    m_increment = incrementOf(step.actions);
    const double d = std::hypot(m_increment.x, m_increment.y);
    m_sigmaXY = std::max(m_noise.a1 * d, m_noise.minStdXY);
    m_sigmaPhi = std::max(m_noise.a3_deg * kDeg * d + m_noise.a4 * std::abs(m_increment.phi),
                          m_noise.minStdPHI_deg * kDeg);
    m_key = (static_cast<uint64_t>(rng.drawUniform32bit()) << 32) | rng.drawUniform32bit();
    m_prepared = true;
}

namespace
{
/** The step's increment with its noise, drawn from a particle's normals (movePoses). */
struct BodyFrameDrawer
{
    mrpt::math::TPose2D increment;
    double sigmaXY, sigmaPhi;

    mrpt::math::TPose2D draw(detail::ParticleNormals& normals) const
    {
        const double n0 = normals(), n1 = normals(), n2 = normals();
        return {increment.x + sigmaXY * n0, increment.y + sigmaXY * n1,
                increment.phi + sigmaPhi * n2};
    }
};
}  // namespace

void DvlMotionModel::move(size_t i0, size_t n, mrpt::math::TPose2D* poses, double*) const
{
    ASSERTMSG_(m_prepared, "DvlMotionModel::move() without prepare()");
    detail::movePoses(BodyFrameDrawer{m_increment, m_sigmaXY, m_sigmaPhi}, m_key, poses, i0, n);
}

}  // namespace semloc
