/* semloc tests — RunMetrics: docs/design.md's convergence definition and the run's figures. */
#include <gtest/gtest.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/experiment/RunMetrics.h>
#include <semloc/filter/CParallelMonteCarloLocalization2D.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

using mrpt::math::TPose2D;

namespace
{
semloc::TStepRecord rec(size_t step, double err, double var)
{
    semloc::TStepRecord r;
    r.step = step;
    r.t = 100.0 + static_cast<double>(step);
    r.gt = TPose2D(0, 0, 0);
    r.est = TPose2D(err, 0, 0);
    r.var_xy = var;
    r.n_particles = 100;
    r.update_us = 50;
    return r;
}
}  // namespace

TEST(RunMetrics, ConvergenceAsDesignDefinesIt)
{
    semloc::RunMetrics::TConvergenceCriterion c;
    std::vector<semloc::TStepRecord> r;
    for (size_t k = 0; k < 40; k++)
    {
        // Lost, then 5 good steps, a relapse, then good for 12 steps, lost again.
        const bool good = (k >= 5 && k < 10) || (k >= 12 && k < 24);
        r.push_back(rec(k, good ? 0.5 : 3.0, good ? 0.2 : 5.0));
    }
    auto m = semloc::RunMetrics::compute(r, c);
    EXPECT_TRUE(m.converged);
    EXPECT_EQ(m.convergence_step, 12) << "5 good steps do not count; 12 consecutive do";
    EXPECT_DOUBLE_EQ(m.convergence_time_s, 12.0);
    EXPECT_EQ(m.steps_with_ground_truth, 40u);
    EXPECT_DOUBLE_EQ(m.final_err_m, 3.0);
    EXPECT_DOUBLE_EQ(m.mean_err_after_conv_m, (12 * 0.5 + 16 * 3.0) / 28);
    EXPECT_DOUBLE_EQ(m.total_update_s, 40 * 50e-6);
    EXPECT_DOUBLE_EQ(m.mean_update_us_per_particle, 0.5);

    // Good to the end, even if shorter than min_steps, converges.
    for (size_t k = 35; k < 40; k++)
    {
        r[k] = rec(k, 0.1, 0.1);
    }
    for (size_t k = 12; k < 24; k++)
    {
        r[k] = rec(k, 3.0, 0.1);
    }
    m = semloc::RunMetrics::compute(r, c);
    EXPECT_EQ(m.convergence_step, 35);
    c.max_err_xy_m = 0.05;
    m = semloc::RunMetrics::compute(r, c);
    EXPECT_FALSE(m.converged);
    EXPECT_EQ(m.convergence_step, -1);
    EXPECT_TRUE(std::isnan(m.convergence_time_s));

    // A step without ground truth breaks a run of good steps.
    r.assign(20, rec(0, 0.1, 0.1));
    for (size_t k = 0; k < 20; k++)
    {
        r[k].step = k;
    }
    r[8].gt.reset();
    c = {};
    EXPECT_EQ(semloc::RunMetrics::compute(r, c).convergence_step, 9);
    EXPECT_EQ(semloc::RunMetrics::compute(r, c).steps_with_ground_truth, 19u);
}

TEST(RunMetrics, RecoveryStepsCountFromTheKidnapping)
{
    semloc::RunMetrics::TConvergenceCriterion c;
    std::vector<semloc::TStepRecord> r;
    for (size_t k = 0; k < 100; k++)
    {
        // Localized from step 5, kidnapped at 40, back from 63 on (a 4-step blip at 55).
        const bool good = (k >= 5 && k < 40) || (k >= 55 && k < 59) || k >= 63;
        r.push_back(rec(k, good ? 0.2 : 8.0, good ? 0.1 : 30.0));
    }
    auto m = semloc::RunMetrics::compute(r, c);
    EXPECT_EQ(m.kidnap_step, -1);
    EXPECT_EQ(m.recovery_steps, -1) << "no kidnapping given";
    m = semloc::RunMetrics::compute(r, c, 40);
    EXPECT_EQ(m.convergence_step, 5);
    EXPECT_EQ(m.kidnap_step, 40);
    EXPECT_EQ(m.recovery_steps, 23);
    for (size_t k = 63; k < 100; k++)
    {
        r[k] = rec(k, 8.0, 30.0);
    }
    EXPECT_EQ(semloc::RunMetrics::compute(r, c, 40).recovery_steps, -1) << "never recovered";
}

