/* semloc tests — the filter step's fast paths against the references written to be read
 * (FilterReference): the motion sample composed onto a particle, systematic resampling and
 * the particles' mean and covariance, on random cases and 1, 2 and 3 threads. */
#include <gtest/gtest.h>

#include <mrpt/bayes/CParticleFilter.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/filter/CParallelMonteCarloLocalization2D.h>
#include <semloc/filter/ParallelExecutor.h>
#include <algorithm>

#include <Eigen/Dense>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <vector>

#include "filter/Estimate.h"
#include "filter/FilterReference.h"
#include "filter/MotionSampling.h"
#include "filter/Resampling.h"
#include "filter/Weights.h"

using mrpt::math::TPose2D;
using semloc::ParallelExecutor;
using semloc::detail::ParticleList;

namespace
{
constexpr double kInf = std::numeric_limits<double>::infinity();

uint64_t bitsOf(double v)
{
    uint64_t b = 0;
    std::memcpy(&b, &v, sizeof b);
    return b;
}

/** The same bits, or both NaN (a NaN's sign and payload are not specified). */
bool sameValue(double a, double b)
{
    return bitsOf(a) == bitsOf(b) || (std::isnan(a) && std::isnan(b));
}

/** The pools of 1, 2 and 3 threads. */
std::vector<std::unique_ptr<ParallelExecutor>> pools()
{
    std::vector<std::unique_ptr<ParallelExecutor>> p;
    for (size_t t = 1; t <= 3; t++)
    {
        p.push_back(std::make_unique<ParallelExecutor>(t));
    }
    return p;
}

/** A heading: mostly in [-pi, pi], some at and next to +-pi, some far outside. */
double randomHeading(mrpt::random::CRandomGenerator& rng)
{
    const double u = rng.drawUniform(0.0, 1.0);
    return u < 0.1    ? M_PI
           : u < 0.2  ? -M_PI
           : u < 0.3  ? M_PI - rng.drawUniform(0.0, 1e-9)
           : u < 0.4  ? -M_PI + rng.drawUniform(0.0, 1e-9)
           : u < 0.45 ? rng.drawUniform(-1e4, 1e4)
                      : rng.drawUniform(-M_PI, M_PI);
}

/** A random odometry Gaussian: mean within a few metres, covariance A A^T (some nearly
 *  singular, some diagonal). */
mrpt::poses::CPosePDFGaussian randomOdometry(mrpt::random::CRandomGenerator& rng)
{
    mrpt::poses::CPosePDFGaussian pdf;
    pdf.mean = mrpt::poses::CPose2D(rng.drawGaussian1D(0, 2), rng.drawGaussian1D(0, 2),
                                    randomHeading(rng));
    mrpt::math::CMatrixDouble33 A;
    const int kind = static_cast<int>(rng.drawUniform32bit() % 3);
    for (int r = 0; r < 3; r++)
    {
        for (int c = 0; c < 3; c++)
        {
            A(r, c) = kind == 2 && r != c ? 0 : rng.drawGaussian1D(0, 0.3);
        }
    }
    if (kind == 1)
    {
        A(2, 2) = 0;  // rank 2: an eigenvalue ~0 (its square root may be NaN)
        A(2, 0) = A(0, 0);
        A(2, 1) = A(0, 1);
    }
    pdf.cov = mrpt::math::CMatrixDouble33(A.asEigen() * A.asEigen().transpose());
    return pdf;
}

/** x and y of the fast path within the reference's: fastSinCos' sin and cos are within
 *  1e-15 of libm's (test_FastMath), each scaled by a coordinate of the increment, and the
 *  sums may then round once differently (4 ulp of the result). */
double composeTolerance(const TPose2D& p, const TPose2D& moved)
{
    const double u = std::abs(moved.x - p.x) + std::abs(moved.y - p.y);
    const double scale =
        std::max({std::abs(p.x), std::abs(p.y), std::abs(moved.x), std::abs(moved.y), u});
    return 2e-15 * u + 4 * std::numeric_limits<double>::epsilon() * scale;
}
}  // namespace

