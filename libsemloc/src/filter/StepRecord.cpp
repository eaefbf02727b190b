/* semloc — TStepRecord: a step's errors and NEES. */
#include <mrpt/math/wrap2pi.h>
#include <semloc/filter/StepRecord.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

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

namespace
{
/** The error e of nees() and P's eigen-decomposition; nullopt without ground truth or with a
 *  non-finite value. */
struct NeesTerms
{
    Eigen::Vector3d e;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
};

std::optional<NeesTerms> neesTerms(const TStepRecord& r)
{
    if (!r.gt)
    {
        return std::nullopt;
    }
    const Eigen::Vector3d e(r.gt->x - r.est.x, r.gt->y - r.est.y,
                            mrpt::math::wrapToPi(r.gt->phi - r.est.phi));
    Eigen::Matrix3d P;
    P << r.var_x, r.cov_xy, r.cov_xphi, r.cov_xy, r.var_y, r.cov_yphi, r.cov_xphi, r.cov_yphi,
        r.var_phi;
    if (!e.allFinite() || !P.allFinite())
    {
        return std::nullopt;
    }
    return NeesTerms{e, Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(P)};
}
}  // namespace

double TStepRecord::nees() const
{
    const auto terms = neesTerms(*this);
    if (!terms)
    {
        return kNaN;
    }
    // P = V diag(l) V^T: e^T P^-1 e = sum_i (v_i . e)^2 / l_i, each l_i floored (StepRecord.h).
    const Eigen::Vector3d proj = terms->eig.eigenvectors().transpose() * terms->e;
    double n = 0;
    for (int i = 0; i < 3; i++)
    {
        n += proj[i] * proj[i] / (std::max(terms->eig.eigenvalues()[i], 0.0) + kNeesFloor);
    }
    return n;
}

bool TStepRecord::neesWellConditioned() const
{
    const auto terms = neesTerms(*this);
    if (!terms || !(ess * static_cast<double>(n_particles) >= kNeesMinEffectiveParticles))
    {
        return false;
    }
    const auto& l = terms->eig.eigenvalues();  // ascending
    return l[0] >= kNeesMinEigenvalue && l[0] * kNeesMaxCondition >= l[2];
}
}  // namespace semloc