namespace
{
using semloc::TStepRecord;

/** The record of a step estimated by `pf` (as Localizer::lastStepRecord fills it), at the
 *  ground truth `gt`. */
TStepRecord estimated(const semloc::CParallelMonteCarloLocalization2D& pf, const TPose2D& gt)
{
    const auto [cov, pose, mean] = pf.covariancesAndMean();
    TStepRecord r;
    r.gt = gt;
    r.est = mean.asTPose();
    r.var_xy = cov(0, 0) + cov(1, 1);
    r.setPoseCovariance(pose);
    return r;
}

/** A record with ground truth at the origin, the estimate off by `e` and covariance
 *  (xx, yy, pp, xy, xp, yp). */
TStepRecord withCovariance(const TPose2D& e, const std::array<double, 6>& c)
{
    TStepRecord r;
    r.gt = TPose2D(0, 0, 0);
    r.est = TPose2D(-e.x, -e.y, -e.phi);
    r.var_x = c[0];
    r.var_y = c[1];
    r.var_phi = c[2];
    r.cov_xy = c[3];
    r.cov_xphi = c[4];
    r.cov_yphi = c[5];
    r.var_xy = r.var_x + r.var_y;
    r.n_particles = 100;
    return r;
}
}  // namespace

TEST(RunMetrics, NeesOfAGaussianParticleSetIsTheHandComputedOne)
{
    // P = L L^T, L = [0.5 0 0; 0.2 0.4 0; 0.05 -0.1 0.1]; an error e = L z has NEES
    // e^T P^-1 e = |z|^2: z = (1, -2, 0.5), e = (0.5, -0.6, 0.3), NEES 5.25.
    const double L[3][3] = {{0.5, 0, 0}, {0.2, 0.4, 0}, {0.05, -0.1, 0.1}};
    const TPose2D mean(10, -4, M_PI - 0.05);  // headings either side of +-pi
    const TPose2D gt(10.5, -4.6, mean.phi + 0.3 - 2 * M_PI);

    // Six equal particles at mean +- sqrt(3) L_i: their covariance is P exactly.
    semloc::CParallelMonteCarloLocalization2D sigma(6);
    for (size_t i = 0; i < 6; i++)
    {
        const double s = (i % 2 ? -1.0 : 1.0) * std::sqrt(3.0);
        const size_t c = i / 2;
        sigma.m_particles[i].d = TPose2D(mean.x + s * L[0][c], mean.y + s * L[1][c],
                                         mrpt::math::wrapToPi(mean.phi + s * L[2][c]));
        sigma.m_particles[i].log_w = 0;
    }
    auto r = estimated(sigma, gt);
    EXPECT_NEAR(r.est.phi, mean.phi, 1e-12);
    EXPECT_NEAR(r.var_x, 0.25, 1e-12);
    EXPECT_NEAR(r.cov_xphi, 0.5 * 0.05, 1e-12);
    EXPECT_NEAR(r.cov_yphi, 0.2 * 0.05 - 0.4 * 0.1, 1e-12);
    EXPECT_NEAR(r.var_phi, 0.05 * 0.05 + 0.1 * 0.1 + 0.1 * 0.1, 1e-12);
    EXPECT_NEAR(r.nees(), 5.25, 1e-9);

    // 20000 particles drawn from N(mean, P): the sample's NEES is within a few percent.
    auto& rng = mrpt::random::getRandomGenerator();
    rng.randomize(3);
    semloc::CParallelMonteCarloLocalization2D drawn(20000);
    for (auto& p : drawn.m_particles)
    {
        double z[3];
        for (double& v : z)
        {
            v = rng.drawGaussian1D_normalized();
        }
        double d[3] = {0, 0, 0};
        for (int k = 0; k < 3; k++)
        {
            for (int c = 0; c <= k; c++)
            {
                d[k] += L[k][c] * z[c];
            }
        }
        p.d = TPose2D(mean.x + d[0], mean.y + d[1], mrpt::math::wrapToPi(mean.phi + d[2]));
        p.log_w = 0;
    }
    r = estimated(drawn, gt);
    EXPECT_NEAR(r.nees(), 5.25, 0.25);
    r.gt.reset();
    EXPECT_TRUE(std::isnan(r.nees())) << "no ground truth";
}