TEST(FilterReference, MotionSampleEqualsMrptsSamplerAndComposition)
{
    // 2 000 odometry Gaussians x 60 particles: the fast path (GaussianIncrementDrawer,
    // movePoses: x and y side by side, fastSinCos two particles at a time) against MRPT's
    // CPoseRandomSampler sample and CPose2D composition, with the same normals. The heading
    // is bit for bit; x and y within composeTolerance (the headings' sin and cos).
    auto& rng = mrpt::random::getRandomGenerator();
    rng.randomize(21);
    size_t cases = 0, phiChecked = 0;
    double worst = 0;
    for (int trial = 0; trial < 2000; trial++)
    {
        const auto pdf = randomOdometry(rng);
        const semloc::detail::GaussianIncrementDrawer drawer(pdf);
        const uint64_t key =
            (static_cast<uint64_t>(rng.drawUniform32bit()) << 32) | rng.drawUniform32bit();
        const size_t n = 1 + rng.drawUniform32bit() % 119;  // odd and even counts
        const size_t i0 = rng.drawUniform32bit() % 100000;
        std::vector<ParticleList::value_type> particles(n);
        for (auto& p : particles)
        {
            p.d =
                TPose2D(rng.drawUniform(-1e3, 1e3), rng.drawUniform(-1e3, 1e3), randomHeading(rng));
        }
        const auto before = particles;
        std::vector<TPose2D> out(n);
        for (size_t k = 0; k < n; k++)
        {
            out[k] = particles[k].d;
        }
        semloc::detail::movePoses(drawer, key, out.data(), i0, n);
        for (size_t k = 0; k < n; k++)
        {
            particles[k].d = out[k];
        }
        for (size_t k = 0; k < n; k++, cases++)
        {
            const TPose2D ref = semloc::reference::movedPose(pdf, key, i0 + k, before[k].d);
            const TPose2D& got = particles[k].d;
            ASSERT_EQ(bitsOf(out[k].x), bitsOf(got.x));
            if (std::isnan(ref.x) || std::isnan(ref.phi))
            {
                // A NaN square root of a negative rounding of a zero eigenvalue: both NaN.
                EXPECT_TRUE(std::isnan(got.x) || std::isnan(got.y) || std::isnan(got.phi))
                    << "trial " << trial << " particle " << k;
                continue;
            }
            ASSERT_TRUE(sameValue(got.phi, ref.phi))
                << "trial " << trial << " particle " << k << ": " << got.phi << " vs " << ref.phi;
            phiChecked++;
            const double tol = composeTolerance(before[k].d, ref);
            ASSERT_NEAR(got.x, ref.x, tol) << "trial " << trial << " particle " << k;
            ASSERT_NEAR(got.y, ref.y, tol) << "trial " << trial << " particle " << k;
            worst = std::max({worst, std::abs(got.x - ref.x) / tol, std::abs(got.y - ref.y) / tol});
        }
    }
    EXPECT_GE(cases, 100000u);
    EXPECT_GT(phiChecked, cases * 9 / 10);
    RecordProperty("worst_xy_error_over_tolerance", std::to_string(worst));
}

