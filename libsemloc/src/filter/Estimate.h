/* semloc — the estimate of the particle set: the weighted mean pose and its covariance,
 * MRPT's CPosePDFParticles values bit for bit (private). */
#pragma once

#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/poses/CPose2D.h>

#include <tuple>
#include <vector>

#include "filter/ParticleStore.h"

namespace semloc
{
class ParallelExecutor;
}

namespace semloc::detail
{
/** MRPT 2.5.8's CPosePDFParticles::getMean (the weighted mean of x and y, the circular mean
 *  of the headings), each particle's exp(log_w) into `w` and their sum (in particle order)
 *  into `weightSum`. The exps, cosines and sines on the executor's threads (no exp() for a
 *  log-weight of 0), the sums in particle order on this thread. Throws as MRPT's when every
 *  weight is zero. */
mrpt::poses::CPose2D meanAndWeights(const ParticleList& particles, ParallelExecutor& ex,
                                    std::vector<double>& w, double& weightSum);

/** MRPT 2.5.8's CPosePDFParticles::getCovarianceAndMean bit for bit; `w` a buffer. With
 *  `poseCov`, also, from the same pass (in particle order on this thread: the same bits for
 *  any thread count), the covariance with signed heading errors: MRPT's heading error is
 *  wrapToPi(|phi - mean|), whose square is right but whose sign is not the error's (its x-phi
 *  and y-phi terms are wrong); `poseCov` gives it the sign of phi - mean (mean in
 *  [0, 2 pi)), i.e. wrapToPi(phi - mean) (+pi where that is -pi). Its other entries are
 *  MRPT's. */
std::tuple<mrpt::math::CMatrixDouble33, mrpt::poses::CPose2D> covarianceAndMean(
    const ParticleList& particles, ParallelExecutor& ex, std::vector<double>& w,
    mrpt::math::CMatrixDouble33* poseCov = nullptr);
}  // namespace semloc::detail