TEST(RunMetrics, NeesWrapsTheHeadingError)
{
    // Estimate and truth 0.02 rad apart across +-pi: the error is 0.02 rad, not 2 pi - 0.02.
    TStepRecord r;
    r.gt = TPose2D(0, 0, -M_PI + 0.01);
    r.est = TPose2D(0, 0, M_PI - 0.01);
    r.var_x = r.var_y = 1;
    r.var_phi = 1e-4;
    EXPECT_NEAR(r.nees(), 4.0, 1e-6);
    std::swap(r.gt->phi, r.est.phi);
    EXPECT_NEAR(r.nees(), 4.0, 1e-6);
    r.gt->phi = r.est.phi + 8 * M_PI + 0.02;  // whole turns apart
    EXPECT_NEAR(r.nees(), 4.0, 1e-6);
}

TEST(RunMetrics, SingularCovarianceGetsTheDocumentedFloor)
{
    const double f = TStepRecord::kNeesFloor;
    // Every particle on one pose: no error is 0, an error e is |e|^2 / floor.
    EXPECT_EQ(withCovariance({0, 0, 0}, {0, 0, 0, 0, 0, 0}).nees(), 0.0);
    EXPECT_NEAR(withCovariance({1e-3, 0, 0}, {0, 0, 0, 0, 0, 0}).nees(), 1e-6 / f, 1e-6 / f * 1e-9);
    // A spread along x only: along it, e^2 / (var + floor); across it, the floor.
    EXPECT_NEAR(withCovariance({2, 0, 0}, {4, 0, 0, 0, 0, 0}).nees(), 1.0, 1e-9);
    EXPECT_NEAR(withCovariance({0, 1e-6, 0}, {4, 0, 0, 0, 0, 0}).nees(), 1.0, 1e-6);
    // Perfectly correlated x and y, rounded indefinite (an eigenvalue of -1e-9): the error
    // across the line meets the floor, not a negative variance.
    const double across = withCovariance({1e-6, -1e-6, 0}, {1, 1, 1, 1 + 1e-9, 0, 0}).nees();
    EXPECT_TRUE(std::isfinite(across));
    EXPECT_NEAR(across, 2e-12 / f, 2e-12 / f * 1e-3);
    EXPECT_NEAR(withCovariance({1, 1, 0}, {1, 1, 1, 1, 0, 0}).nees(), 1.0, 1e-9);
    // Non-finite values are NaN, never a number.
    EXPECT_TRUE(std::isnan(withCovariance({1, 0, 0}, {NAN, 1, 1, 0, 0, 0}).nees()));
    EXPECT_TRUE(std::isnan(withCovariance({1, 0, 0}, {1, 1, 1, INFINITY, 0, 0}).nees()));
}

