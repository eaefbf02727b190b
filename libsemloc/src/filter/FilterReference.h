/* semloc — the filter step's fast paths written to be read (private): the Gaussian odometry
 * sample composed onto a particle, systematic resampling and the particles' mean and
 * covariance, each the textbook formula in plain scalar code, one particle at a time, with
 * MRPT's operations. test_FilterReference holds the fast paths (MotionSampling, Resampling,
 * Estimate) to them. */
#pragma once

#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPosePDFGaussian.h>

#include <cstddef>
#include <cstdint>
#include <tuple>
#include <vector>

#include "filter/ParticleRuns.h"

namespace semloc::reference
{
/** Particle `particle` at pose p moved by a sample of the odometry `pdf`, with the normals
 *  of its stream ParticleNormals(key, particle): MRPT's CPoseRandomSampler sample (setPosePDF:
 *  Z sqrt(D) for the eigen-decomposition Z D Z^T of the covariance; do_sample_2D:
 *  u = mean + Z sqrt(D) n, the heading wrapped), composed as CPose2D(p) + CPose2D(u) (libm's
 *  sin and cos). */
mrpt::math::TPose2D movedPose(const mrpt::poses::CPosePDFGaussian& pdf, uint64_t key,
                              size_t particle, const mrpt::math::TPose2D& p);

/** Systematic resampling (Thrun et al., Probabilistic Robotics, Table 4.4; MRPT's
 *  prSystematic) of the linear weights w (>= 0, positive sum W) into M particles (`count`;
 *  0: as many as weights): the M pointers t_i = (u + i) W / M, u in [0, 1); particle j takes
 *  the pointers in [c_{j-1}, c_j), c_j = w_0 + ... + w_j summed in order, and the last
 *  particle of positive weight those beyond c_{N-1} (rounding). The source index of each
 *  resampled particle, in order. Also KldResampling's candidate draw. */
std::vector<size_t> systematicResamplingIndices(const std::vector<double>& w, double u,
                                                size_t count = 0);

/** MRPT 2.5.8's CPosePDFParticles::getCovarianceAndMean: weights exp(log_w); the weighted
 *  mean of x and y; the circular mean atan2(sum w sin phi, sum w cos phi) of the headings;
 *  the weighted covariance (over sum w), heading errors wrapToPi(|phi - mean|) with the mean
 *  moved to [0, 2 pi); zero with fewer than two particles. Throws when every weight is
 *  zero. */
std::tuple<mrpt::math::CMatrixDouble33, mrpt::poses::CPose2D> covarianceAndMean(
    const detail::ParticleList& particles);
}  // namespace semloc::reference