TEST(FilterReference, FilterPredictionEqualsTheReferenceOnOneTwoAndThreeThreads)
{
    // The whole prediction of the filter (key drawn from MRPT's generator, particles moved on
    // the executor's threads) against the reference particle by particle.
    mrpt::obs::CActionRobotMovement2D act;
    mrpt::obs::CActionRobotMovement2D::TMotionModelOptions mo;
    mo.modelSelection = mrpt::obs::CActionRobotMovement2D::mmGaussian;
    act.computeFromOdometry(mrpt::poses::CPose2D(0.6, -0.05, 0.2), mo);
    mrpt::obs::CActionCollection acts;
    acts.insert(act);
    const auto pdf = *semloc::detail::gaussianMotion(acts);
    mrpt::bayes::CParticleFilter::TParticleFilterOptions o;
    auto& rng = mrpt::random::getRandomGenerator();
    for (size_t threads = 1; threads <= 3; threads++)
    {
        semloc::CParallelMonteCarloLocalization2D pf;
        pf.setExecutor(std::make_shared<ParallelExecutor>(threads));
        rng.randomize(4);
        pf.resetUniform(0, 50, 0, 50, -M_PI, M_PI, 5000);
        const auto before = pf.m_particles;
        rng.randomize(40 + threads);
        // The filter's key: the same expression, the same two draws.
        const uint64_t key =
            (static_cast<uint64_t>(rng.drawUniform32bit()) << 32) | rng.drawUniform32bit();
        rng.randomize(40 + threads);
        pf.prediction_and_update_pfStandardProposal(&acts, nullptr, o);
        ASSERT_EQ(pf.size(), before.size());
        for (size_t i = 0; i < before.size(); i++)
        {
            const TPose2D ref = semloc::reference::movedPose(pdf, key, i, before[i].d);
            const TPose2D& got = pf.m_particles[i].d;
            const double tol = composeTolerance(before[i].d, ref);
            ASSERT_EQ(bitsOf(got.phi), bitsOf(ref.phi)) << i << ", " << threads << " threads";
            ASSERT_NEAR(got.x, ref.x, tol) << i << ", " << threads << " threads";
            ASSERT_NEAR(got.y, ref.y, tol) << i << ", " << threads << " threads";
        }
    }
}

namespace
{
/** Random linear weights (>= 0, positive sum) of one of several kinds. */
std::vector<double> randomWeights(mrpt::random::CRandomGenerator& rng, size_t M, int kind)
{
    std::vector<double> w(M, 1.0);  // kind 0: equal
    for (auto& wi : w)
    {
        if (kind == 1)
        {
            wi = rng.drawUniform(0.0, 1.0);
        }
        else if (kind == 2)
        {
            // Some weights zero (log-weight -inf).
            wi = rng.drawUniform(0.0, 1.0) < 0.4 ? 0.0 : std::exp(rng.drawGaussian1D(0, 2));
        }
        else if (kind == 3)
        {
            // Huge dynamic range: exp of log-weights spread over +-700 relative to the
            // largest (most underflow to zero or to subnormals).
            wi = std::exp(-std::abs(rng.drawGaussian1D(0, 300)));
        }
        else if (kind == 4)
        {
            wi = 0;  // one positive weight, placed below
        }
    }
    if (kind == 4 || (kind == 3 && rng.drawUniform(0.0, 1.0) < 0.5))
    {
        w[rng.drawUniform32bit() % M] = 1;
    }
    if (kind == 5)
    {
        // Trailing zeros: pointers beyond the last positive weight's cumulative sum.
        for (size_t i = M / 2; i < M; i++)
        {
            w[i] = 0;
        }
        w[0] = 1;
    }
    double sum = 0;
    for (const double wi : w)
    {
        sum += wi;
    }
    if (!(sum > 0))
    {
        w[0] = 1;
    }
    return w;
}

/** A uniform offset: random, 0 or the largest below 1. */
double randomOffset(mrpt::random::CRandomGenerator& rng)
{
    const double u = rng.drawUniform(0.0, 1.0);
    return u < 0.05 ? 0.0 : u < 0.1 ? std::nextafter(1.0, 0.0) : rng.drawUniform(0.0, 1.0);
}
}  // namespace