TEST(RunMetrics, NeesIsWellConditionedOnEnoughParticlesAndARegularCovariance)
{
    const auto wellConditioned = [](const std::array<double, 6>& c, double ess = 1)
    {
        auto r = withCovariance({0.1, 0.2, 0.01}, c);
        r.ess = ess;
        return r.neesWellConditioned();
    };
    EXPECT_TRUE(wellConditioned({1, 1, 1, 0, 0, 0}));
    // 100 particles: 45 effective ones (ess 0.45) are enough, 44 are not.
    EXPECT_TRUE(wellConditioned({1, 1, 1, 0, 0, 0}, 0.45));
    EXPECT_FALSE(wellConditioned({1, 1, 1, 0, 0, 0}, 0.44));
    EXPECT_FALSE(wellConditioned({1, 1, 1, 0, 0, 0}, 0.02)) << "the hostile user's ESS 0.002";
    // Every particle on one pose, a direction at the floor, or eigenvalues under 1e-9.
    EXPECT_FALSE(wellConditioned({0, 0, 0, 0, 0, 0}));
    EXPECT_FALSE(wellConditioned({1, 1, 0, 0, 0, 0}));
    EXPECT_TRUE(wellConditioned({1e-8, 1e-8, 1e-8, 0, 0, 0}));
    EXPECT_FALSE(wellConditioned({1e-10, 1e-10, 1e-10, 0, 0, 0}));
    // The condition number: 1e9 is the largest taken.
    EXPECT_TRUE(wellConditioned({10, 1, 1e-8, 0, 0, 0}));
    EXPECT_FALSE(wellConditioned({11, 1, 1e-8, 0, 0, 0}));
    // Perfectly correlated x and y (rounded indefinite), non-finite, no ground truth.
    EXPECT_FALSE(wellConditioned({1, 1, 1, 1 + 1e-9, 0, 0}));
    EXPECT_FALSE(wellConditioned({NAN, 1, 1, 0, 0, 0}));
    auto r = withCovariance({0.1, 0.2, 0.01}, {1, 1, 1, 0, 0, 0});
    r.gt.reset();
    EXPECT_FALSE(r.neesWellConditioned());
    r = withCovariance({0.1, 0.2, 0.01}, {1, 1, 1, 0, 0, 0});
    r.n_particles = 0;
    EXPECT_FALSE(r.neesWellConditioned()) << "no particle count: no effective particles";
}

