/* semloc — the motion model's samples: the Gaussian odometry's increment drawer. */
#include "filter/MotionSampling.h"

#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/obs/CActionRobotMovement2D.h>

#include <Eigen/Dense>

#include <vector>

namespace semloc::detail
{
std::optional<mrpt::poses::CPosePDFGaussian> gaussianMotion(
    const mrpt::obs::CActionCollection& actions)
{
    const auto mov2D = actions.getBestMovementEstimation();
    const auto* gauss =
        mov2D ? dynamic_cast<const mrpt::poses::CPosePDFGaussian*>(mov2D->poseChange.get())
              : nullptr;
    if (gauss)
    {
        return *gauss;
    }
    return std::nullopt;
}

GaussianIncrementDrawer::GaussianIncrementDrawer(const mrpt::poses::CPosePDFGaussian& pdf)
    : m_meanXY{pdf.mean.x(), pdf.mean.y()}, m_meanPhi(pdf.mean.phi())
{
    // CPoseRandomSampler::setPosePDF: the eigenvectors scaled by the square roots of the
    // eigenvalues.
    mrpt::math::CMatrixDouble33 Z;
    std::vector<double> eigVals;
    pdf.cov.eig_symmetric(Z, eigVals);
    mrpt::math::CMatrixDouble33 D;
    D.setDiagonal(eigVals);
    D = D.asEigen().array().sqrt().matrix();
    Z.matProductOf_AB(Z, D);
    for (int i = 0; i < 3; i++)
    {
        m_zxy[i] = Vec2{Z(0, i), Z(1, i)};
        m_zphi[i] = Z(2, i);
    }
}
}  // namespace semloc::detail