TEST(FilterReference, SystematicResamplingIndicesEqualTheReference)
{
    // 120 000 weight vectors (6 kinds; 1 to 40 particles, and every 100th up to 3000:
    // several blocks of SystematicResampling::kBlock), each resampled on 1, 2 and 3 threads
    // by the block-parallel fast path: the indices are the reference's, bit for bit; on odd
    // trials a value per particle (the heading drift's) follows its particle.
    auto& rng = mrpt::random::getRandomGenerator();
    rng.randomize(33);
    const auto ex = pools();
    semloc::detail::SystematicResampling fast;
    ParticleList from, to;
    std::vector<double> carriedFrom, carriedTo;
    size_t cases = 0, moved = 0;
    for (int trial = 0; trial < 120000; trial++)
    {
        const int kind = trial % 6;
        const size_t M =
            trial % 100 == 99 ? 1 + rng.drawUniform32bit() % 3000 : 1 + rng.drawUniform32bit() % 40;
        const auto w = randomWeights(rng, M, kind);
        const double u = randomOffset(rng);
        const auto ref = semloc::detail::systematicResamplingIndices(w, u);
        from.resize(M);
        for (size_t i = 0; i < M; i++)
        {
            from[i].d = TPose2D(static_cast<double>(i), 0, 0);  // the index, exactly
            from[i].log_w = -1;
        }
        auto& pool = *ex[static_cast<size_t>(trial) % 3];
        fast.setWeights(w);
        const bool carry = trial % 2 == 1;
        carriedFrom.resize(M);
        carriedTo.assign(M, -1);
        for (size_t i = 0; i < M; i++)
        {
            carriedFrom[i] = static_cast<double>(i) + 0.5;
        }
        const semloc::detail::CarriedValues carried{carriedFrom.data(), carriedTo.data(), 1};
        fast.resample(u, from, to, pool, carry ? &carried : nullptr);
        ASSERT_EQ(to.size(), M);
        for (size_t i = 0; i < M; i++)
        {
            ASSERT_EQ(to[i].d.x, static_cast<double>(ref[i]))
                << "trial " << trial << " kind " << kind << " M " << M << " u " << u << " pointer "
                << i << ", " << pool.threads() << " threads";
            ASSERT_EQ(to[i].log_w, 0);
            ASSERT_EQ(carriedTo[i], carry ? static_cast<double>(ref[i]) + 0.5 : -1.0)
                << "trial " << trial << " pointer " << i;
            moved += ref[i] != i;
        }
        cases++;
    }
    EXPECT_EQ(cases, 120000u);
    EXPECT_GT(moved, 0u);
}

TEST(FilterReference, FilterStepResamplesAsTheReference)
{
    // The filter's own step (ESS < BETA, prSystematic): its weights relative to the largest,
    // the uniform draw of MRPT's generator, the indices of the reference.
    auto& rng = mrpt::random::getRandomGenerator();
    for (int trial = 0; trial < 60; trial++)
    {
        const size_t threads = 1 + static_cast<size_t>(trial) % 3;
        rng.randomize(100 + static_cast<unsigned>(trial));
        const size_t M = 1 + rng.drawUniform32bit() % 5000;
        semloc::CParallelMonteCarloLocalization2D pf(M);
        pf.setExecutor(std::make_shared<ParallelExecutor>(threads));
        std::vector<double> logW(M);
        double maxLogW = -kInf;
        for (size_t i = 0; i < M; i++)
        {
            logW[i] = rng.drawUniform(0.0, 1.0) < 0.2 ? -kInf : rng.drawGaussian1D(0, 3 * trial);
            maxLogW = std::max(maxLogW, logW[i]);
            pf.m_particles[i].d = TPose2D(static_cast<double>(i), 0, 0);
            pf.m_particles[i].log_w = logW[i];
        }
        if (!(maxLogW > -kInf))
        {
            continue;
        }
        std::vector<double> w;
        const ParticleList particles(pf.m_particles.begin(), pf.m_particles.end());
        semloc::detail::weightsAndESS(particles, pf.executor(),
                                      semloc::detail::minMaxLogWeights(particles, pf.executor()),
                                      &w);
        mrpt::bayes::CParticleFilter::TParticleFilterOptions o;
        o.resamplingMethod = mrpt::bayes::CParticleFilter::prSystematic;
        o.BETA = 1.01;
        const auto state = rng;  // the uniform the step will draw
        auto copy = state;
        const double u = copy.drawUniform(0.0, 1.0);
        pf.prediction_and_update_pfStandardProposal(nullptr, nullptr, o);
        const auto ref = semloc::detail::systematicResamplingIndices(w, u);
        ASSERT_EQ(pf.size(), M);
        for (size_t i = 0; i < M; i++)
        {
            ASSERT_EQ(pf.m_particles[i].d.x, static_cast<double>(ref[i]))
                << "trial " << trial << " pointer " << i;
        }
    }
}

