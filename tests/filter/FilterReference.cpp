/* semloc tests — the filter step's fast paths written to be read: motion sample, mean and
 * covariance. */
#include "filter/FilterReference.h"

#include <mrpt/core/exceptions.h>
#include <mrpt/math/wrap2pi.h>

#include <Eigen/Dense>

#include <cerrno>
#include <cmath>

#include "filter/MotionSampling.h"

namespace semloc::reference
{
namespace
{
/** libm's cos and sin, called apart as MRPT's SO_average calls them (not fused by the
 *  compiler into one sincos call). */
[[gnu::noinline]] double libmCos(double a)
{
    return std::cos(a);
}

[[gnu::noinline]] double libmSin(double a)
{
    return std::sin(a);
}
}  // namespace

mrpt::math::TPose2D movedPose(const mrpt::poses::CPosePDFGaussian& pdf, uint64_t key,
                              size_t particle, const mrpt::math::TPose2D& p)
{
    // CPoseRandomSampler::setPosePDF.
    mrpt::math::CMatrixDouble33 Z;
    std::vector<double> eigVals;
    pdf.cov.eig_symmetric(Z, eigVals);
    mrpt::math::CMatrixDouble33 D;
    D.setDiagonal(eigVals);
    D = D.asEigen().array().sqrt().matrix();
    Z.matProductOf_AB(Z, D);
    // CPoseRandomSampler::do_sample_2D: r = sum_i Z(:, i) n_i, one normal at a time.
    detail::ParticleNormals normals(key, particle);
    double r[3] = {0, 0, 0};
    for (int i = 0; i < 3; i++)
    {
        const double n = normals();
        for (int d = 0; d < 3; d++)
        {
            r[d] += Z(d, i) * n;
        }
    }
    // (CPose2D's constructor from three numbers wraps the heading: the setters do not.)
    mrpt::poses::CPose2D u;
    u.x(pdf.mean.x() + r[0]);
    u.y(pdf.mean.y() + r[1]);
    u.phi(pdf.mean.phi() + r[2]);
    u.normalizePhi();
    // The particle moved: p (+) u.
    mrpt::poses::CPose2D from;
    from.x(p.x);
    from.y(p.y);
    from.phi(p.phi);
    return (from + u).asTPose();
}

std::tuple<mrpt::math::CMatrixDouble33, mrpt::poses::CPose2D> covarianceAndMean(
    const detail::ParticleList& particles)
{
    mrpt::math::CMatrixDouble33 cov;
    cov.setZero();
    if (particles.empty())
    {
        return {cov, mrpt::poses::CPose2D()};
    }
    // The mean (SE_average<2>, SO_average<2>).
    double sumW = 0, sumX = 0, sumY = 0, sumCos = 0, sumSin = 0;
    for (const auto& p : particles)
    {
        const double w = std::exp(p.log_w);
        sumW += w;
        sumX += w * p.d.x;
        sumY += w * p.d.y;
        sumCos += libmCos(p.d.phi) * w;
        sumSin += libmSin(p.d.phi) * w;
    }
    ASSERT_GT_(sumW, 0);
    errno = 0;
    double phi = std::atan2(sumSin / sumW, sumCos / sumW);
    if (errno == EDOM)
    {
        phi = 0;  // an undetermined angle
    }
    mrpt::poses::CPose2D mean;  // (the constructor from three numbers would wrap phi)
    mean.x(sumX / sumW);
    mean.y(sumY / sumW);
    mean.phi(phi);
    if (particles.size() < 2)
    {
        return {cov, mean};
    }
    // The covariance, heading errors against the mean in [0, 2 pi).
    const double meanPhi = phi < 0 ? M_2PI + phi : phi;
    for (const auto& p : particles)
    {
        const double w = std::exp(p.log_w) / sumW;
        const double e[3] = {p.d.x - mean.x(), p.d.y - mean.y(),
                             mrpt::math::wrapToPi(std::abs(p.d.phi - meanPhi))};
        for (int k = 0; k < 3; k++)
        {
            for (int l = 0; l < 3; l++)
            {
                cov(k, l) += (e[k] * e[l]) * w;
            }
        }
    }
    return {cov, mean};
}
}  // namespace semloc::reference
