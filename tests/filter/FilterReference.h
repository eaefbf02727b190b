/* semloc tests — the filter step's fast paths written to be read: the Gaussian odometry
 * sample composed onto a particle and the particles' mean and covariance, each the textbook
 * formula in plain scalar code, one particle at a time, with MRPT's operations.
 * test_FilterReference holds the fast paths (MotionSampling, Estimate) to them, and
 * Resampling's blocks to its sequential walk (systematicResamplingIndices). */
#pragma once

#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPosePDFGaussian.h>

#include <cstddef>
#include <cstdint>
#include <tuple>
#include <vector>

#include "filter/ParticleStore.h"

namespace semloc::reference
{
/** Particle `particle` at pose p moved by a sample of the odometry `pdf`, with the normals
 *  of its stream ParticleNormals(key, particle): MRPT's CPoseRandomSampler sample (setPosePDF:
 *  Z sqrt(D) for the eigen-decomposition Z D Z^T of the covariance; do_sample_2D:
 *  u = mean + Z sqrt(D) n, the heading wrapped), composed as CPose2D(p) + CPose2D(u) (libm's
 *  sin and cos). */
mrpt::math::TPose2D movedPose(const mrpt::poses::CPosePDFGaussian& pdf, uint64_t key,
                              size_t particle, const mrpt::math::TPose2D& p);

/** MRPT 2.5.8's CPosePDFParticles::getCovarianceAndMean: weights exp(log_w); the weighted
 *  mean of x and y; the circular mean atan2(sum w sin phi, sum w cos phi) of the headings;
 *  the weighted covariance (over sum w), heading errors wrapToPi(|phi - mean|) with the mean
 *  moved to [0, 2 pi); zero with fewer than two particles. Throws when every weight is
 *  zero. */
std::tuple<mrpt::math::CMatrixDouble33, mrpt::poses::CPose2D> covarianceAndMean(
    const detail::ParticleList& particles);
}  // namespace semloc::reference