namespace
{
/** n particles of one of several kinds of weights and headings. */
ParticleList randomCloud(mrpt::random::CRandomGenerator& rng, size_t n, int kind)
{
    ParticleList particles(n);
    for (auto& p : particles)
    {
        p.d = TPose2D(rng.drawGaussian1D(25, 5), rng.drawGaussian1D(25, 5),
                      kind == 3 ? randomHeading(rng) : rng.drawUniform(-M_PI, M_PI));
        p.log_w = kind == 0 ? 0.0 : rng.drawGaussian1D(0, 3) - 2;  // kind 0: equal weights
        if (kind == 2 && rng.drawUniform(0.0, 1.0) < 0.3)
        {
            p.log_w = -kInf;
        }
        if (kind == 4)
        {
            // Huge dynamic range: most weights underflow to zero or to subnormals.
            p.log_w = std::max(-800.0, std::min(700.0, rng.drawGaussian1D(-200, 300)));
        }
        if (kind == 5)
        {
            p.log_w = -kInf;  // every weight zero: both throw
        }
    }
    return particles;
}
}  // namespace

TEST(FilterReference, EstimateEqualsTheReferenceBitForBit)
{
    // 120 000 particle sets (0 to 40 particles, every 200th up to 4000: split over the
    // threads), 6 kinds: equal weights, random, some zero, headings around +-pi and far
    // outside, huge dynamic range, every weight zero. Estimate's mean and covariance (exp,
    // cos and sin on 1, 2 or 3 threads, the sums in order) are the reference's bit for bit.
    auto& rng = mrpt::random::getRandomGenerator();
    rng.randomize(55);
    const auto ex = pools();
    std::vector<double> w;
    size_t compared = 0, throwing = 0;
    for (int trial = 0; trial < 120000; trial++)
    {
        const int kind = trial % 6;
        const size_t n =
            trial % 200 == 199 ? 1 + rng.drawUniform32bit() % 4000 : rng.drawUniform32bit() % 41;
        const ParticleList particles = randomCloud(rng, n, kind);
        auto& pool = *ex[static_cast<size_t>(trial / 6) % 3];
        if (kind == 5 && n > 0)
        {
            EXPECT_ANY_THROW(semloc::reference::covarianceAndMean(particles));
            EXPECT_ANY_THROW(semloc::detail::covarianceAndMean(particles, pool, w));
            throwing++;
            continue;
        }
        bool refThrew = false, fastThrew = false;
        std::tuple<mrpt::math::CMatrixDouble33, mrpt::poses::CPose2D> ref, fast;
        try
        {
            ref = semloc::reference::covarianceAndMean(particles);
        }
        catch (const std::exception&)
        {
            refThrew = true;  // every weight underflowed (kind 4)
        }
        try
        {
            fast = semloc::detail::covarianceAndMean(particles, pool, w);
        }
        catch (const std::exception&)
        {
            fastThrew = true;
        }
        ASSERT_EQ(refThrew, fastThrew) << "trial " << trial;
        if (refThrew)
        {
            continue;
        }
        const auto& [covRef, meanRef] = ref;
        const auto& [covFast, meanFast] = fast;
        for (int k = 0; k < 3; k++)
        {
            ASSERT_TRUE(sameValue(meanFast[k], meanRef[k]))
                << "trial " << trial << " kind " << kind << " n " << n << " mean " << k << ": "
                << meanFast[k] << " vs " << meanRef[k];
            for (int l = 0; l < 3; l++)
            {
                ASSERT_TRUE(sameValue(covFast(k, l), covRef(k, l)))
                    << "trial " << trial << " kind " << kind << " n " << n << " cov (" << k << ", "
                    << l << "): " << covFast(k, l) << " vs " << covRef(k, l);
            }
        }
        compared++;
    }
    EXPECT_GT(compared, 99000u);
    EXPECT_GT(throwing, 19000u);
}

