/* semloc tests — a sensor model of the tests' own: a Gaussian position fix (MRPT's
 * CObservationRobotPose, e.g. a surfaced AUV's GPS or a USBL fix) scored through
 * BatchLikelihood. */
#pragma once

#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3D.h>
#include <semloc/models/BatchLikelihood.h>

#include <atomic>
#include <cstddef>

namespace semloc::test
{
using mrpt::math::TPose2D;

/** The plugged model: log p(fix | pose) of a Gaussian position fix (isotropic, the fix's own
 *  x variance). A points map of MRPT's only to be a CMetricMap; its points are not used. */
class PositionFixModel : public mrpt::maps::CSimplePointsMap, public semloc::BatchLikelihood
{
public:
    /** Batch calls made (the filter used the plugged path). */
    mutable std::atomic<size_t> batchCalls{0};

    static double logLik(const mrpt::obs::CObservationRobotPose& fix, double x, double y)
    {
        const double var = fix.pose.cov(0, 0);
        const double dx = x - fix.pose.mean.x(), dy = y - fix.pose.mean.y();
        return -0.5 * (dx * dx + dy * dy) / var;
    }

    bool uses(const mrpt::obs::CObservation& obs) const override
    {
        return dynamic_cast<const mrpt::obs::CObservationRobotPose*>(&obs) != nullptr;
    }

    void logLikelihoods(const mrpt::obs::CObservation& obs, const TPose2D* poses, size_t n,
                        double* out) const override
    {
        batchCalls.fetch_add(1, std::memory_order_relaxed);
        const auto& fix = dynamic_cast<const mrpt::obs::CObservationRobotPose&>(obs);
        for (size_t i = 0; i < n; i++)
        {
            out[i] = logLik(fix, poses[i].x, poses[i].y);
        }
    }

    // MRPT's per-pose interface, the same values (what MRPT's own filter would use).
    bool internal_canComputeObservationLikelihood(const mrpt::obs::CObservation& obs) const override
    {
        return uses(obs);
    }
    double internal_computeObservationLikelihood(const mrpt::obs::CObservation& obs,
                                                 const mrpt::poses::CPose3D& from) const override
    {
        const auto* fix = dynamic_cast<const mrpt::obs::CObservationRobotPose*>(&obs);
        return fix ? logLik(*fix, from.x(), from.y()) : 0.0;
    }
};

inline mrpt::obs::CSensoryFrame fixFrame(double x, double y, double sigma)
{
    auto fix = mrpt::obs::CObservationRobotPose::Create();
    fix->pose.mean = mrpt::poses::CPose3D(x, y, 0, 0, 0, 0);
    fix->pose.cov.setIdentity();
    fix->pose.cov *= sigma * sigma;
    mrpt::obs::CSensoryFrame sf;
    sf.insert(fix);
    return sf;
}

/** An odometry action: d metres straight ahead, MRPT's Gaussian model. */
inline mrpt::obs::CActionCollection forward(double d)
{
    mrpt::obs::CActionRobotMovement2D::TMotionModelOptions opts;
    opts.modelSelection = mrpt::obs::CActionRobotMovement2D::mmGaussian;
    mrpt::obs::CActionRobotMovement2D move;
    move.computeFromOdometry(mrpt::poses::CPose2D(d, 0, 0), opts);
    mrpt::obs::CActionCollection acts;
    acts.insert(move);
    return acts;
}

}  // namespace semloc::test
