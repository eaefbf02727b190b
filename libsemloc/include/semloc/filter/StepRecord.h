/* semloc — one filter step as the outputs record it (a row of steps.csv). */
#pragma once

#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/math/TPose2D.h>

#include <cstddef>
#include <optional>

namespace semloc
{
/** One filter step, a row of steps.csv. */
struct TStepRecord
{
    /** Step index, from 0. */
    size_t step = 0;
    /** Time of the step's observations [s] (mrpt::Clock::toDouble); NaN if unknown. */
    double t = 0;
    /** Ground-truth pose at t, if any. */
    std::optional<mrpt::math::TPose2D> gt;
    /** Weighted mean of the particles. */
    mrpt::math::TPose2D est;
    /** Trace of the particles' x-y covariance [m^2]. */
    double var_xy = 0;
    /** @name The particles' weighted covariance of (x, y, phi) about `est`, heading errors
     *  wrapToPi(phi - est.phi) (signed, unlike MRPT's getCovarianceAndMean's x-phi and y-phi
     *  terms); var_x + var_y = var_xy. 0 when unknown.
     *  @{ */
    double var_x = 0;     ///< [m^2]
    double var_y = 0;     ///< [m^2]
    double var_phi = 0;   ///< [rad^2]
    double cov_xy = 0;    ///< [m^2]
    double cov_xphi = 0;  ///< [m rad]
    double cov_yphi = 0;  ///< [m rad]
    /** @} */
    /** Effective sample size before resampling, in [0, 1]. */
    double ess = 1;
    /** Particles after the step. */
    size_t n_particles = 0;
    /** Filter update time [us]. */
    double update_us = 0;

    /** Sets var_x .. cov_yphi from the symmetric 3 x 3 covariance `P` of (x, y, phi). */
    void setPoseCovariance(const mrpt::math::CMatrixDouble33& P);
    /** Position error to the ground truth [m]; NaN without one. */
    double errXY() const;
    /** Heading error to the ground truth, wrapped to [-pi, pi] [rad]; NaN without one. */
    double errPhi() const;
    /** Floor added to the covariance's eigenvalues by nees() [m^2, rad^2]. */
    static constexpr double kNeesFloor = 1e-12;
    /** Normalized estimation error squared of the pose (docs/design.md, "Consistency"):
     *  e^T P^-1 e, e = (gt_x - est_x, gt_y - est_y, wrapToPi(gt_phi - est_phi)), P the
     *  covariance above. A singular or (by rounding) indefinite P: P = V diag(l) V^T, each
     *  eigenvalue taken as max(l, 0) + kNeesFloor, i.e. e^T (P + kNeesFloor I)^-1 e for a
     *  positive semi-definite P; so always finite, 0 for e = 0, and up to |e|^2 / 1e-12 when P
     *  is 0 (one particle, or every particle on one pose). NaN without ground truth or with a
     *  non-finite value. */
    double nees() const;
    /** @name When nees() says something of the filter (docs/design.md, "Consistency")
     *  @{ */
    /** Fewest effective particles (ess x n_particles): a covariance estimated from n samples of
     *  a 3-D Gaussian has E[P^-1] = Sigma^-1 (n - 1) / (n - 5), so the mean NEES is inflated by
     *  at most 10 % from n = 45 on (and without bound below n = 5). */
    static constexpr double kNeesMinEffectiveParticles = 45;
    /** Largest condition number of P (its largest eigenvalue over its smallest, in m^2 and
     *  rad^2): the eigenvalues come out of P's sums and its eigen-decomposition with errors
     *  of up to ~1e-16 x particles x the largest, so up to 1e9 the smallest, which the NEES
     *  divides by, keeps three digits for up to 10 000 particles. */
    static constexpr double kNeesMaxCondition = 1e9;
    /** Smallest eigenvalue of P [m^2, rad^2]: from 1000 x kNeesFloor on the floor moves the
     *  NEES by at most 0.1 %. */
    static constexpr double kNeesMinEigenvalue = 1e3 * kNeesFloor;
    /** Whether P is well conditioned, so that nees() measures the filter and not its
     *  degeneracy (a cloud collapsed on a few particles, P at the floor): at least
     *  kNeesMinEffectiveParticles effective particles, P's smallest eigenvalue at least
     *  kNeesMinEigenvalue and at least 1 / kNeesMaxCondition of its largest. False when
     *  nees() is NaN. */
    bool neesWellConditioned() const;
    /** @} */
};

}  // namespace semloc
