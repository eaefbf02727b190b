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
};

}  // namespace semloc
