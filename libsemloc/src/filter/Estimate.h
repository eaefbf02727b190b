/* semloc — the estimate of the particle set: the weighted mean pose and its covariance,
 * MRPT's CPosePDFParticles values bit for bit (private). */
#pragma once

#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/poses/CPose2D.h>

#include <tuple>
#include <vector>

#include "filter/ParticleRuns.h"

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

/** MRPT 2.5.8's CPosePDFParticles::getCovarianceAndMean bit for bit; `w` a buffer. */
std::tuple<mrpt::math::CMatrixDouble33, mrpt::poses::CPose2D> covarianceAndMean(
    const ParticleList& particles, ParallelExecutor& ex, std::vector<double>& w);
}  // namespace semloc::detail