namespace
{
/** The figures RunMetricsAccumulator keeps online, computed over the whole record list. */
struct BruteForce
{
    long convergence = -1;
    size_t lostSteps = 0, episodes = 0;
    double lostS = NAN, longestS = NAN, firstLostS = NAN, neesMean = NAN, inside = NAN;
    double neesMedian = NAN, wellConditionedShare = NAN, neesMeanWellConditioned = NAN;
};

BruteForce bruteForce(const std::vector<TStepRecord>& r,
                      const semloc::RunMetrics::TConvergenceCriterion& c)
{
    BruteForce b;
    const size_t n = r.size(), minSteps = static_cast<size_t>(std::max(1, c.min_steps));
    const auto ok = [&](size_t k)
    { return r[k].gt && r[k].errXY() < c.max_err_xy_m && r[k].var_xy < c.max_var_xy_m2; };
    const auto lost = [&](size_t k) { return r[k].gt && r[k].errXY() > c.max_err_xy_m; };
    for (size_t i = 0; i < n && b.convergence < 0; i++)
    {
        size_t len = 0;
        while (i + len < n && ok(i + len))
        {
            len++;
        }
        if (len > 0 && (len >= minSteps || i + len == n))
        {
            b.convergence = static_cast<long>(i);
        }
    }
    if (b.convergence >= 0)
    {
        b.lostS = b.longestS = 0;
        double start = 0;
        for (auto k = static_cast<size_t>(b.convergence); k < n; k++)
        {
            if (!lost(k))
            {
                continue;
            }
            b.lostSteps++;
            if (b.lostSteps == 1)
            {
                b.firstLostS = r[k].t - r[0].t;
            }
            if (k == static_cast<size_t>(b.convergence) || !lost(k - 1))
            {
                b.episodes++;
                start = r[k].t;
            }
            if (k + 1 == n || !lost(k + 1))
            {
                const double d = (k + 1 < n ? r[k + 1].t : r[n - 1].t) - start;
                b.lostS += d;
                b.longestS = std::max(b.longestS, d);
            }
        }
    }
    double sum = 0, sumWellConditioned = 0;
    size_t count = 0, in = 0, wellConditioned = 0;
    std::vector<double> all;
    for (const auto& s : r)
    {
        if (s.gt)
        {
            sum += s.nees();
            count++;
            in += s.nees() <= semloc::RunMetrics::kNeesChi2_95 ? 1 : 0;
            all.push_back(s.nees());
            if (s.neesWellConditioned())
            {
                sumWellConditioned += s.nees();
                wellConditioned++;
            }
        }
    }
    if (count > 0)
    {
        b.neesMean = sum / static_cast<double>(count);
        b.inside = static_cast<double>(in) / static_cast<double>(count);
        std::sort(all.begin(), all.end());
        b.neesMedian = 0.5 * (all[(count - 1) / 2] + all[count / 2]);
        b.wellConditionedShare = static_cast<double>(wellConditioned) / static_cast<double>(count);
        if (wellConditioned > 0)
        {
            b.neesMeanWellConditioned = sumWellConditioned / static_cast<double>(wellConditioned);
        }
    }
    return b;
}

/** Steps that are good, lost or neither (bad variance, an error of exactly the bound, no
 *  ground truth), in runs of either kind, with random covariances and headings. */
std::vector<TStepRecord> randomRecords(mrpt::random::CRandomGenerator& rng, size_t n)
{
    std::vector<TStepRecord> r(n);
    bool good = rng.drawUniform(0.0, 1.0) < 0.5;
    double t = 1000 * rng.drawUniform(0.0, 1.0);
    for (size_t k = 0; k < n; k++)
    {
        good = rng.drawUniform(0.0, 1.0) < 0.15 ? !good : good;
        const double u = rng.drawUniform(0.0, 1.0);
        const double err = u < 0.03 ? 1.0  // the bound: neither good nor lost
                           : good   ? rng.drawUniform(0.0, 0.99)
                                    : rng.drawUniform(1.01, 6.0);
        auto& s = r[k];
        s.step = k;
        t += rng.drawUniform(0.05, 0.5);
        s.t = t;
        const double dir = rng.drawUniform(-M_PI, M_PI), phi = rng.drawUniform(-M_PI, M_PI);
        s.est = TPose2D(rng.drawUniform(-50, 50), rng.drawUniform(-50, 50), phi);
        s.gt = TPose2D(s.est.x + err * std::cos(dir), s.est.y + err * std::sin(dir),
                       mrpt::math::wrapToPi(phi + rng.drawGaussian1D(0, 0.2)));
        if (u > 0.95)
        {
            s.gt.reset();
        }
        const double a = rng.drawUniform(0.0, 1.0), b = rng.drawUniform(0.0, 1.0);
        s.var_x = a * a;
        s.var_y = b * b;
        s.var_phi = rng.drawUniform(0.0, 0.1);
        s.cov_xy = rng.drawUniform(-0.9, 0.9) * a * b;
        s.cov_xphi = u < 0.5 ? 0.0 : rng.drawUniform(-0.1, 0.1) * a;
        s.var_xy = rng.drawUniform(0.0, 1.0) < 0.05 ? 2.0 : s.var_x + s.var_y;
        s.n_particles = 100;
        s.ess = k % 7 == 3 ? 0.2 : 1.0;  // 20 effective particles: not well conditioned
    }
    return r;
}
}  // namespace

