/* semloc — the estimate of the particle set: weighted mean pose and covariance. */
#include "filter/Estimate.h"

#include <mrpt/core/exceptions.h>
#include <semloc/filter/ParallelExecutor.h>

#include <cerrno>
#include <cmath>
#include <tuple>

#include "filter/WrapToPi.h"

namespace semloc::detail
{
namespace
{
/** Loops with a sin and a cos per particle (~25 ns): the estimate's. */
constexpr size_t kTrigLoopGrain = 512;

/** Each particle's weight exp(log_w) (1 for log_w = 0: glibc's exp(+-0) is 1 exactly) and
 *  the cos and sin of its heading (glibc's) into W, C and S, on the executor's threads. */
void weightsAndHeadings(const ParticleList& particles, ParallelExecutor& ex, double* W, double* C,
                        double* S)
{
    ex.forEachRange(
        particles.size(),
        [&](size_t b, size_t e, size_t)
        {
            forEachRun(particles, b, e,
                       [&](const auto* p, size_t i0, size_t len)
                       {
                           for (size_t k = 0; k < len; k++)
                           {
                               const double logW = p[k].log_w;
                               W[i0 + k] = logW == 0 ? 1.0 : std::exp(logW);
                               C[i0 + k] = std::cos(p[k].d.phi);
                               S[i0 + k] = std::sin(p[k].d.phi);
                           }
                       });
        },
        kTrigLoopGrain);
}
}  // namespace

mrpt::poses::CPose2D meanAndWeights(const ParticleList& particles, ParallelExecutor& ex,
                                    std::vector<double>& w, double& weightSum)
{
    // MRPT 2.5.8's CPosePDFParticles::getMean: SE_average<2> over the particles in order,
    // weights exp(log_w); the exps, cosines and sines first (the same values), then the sums
    // in particle order on this thread. The two counts of SE_average and SO_average add the
    // same weights in the same order: one here.
    const size_t n = particles.size();
    w.resize(n);
    weightSum = 0;
    if (n == 0)
    {
        return {};
    }
    thread_local std::vector<double> cosPhi, sinPhi;  // this thread's calls' buffers
    cosPhi.resize(n);
    sinPhi.resize(n);
    const double* W = w.data();
    const double* C = cosPhi.data();
    const double* S = sinPhi.data();
    weightsAndHeadings(particles, ex, w.data(), cosPhi.data(), sinPhi.data());
    double count = 0, sumX = 0, sumY = 0, sumCos = 0, sumSin = 0;
    forEachRun(particles, 0, n,
               [&](const auto* p, size_t i0, size_t len)
               {
                   for (size_t k = 0; k < len; k++)
                   {
                       const double wk = W[i0 + k];
                       count += wk;
                       sumX += wk * p[k].d.x;
                       sumY += wk * p[k].d.y;
                       sumCos += C[i0 + k] * wk;
                       sumSin += S[i0 + k] * wk;
                   }
               });
    weightSum = count;
    ASSERT_GT_(count, 0);
    mrpt::poses::CPose2D mean;
    mean.x(sumX / count);
    mean.y(sumY / count);
    // SO_average<2>::get_average (an undetermined angle is 0, MRPT's default).
    errno = 0;
    double ang = std::atan2(sumSin / count, sumCos / count);
    if (errno == EDOM)
    {
        ang = 0;
    }
    mean.phi(ang);
    return mean;
}

std::tuple<mrpt::math::CMatrixDouble33, mrpt::poses::CPose2D> covarianceAndMean(
    const ParticleList& particles, ParallelExecutor& ex, std::vector<double>& w,
    mrpt::math::CMatrixDouble33* poseCov)
{
    // MRPT 2.5.8's CPosePDFParticles::getCovarianceAndMean, the same operations in the same
    // order. Its sum of exp(log_w) adds the same weights in the same order as getMean's
    // count: meanAndWeights' weightSum.
    double linWSum = 0;
    const mrpt::poses::CPose2D mean = meanAndWeights(particles, ex, w, linWSum);
    const size_t n = particles.size();
    if (linWSum == 0)
    {
        linWSum = 1;
    }
    double meanPhi = mean.phi();
    if (meanPhi < 0)
    {
        meanPhi = M_2PI + meanPhi;
    }
    const double mx = mean.x(), my = mean.y();
    double varX = 0, varY = 0, varP = 0, varXY = 0, varXP = 0, varYP = 0;
    double signedXP = 0, signedYP = 0;  // poseCov's
    forEachRun(particles, 0, n,
               [&](const auto* p, size_t i0, size_t len)
               {
                   for (size_t k = 0; k < len; k++)
                   {
                       const double wk = w[i0 + k] / linWSum;
                       const double errX = p[k].d.x - mx;
                       const double errY = p[k].d.y - my;
                       const double d = p[k].d.phi - meanPhi;
                       const double errPhi = wrapToPiExact(std::abs(d));
                       const double signedPhi = d < 0 ? -errPhi : errPhi;
                       varX += (errX * errX) * wk;
                       varY += (errY * errY) * wk;
                       varP += (errPhi * errPhi) * wk;
                       varXY += (errX * errY) * wk;
                       varXP += (errX * errPhi) * wk;
                       varYP += (errY * errPhi) * wk;
                       signedXP += (errX * signedPhi) * wk;
                       signedYP += (errY * signedPhi) * wk;
                   }
               });
    mrpt::math::CMatrixDouble33 cov;
    cov.setZero();
    if (n >= 2)
    {
        cov(0, 0) = varX;
        cov(1, 1) = varY;
        cov(2, 2) = varP;
        cov(1, 0) = cov(0, 1) = varXY;
        cov(2, 0) = cov(0, 2) = varXP;
        cov(1, 2) = cov(2, 1) = varYP;
    }
    if (poseCov)
    {
        *poseCov = cov;
        if (n >= 2)
        {
            (*poseCov)(2, 0) = (*poseCov)(0, 2) = signedXP;
            (*poseCov)(1, 2) = (*poseCov)(2, 1) = signedYP;
        }
    }
    return {cov, mean};
}
}  // namespace semloc::detail