TEST(FilterReference, PoseCovarianceSignsTheHeadingErrorsInTheSamePass)
{
    // The covariance a NEES needs: MRPT's with the x-phi and y-phi terms of signed heading
    // errors wrapToPi(phi - mean phi). MRPT's own stays bit for bit the same, the other
    // entries are MRPT's, the two cross terms are the direct sums', the same bits on 1, 2
    // and 3 threads.
    auto& rng = mrpt::random::getRandomGenerator();
    rng.randomize(57);
    const auto ex = pools();
    std::vector<double> w;
    for (int trial = 0; trial < 3000; trial++)
    {
        const int kind = trial % 4;  // equal, random, some zero weights; headings near +-pi
        const ParticleList particles = randomCloud(rng, 2 + rng.drawUniform32bit() % 300, kind);
        if (std::none_of(particles.begin(), particles.end(),
                         [](const auto& p) { return std::isfinite(p.log_w); }))
        {
            continue;  // a few particles all of weight zero (kind 2): no estimate to compare
        }
        const auto [cov, mean] = semloc::detail::covarianceAndMean(particles, *ex[0], w);
        std::vector<mrpt::math::CMatrixDouble33> pose(ex.size());
        for (size_t t = 0; t < ex.size(); t++)
        {
            const auto [covT, meanT] =
                semloc::detail::covarianceAndMean(particles, *ex[t], w, &pose[t]);
            for (int k = 0; k < 9; k++)
            {
                ASSERT_EQ(bitsOf(covT(k / 3, k % 3)), bitsOf(cov(k / 3, k % 3))) << trial;
                ASSERT_EQ(bitsOf(pose[t](k / 3, k % 3)), bitsOf(pose[0](k / 3, k % 3))) << trial;
                ASSERT_EQ(pose[t](k / 3, k % 3), pose[t](k % 3, k / 3)) << "symmetric";
            }
        }
        for (const auto& [k, l] : {std::pair{0, 0}, {1, 1}, {2, 2}, {0, 1}})
        {
            ASSERT_EQ(bitsOf(pose[0](k, l)), bitsOf(cov(k, l))) << trial;
        }
        if (kind == 3)
        {
            continue;  // headings at +-pi: which end a wrap takes is rounding's
        }
        double sumW = 0, xp = 0, yp = 0;
        for (const auto& p : particles)
        {
            sumW += std::exp(p.log_w);
        }
        for (const auto& p : particles)
        {
            const double wk = std::exp(p.log_w) / sumW;
            const double e = mrpt::math::wrapToPi(p.d.phi - mean.phi());
            xp += (p.d.x - mean.x()) * e * wk;
            yp += (p.d.y - mean.y()) * e * wk;
        }
        EXPECT_NEAR(pose[0](0, 2), xp, 1e-9) << trial;
        EXPECT_NEAR(pose[0](1, 2), yp, 1e-9) << trial;
    }

    // By hand: two equal particles either side of the heading pi, the one at x = -1 turned
    // 0.1 rad clockwise of the mean, the one at x = 1 0.1 rad counter-clockwise: x and phi
    // go together (cov 0.1); MRPT's |phi - mean| turns one error's sign: -0.1.
    ParticleList two(2);
    two[0].d = TPose2D(-1, 0, M_PI - 0.1);
    two[1].d = TPose2D(1, 0, -M_PI + 0.1);
    mrpt::math::CMatrixDouble33 pose;
    const auto [cov, mean] = semloc::detail::covarianceAndMean(two, *ex[1], w, &pose);
    EXPECT_NEAR(std::abs(mean.phi()), M_PI, 1e-12);
    EXPECT_NEAR(pose(0, 2), 0.1, 1e-12);
    EXPECT_NEAR(pose(2, 2), 0.01, 1e-12);
    EXPECT_NEAR(pose(0, 0), 1.0, 1e-12);
    EXPECT_NEAR(cov(0, 2), -0.1, 1e-12);
}
