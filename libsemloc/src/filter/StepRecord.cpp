/* semloc — TStepRecord: a step's errors and NEES. */
#include <mrpt/math/wrap2pi.h>
#include <semloc/filter/StepRecord.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace semloc
{
namespace
{
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

void TStepRecord::setPoseCovariance(const mrpt::math::CMatrixDouble33& P)
{
    var_x = P(0, 0);
    var_y = P(1, 1);
    var_phi = P(2, 2);
    cov_xy = P(0, 1);
    cov_xphi = P(0, 2);
    cov_yphi = P(1, 2);
}

double TStepRecord::errXY() const
{
    return gt ? std::hypot(est.x - gt->x, est.y - gt->y) : kNaN;
}

double TStepRecord::errPhi() const
{
    return gt ? mrpt::math::wrapToPi(est.phi - gt->phi) : kNaN;
}

double TStepRecord::nees() const
{
    if (!gt)
    {
        return kNaN;
    }
    const Eigen::Vector3d e(gt->x - est.x, gt->y - est.y, mrpt::math::wrapToPi(gt->phi - est.phi));
    Eigen::Matrix3d P;
    P << var_x, cov_xy, cov_xphi, cov_xy, var_y, cov_yphi, cov_xphi, cov_yphi, var_phi;
    if (!e.allFinite() || !P.allFinite())
    {
        return kNaN;
    }
    // P = V diag(l) V^T: e^T P^-1 e = sum_i (v_i . e)^2 / l_i, each l_i floored (StepRecord.h).
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(P);
    const Eigen::Vector3d proj = eig.eigenvectors().transpose() * e;
    double n = 0;
    for (int i = 0; i < 3; i++)
    {
        n += proj[i] * proj[i] / (std::max(eig.eigenvalues()[i], 0.0) + kNeesFloor);
    }
    return n;
}
}  // namespace semloc