TEST(RunMetrics, AccumulatorMatchesABruteForceOverTheRecordsAtEveryStep)
{
    // Random runs with short runs of good steps that break before they settle (the candidate
    // convergence step changes), lost episodes after convergence, steps without ground truth
    // and at the exact bound. After every record, the accumulator's figures are the brute
    // force's over the records so far, and compute()'s.
    auto& rng = mrpt::random::getRandomGenerator();
    rng.randomize(11);
    size_t withEpisodes = 0, withReset = 0, converged = 0, openAtEnd = 0;
    size_t wellConditioned = 0, illConditioned = 0;
    for (int trial = 0; trial < 400; trial++)
    {
        semloc::RunMetrics::TConvergenceCriterion c;
        c.min_steps = 1 + static_cast<int>(rng.drawUniform32bit() % 8);
        const auto r = randomRecords(rng, 5 + rng.drawUniform32bit() % 120);
        semloc::RunMetricsAccumulator acc(c);
        long firstCandidate = -1;
        for (size_t k = 0; k < r.size(); k++)
        {
            acc.add(r[k]);
            const auto m = acc.result();
            const std::vector<TStepRecord> prefix(r.begin(), r.begin() + k + 1);
            const auto b = bruteForce(prefix, c);
            firstCandidate = firstCandidate < 0 ? m.convergence_step : firstCandidate;
            ASSERT_EQ(m.convergence_step, b.convergence) << trial << " step " << k;
            ASSERT_EQ(m.lost_after_convergence_steps, b.lostSteps) << trial << " step " << k;
            ASSERT_EQ(m.lost_episodes, b.episodes) << trial << " step " << k;
            const auto same = [](double x, double y) {
                return (std::isnan(x) && std::isnan(y)) ||
                       std::abs(x - y) <= 1e-9 * (1 + std::abs(y));
            };
            ASSERT_PRED2(same, m.lost_after_convergence_s, b.lostS) << trial << " step " << k;
            ASSERT_PRED2(same, m.longest_lost_s, b.longestS) << trial << " step " << k;
            ASSERT_PRED2(same, m.first_lost_after_convergence_s, b.firstLostS) << trial;
            ASSERT_PRED2(same, m.nees_mean, b.neesMean) << trial << " step " << k;
            ASSERT_PRED2(same, m.nees_inside_share, b.inside) << trial << " step " << k;
            ASSERT_PRED2(same, m.nees_median, b.neesMedian) << trial << " step " << k;
            ASSERT_PRED2(same, m.nees_well_conditioned_share, b.wellConditionedShare) << trial;
            ASSERT_PRED2(same, m.nees_mean_well_conditioned, b.neesMeanWellConditioned)
                << trial << " step " << k;
            wellConditioned += r[k].neesWellConditioned() ? 1 : 0;
            illConditioned += r[k].gt && !r[k].neesWellConditioned() ? 1 : 0;
        }
        const auto all = semloc::RunMetrics::compute(r, c);
        const auto m = acc.result();
        EXPECT_EQ(all.lost_episodes, m.lost_episodes);
        EXPECT_EQ(all.nees_mean, m.nees_mean);
        withReset += firstCandidate >= 0 && m.convergence_step != firstCandidate ? 1 : 0;
        withEpisodes += m.lost_episodes > 1 ? 1 : 0;
        converged += m.converged ? 1 : 0;
        openAtEnd += m.converged && r.back().gt && r.back().errXY() > 1 ? 1 : 0;
    }
    EXPECT_GT(withReset, 40u) << "the convergence candidate must change in some runs";
    EXPECT_GT(withEpisodes, 40u) << "runs with several lost episodes after convergence";
    EXPECT_GT(converged, 200u);
    EXPECT_GT(openAtEnd, 20u) << "runs that end lost";
    EXPECT_GT(illConditioned, wellConditioned / 20) << "steps of either kind";
    EXPECT_GT(wellConditioned, illConditioned);
}

TEST(RunMetrics, LostAgainCountsTheEpisodesAfterConvergence)
{
    // Good from step 5 (10 steps settle it), lost at 20-22, good, lost at 30, good, lost from
    // 37 to the end (step 39); steps 1 s apart from t = 100.
    semloc::RunMetrics::TConvergenceCriterion c;
    std::vector<TStepRecord> r;
    for (size_t k = 0; k < 40; k++)
    {
        const bool lost = k < 5 || (k >= 20 && k < 23) || k == 30 || k >= 37;
        r.push_back(rec(k, lost ? 2.0 : 0.3, 0.2));
    }
    auto m = semloc::RunMetrics::compute(r, c);
    ASSERT_EQ(m.convergence_step, 5);
    EXPECT_EQ(m.lost_after_convergence_steps, 3u + 1u + 3u);
    EXPECT_EQ(m.lost_episodes, 3u);
    EXPECT_DOUBLE_EQ(m.lost_after_convergence_s, 3.0 + 1.0 + 2.0) << "the last ends at step 39";
    EXPECT_DOUBLE_EQ(m.longest_lost_s, 3.0);
    EXPECT_DOUBLE_EQ(m.first_lost_after_convergence_s, 20.0);

    // The steps before convergence do not count; none after it: 0 and no first time.
    for (size_t k = 20; k < 40; k++)
    {
        r[k] = rec(k, 0.3, 0.2);
    }
    m = semloc::RunMetrics::compute(r, c);
    EXPECT_EQ(m.lost_after_convergence_steps, 0u);
    EXPECT_EQ(m.lost_episodes, 0u);
    EXPECT_EQ(m.lost_after_convergence_s, 0.0);
    EXPECT_EQ(m.longest_lost_s, 0.0);
    EXPECT_TRUE(std::isnan(m.first_lost_after_convergence_s));

    // Not converged: counts 0, times NaN.
    c.max_err_xy_m = 0.1;
    m = semloc::RunMetrics::compute(r, c);
    EXPECT_FALSE(m.converged);
    EXPECT_EQ(m.lost_episodes, 0u);
    EXPECT_TRUE(std::isnan(m.lost_after_convergence_s));
    EXPECT_TRUE(std::isnan(m.longest_lost_s));
}

