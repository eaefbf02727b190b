/* semloc — the odometry's motion model: Gaussian increments drawn per particle, MRPT's sampler
 * otherwise, and the heading drift as a state of every particle. */
#include <mrpt/core/exceptions.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/random/RandomGenerators.h>
#include <mrpt/system/datetime.h>
#include <semloc/filter/ParticleMotionModel.h>

#include <cmath>

#include "filter/MotionSampling.h"

namespace semloc
{
OdometryMotionModel::OdometryMotionModel() = default;
OdometryMotionModel::~OdometryMotionModel() = default;

void OdometryMotionModel::setHeadingDrift(double priorStd, double walkStd)
{
    ASSERT_(std::isfinite(priorStd) && priorStd >= 0 && std::isfinite(walkStd) && walkStd >= 0);
    m_priorStd = priorStd;
    m_walkStd = walkStd;
}

void OdometryMotionModel::drawState(double* state, mrpt::random::CRandomGenerator& rng) const
{
    if (headingDrift())
    {
        state[0] = m_priorStd * rng.drawGaussian1D_normalized();
    }
}

double OdometryMotionModel::elapsed(const TMotionStep& step)
{
    mrpt::Clock::time_point t = INVALID_TIMESTAMP;
    if (step.frame && step.frame->size() > 0)
    {
        t = step.frame->getObservationByIndex(0)->timestamp;
    }
    if (t == INVALID_TIMESTAMP && step.actions.size() > 0)
    {
        t = step.actions.get(0).timestamp;
    }
    if (t == INVALID_TIMESTAMP)
    {
        THROW_EXCEPTION(
            "[MotionModel] heading_drift_*: the heading drift model needs timestamped "
            "observations (every frame's first observation, or its odometry action, carries "
            "its time)");
    }
    double dt = 0;
    if (m_last && t > *m_last)
    {
        dt = mrpt::system::timeDifference(*m_last, t);
    }
    if (!m_last || t > *m_last)
    {
        m_last = t;
    }
    return dt;
}

void OdometryMotionModel::prepare(const TMotionStep& step, mrpt::random::CRandomGenerator& rng)
{
    m_dt = headingDrift() ? elapsed(step) : 0;
    m_walk = m_walkStd * std::sqrt(m_dt);
    m_drawer.reset();
    m_sampled = false;
    if (const auto gauss = detail::gaussianMotion(step.actions))
    {
        // One key per step from MRPT's generator (the seed decides it); each particle's
        // numbers from (key, index), drawn on any thread.
        m_key = (static_cast<uint64_t>(rng.drawUniform32bit()) << 32) | rng.drawUniform32bit();
        m_drawer = std::make_unique<detail::GaussianIncrementDrawer>(*gauss);
        return;
    }
    prepareSampled(step, rng);
}

void OdometryMotionModel::prepareSampled(const TMotionStep& step,
                                         mrpt::random::CRandomGenerator& rng)
{
    // Any other odometry (MRPT's Thrun particles, 3D actions): MRPT's sampler, as
    // PF_SLAM_implementation_pfStandardProposal, on this thread.
    if (const auto mov2D = step.actions.getBestMovementEstimation())
    {
        ASSERT_(mov2D->poseChange);
        m_sampler.setPosePDF(*mov2D->poseChange);
    }
    else if (const auto mov3D = step.actions.getActionByClass<mrpt::obs::CActionRobotMovement3D>())
    {
        m_sampler.setPosePDF(mov3D->poseChange);
    }
    else
    {
        THROW_EXCEPTION(
            "Action list does not contain any CActionRobotMovement2D or CActionRobotMovement3D "
            "object!");
    }
    m_increments.resize(step.particles);
    for (size_t i = 0; i < step.particles; i++)
    {
        m_sampler.drawSample(m_increments[i]);
        if (headingDrift())
        {
            // The rate off the increment's yaw, then its walk.
            double& rate = step.states[i];
            auto& inc = m_increments[i];
            inc.setYawPitchRoll(inc.yaw() - rate * m_dt, inc.pitch(), inc.roll());
            rate += m_walk * rng.drawGaussian1D_normalized();
        }
    }
    m_sampled = true;
}

void OdometryMotionModel::move(size_t i0, size_t n, mrpt::math::TPose2D* poses,
                               double* states) const
{
    if (m_drawer)
    {
        const detail::DriftStep drift{states, m_dt, m_walk};
        detail::movePoses(*m_drawer, m_key, poses, i0, n, headingDrift() ? &drift : nullptr);
        return;
    }
    ASSERTMSG_(m_sampled && i0 + n <= m_increments.size(),
               "OdometryMotionModel::move() without prepare() for these particles");
    for (size_t k = 0; k < n; k++)
    {
        const mrpt::poses::CPose3D p{mrpt::math::TPose3D(poses[k])};
        poses[k] = mrpt::math::TPose2D((p + m_increments[i0 + k]).asTPose());
    }
}
}  // namespace semloc