TEST(RunMetrics, NeesSummaryCountsTheStepsWithGroundTruth)
{
    // NEES 1 (inside), 4 (inside), 16 (outside: > 7.81), a step without ground truth.
    std::vector<TStepRecord> r;
    for (const double e : {1.0, 2.0, 4.0, 3.0})
    {
        r.push_back(withCovariance({e, 0, 0}, {1, 1, 1, 0, 0, 0}));
        r.back().step = r.size() - 1;
    }
    r.back().gt.reset();
    auto m = semloc::RunMetrics::compute(r, {});
    EXPECT_NEAR(m.nees_mean, 7.0, 1e-9);
    EXPECT_DOUBLE_EQ(m.nees_inside_share, 2.0 / 3.0);
    EXPECT_NEAR(m.nees_median, 4.0, 1e-9);
    EXPECT_NEAR(m.nees_mean_well_conditioned, 7.0, 1e-9);
    EXPECT_DOUBLE_EQ(m.nees_well_conditioned_share, 1.0);
    // A fourth step with ground truth: an even count's median is the mean of the middle two.
    r.back().gt = TPose2D(0, 0, 0);
    m = semloc::RunMetrics::compute(r, {});
    EXPECT_NEAR(m.nees_median, (4.0 + 9.0) / 2, 1e-9);
    r.resize(1);
    r[0].gt.reset();
    m = semloc::RunMetrics::compute(r, {});
    for (const double v : {m.nees_mean, m.nees_inside_share, m.nees_median,
                           m.nees_mean_well_conditioned, m.nees_well_conditioned_share})
    {
        EXPECT_TRUE(std::isnan(v)) << "no ground truth";
    }
}

TEST(RunMetrics, ADegenerateStepSetsTheMeanButNotTheFiguresReported)
{
    // The hostile user's run: 430 steps of a consistent filter (NEES 3: e = (1, 1, 1) with
    // P = I) and one whose cloud collapsed (ESS 0.002 of 2000 particles, P of determinant
    // 4e-30): its NEES, ~2e10, sets the mean of every step alone, ~4e7.
    std::vector<TStepRecord> r;
    for (size_t k = 0; k < 431; k++)
    {
        r.push_back(withCovariance({1, 1, 1}, {1, 1, 1, 0, 0, 0}));
        r.back().step = k;
        r.back().n_particles = 2000;
    }
    r[200] = withCovariance({1, 1, 1}, {1.587e-10, 1.587e-10, 1.587e-10, 0, 0, 0});
    r[200].step = 200;
    r[200].n_particles = 2000;
    r[200].ess = 0.002;
    ASSERT_GT(r[200].nees(), 1e10);
    const auto m = semloc::RunMetrics::compute(r, {});
    EXPECT_GT(m.nees_mean, 1e7) << "the mean of every step means nothing";
    EXPECT_NEAR(m.nees_median, 3.0, 1e-9);
    EXPECT_DOUBLE_EQ(m.nees_inside_share, 430.0 / 431.0);
    EXPECT_NEAR(m.nees_mean_well_conditioned, 3.0, 1e-9);
    EXPECT_DOUBLE_EQ(m.nees_well_conditioned_share, 430.0 / 431.0);
}
