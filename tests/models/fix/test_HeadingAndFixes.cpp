/* semloc tests — the compass (CCompassMap), the position fixes (CPoseFixMap) and the DVL's
 * motion model (DvlMotionModel): each against its formula, created by name, its bad inputs
 * refused, and a DVL dead-reckoned survey held by its compass and USBL fixes, the same for 1 and
 * 2 threads. */
#include <gtest/gtest.h>
#include <mrpt/bayes/CParticleFilter.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/filter/CParallelMonteCarloLocalization2D.h>
#include <semloc/filter/DvlMotionModel.h>
#include <semloc/filter/MotionModelRegistry.h>
#include <semloc/filter/ParallelExecutor.h>
#include <semloc/models/SensorModelRegistry.h>
#include <semloc/models/compass/CCompassMap.h>
#include <semloc/models/fix/CPoseFixMap.h>

#include <Eigen/Dense>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

namespace
{
using mrpt::math::TPose2D;
constexpr double kDeg = M_PI / 180;

std::shared_ptr<mrpt::obs::CObservationIMU> compassReading(double yaw, double mountYaw = 0)
{
    auto imu = mrpt::obs::CObservationIMU::Create();
    imu->set(mrpt::obs::IMU_YAW, yaw);
    imu->sensorPose = mrpt::poses::CPose3D(0, 0, 0, mountYaw, 0, 0);
    return imu;
}

std::shared_ptr<mrpt::obs::CObservationRobotPose> fix(double x, double y, double sxx, double sxy,
                                                      double syy)
{
    auto f = mrpt::obs::CObservationRobotPose::Create();
    f->pose.mean = mrpt::poses::CPose3D(x, y, -20, 0, 0, 0);
    f->pose.cov.setIdentity();
    f->pose.cov(0, 0) = sxx;
    f->pose.cov(0, 1) = f->pose.cov(1, 0) = sxy;
    f->pose.cov(1, 1) = syy;
    return f;
}

TEST(HeadingAndFixes, CompassIsItsFormula)
{
    semloc::CCompassMap map;
    map.likelihoodOptions.sigma_deg = 3;
    map.likelihoodOptions.p_outlier = 0.05;
    const auto reading = compassReading(3.1, 0.2);
    std::vector<TPose2D> poses;
    for (double phi = -M_PI; phi < M_PI; phi += 0.1)
    {
        poses.emplace_back(1, 2, phi);
    }
    std::vector<double> out(poses.size());
    ASSERT_TRUE(map.uses(*reading));
    map.logLikelihoods(*reading, poses.data(), poses.size(), out.data());
    for (size_t i = 0; i < poses.size(); i++)
    {
        const double d = std::remainder(3.1 - 0.2 - poses[i].phi, 2 * M_PI);
        const double s = 3 * kDeg;
        const double want =
            std::log(0.95 * std::exp(-0.5 * d * d / (s * s)) / (std::sqrt(2 * M_PI) * s) +
                     0.05 / (2 * M_PI));
        EXPECT_NEAR(out[i], want, 1e-12) << i;
        EXPECT_NEAR(map.computeObservationLikelihood(
                        *reading, mrpt::poses::CPose3D(1, 2, 0, poses[i].phi, 0, 0)),
                    out[i], 1e-9);
    }
    // An IMU reading without a yaw, or of another sensor, is not the compass's.
    auto gyroOnly = mrpt::obs::CObservationIMU::Create();
    gyroOnly->set(mrpt::obs::IMU_WZ, 0.1);
    EXPECT_FALSE(map.uses(*gyroOnly));
    map.likelihoodOptions.sensor_label = "ahrs";
    EXPECT_FALSE(map.uses(*reading));
}

TEST(HeadingAndFixes, FixIsItsGaussian)
{
    semloc::CPoseFixMap map;
    map.likelihoodOptions.p_outlier = 0;
    const auto f = fix(10, 20, 4, 1.5, 2);
    Eigen::Matrix2d c;
    c << 4, 1.5, 1.5, 2;
    for (const auto& p : {TPose2D(10, 20, 0), TPose2D(12, 19, 1), TPose2D(3, 30, -2)})
    {
        double out = 0;
        map.logLikelihoods(*f, &p, 1, &out);
        const Eigen::Vector2d d(10 - p.x, 20 - p.y);
        const double want =
            -0.5 * d.dot(c.inverse() * d) - std::log(2 * M_PI) - 0.5 * std::log(c.determinant());
        EXPECT_NEAR(out, want, 1e-12);
    }
    // sigma_m overrides the fix's covariance; an outlier share bounds a far fix's cost.
    map.likelihoodOptions.sigma_m = 3;
    double sxx = 0, sxy = 0, syy = 0;
    ASSERT_TRUE(map.covariance(*f, sxx, sxy, syy));
    EXPECT_EQ(sxx, 9);
    EXPECT_EQ(sxy, 0);
    const TPose2D far(300, 20, 0);
    double sharp = 0, robust = 0;
    map.logLikelihoods(*f, &far, 1, &sharp);
    map.likelihoodOptions.p_outlier = 0.05;
    map.logLikelihoods(*f, &far, 1, &robust);
    EXPECT_LT(sharp, -4000);
    EXPECT_GT(robust, -30);
    // A fix whose covariance is not positive definite is refused where a fix map is held.
    semloc::CPoseFixMap own;
    const auto* kind = semloc::SensorModelRegistry::of(own);
    ASSERT_NE(kind, nullptr);
    EXPECT_NE(kind->invalidObservation(*fix(1, 2, 0, 0, 0), own).find("positive definite"),
              std::string::npos);
    EXPECT_NE(kind->invalidObservation(*fix(std::nan(""), 2, 1, 0, 1), own).find("not finite"),
              std::string::npos);
    EXPECT_EQ(kind->invalidObservation(*fix(1, 2, 1, 0, 1), own), "");
    semloc::CCompassMap compass;
    EXPECT_EQ(kind->invalidObservation(*fix(1, 2, 0, 0, 0), compass), "")
        << "only a filter with a fix map refuses fixes";
}

std::string loadError(const std::string& text)
{
    mrpt::config::CConfigFileMemory ini;
    ini.setContent(text);
    mrpt::maps::TSetOfMetricMapInitializers inits;
    try
    {
        inits.loadFromConfigFile(ini, "MetricMap");
    }
    catch (const std::exception& e)
    {
        return e.what();
    }
    return {};
}

TEST(HeadingAndFixes, CreatedByNameAndReadStrictly)
{
    mrpt::config::CConfigFileMemory ini;
    ini.setContent(
        "[MetricMap]\ncompassMap_count=1\nposeFixMap_count=1\n"
        "[MetricMap_compassMap_00_likelihoodOpts]\nsigma_deg=5\n"
        "[MetricMap_poseFixMap_00_likelihoodOpts]\nsigma_m=2.5\nsensor_label=usbl\n");
    mrpt::maps::TSetOfMetricMapInitializers inits;
    inits.loadFromConfigFile(ini, "MetricMap");
    mrpt::maps::CMultiMetricMap multi(inits);
    ASSERT_EQ(multi.maps.size(), 2u);
    size_t found = 0;
    for (const auto& m : multi.maps)
    {
        if (const auto* c = dynamic_cast<const semloc::CCompassMap*>(m.get()))
        {
            EXPECT_EQ(c->likelihoodOptions.sigma_deg, 5);
            found++;
        }
        if (const auto* f = dynamic_cast<const semloc::CPoseFixMap*>(m.get()))
        {
            EXPECT_EQ(f->likelihoodOptions.sigma_m, 2.5);
            EXPECT_EQ(f->likelihoodOptions.sensor_label, "usbl");
            found++;
        }
    }
    EXPECT_EQ(found, 2u);
    EXPECT_NE(loadError("[MetricMap]\ncompassMap_count=1\n"
                        "[MetricMap_compassMap_00_likelihoodOpts]\nsigma=5\n")
                  .find("sigma"),
              std::string::npos);
    EXPECT_NE(loadError("[MetricMap]\ncompassMap_count=1\n"
                        "[MetricMap_compassMap_00_likelihoodOpts]\np_outlier=1\n")
                  .find("p_outlier"),
              std::string::npos);
    EXPECT_NE(loadError("[MetricMap]\nposeFixMap_count=1\n"
                        "[MetricMap_poseFixMap_00_likelihoodOpts]\nsigma_m=-1\n")
                  .find("sigma_m"),
              std::string::npos);
}

/** A DVL increment of (du, dv, dpsi) as a rawlog carries it. */
mrpt::obs::CActionCollection dvlStep(double du, double dv, double dpsi)
{
    mrpt::obs::CActionRobotMovement2D move;
    mrpt::obs::CActionRobotMovement2D::TMotionModelOptions opts;
    opts.modelSelection = mrpt::obs::CActionRobotMovement2D::mmGaussian;
    move.computeFromOdometry(mrpt::poses::CPose2D(du, dv, dpsi), opts);
    mrpt::obs::CActionCollection acts;
    acts.insert(move);
    return acts;
}

TEST(HeadingAndFixes, DvlNoiseIsAShareOfTheDistanceInEachBodyAxis)
{
    semloc::MotionModelConfig::TOptions o;
    o.kind = "dvl";
    o.a1 = 0.02;
    o.a3 = 0.5;
    o.a4 = 0.1;
    const auto model = semloc::MotionModelRegistry::create(o);
    ASSERT_TRUE(std::dynamic_pointer_cast<semloc::DvlMotionModel>(model));
    const size_t n = 40000;
    const auto acts = dvlStep(3, 4, 0.2);  // 5 m, crabbing
    mrpt::random::CRandomGenerator rng(4);
    model->prepare({acts, nullptr, n, nullptr}, rng);
    std::vector<TPose2D> poses(n, TPose2D(0, 0, M_PI / 2));  // heading north: body x is world y
    model->move(0, n, poses.data(), nullptr);
    double mu = 0, mv = 0, mp = 0, vu = 0, vv = 0, vp = 0;
    for (const auto& p : poses)
    {
        const double u = p.y, v = -p.x, dp = p.phi - M_PI / 2;  // back into the body frame
        mu += u, mv += v, mp += dp;
        vu += (u - 3) * (u - 3), vv += (v - 4) * (v - 4), vp += (dp - 0.2) * (dp - 0.2);
    }
    mu /= n, mv /= n, mp /= n;
    const double su = std::sqrt(vu / n), sv = std::sqrt(vv / n), sp = std::sqrt(vp / n);
    EXPECT_NEAR(mu, 3, 0.005);
    EXPECT_NEAR(mv, 4, 0.005);
    EXPECT_NEAR(mp, 0.2, 0.001);
    EXPECT_NEAR(su, 0.1, 0.003);  // 2 % of 5 m
    EXPECT_NEAR(sv, 0.1, 0.003);
    EXPECT_NEAR(sp, (0.5 * 5 + 0.1 * 0.2 / kDeg) * kDeg, 0.002);
    // The same particles for any split into blocks.
    model->prepare({acts, nullptr, n, nullptr}, rng);
    std::vector<TPose2D> a(100, TPose2D(1, 2, 0.3)), b = a;
    model->move(0, 100, a.data(), nullptr);
    model->move(0, 37, b.data(), nullptr);
    model->move(37, 63, b.data() + 37, nullptr);
    for (size_t i = 0; i < a.size(); i++)
    {
        ASSERT_EQ(a[i].x, b[i].x);
        ASSERT_EQ(a[i].phi, b[i].phi);
    }
    // Its keys are the odometry's own; the odometry model's extras are refused.
    o.heading_drift_std_deg_per_min = 1;
    EXPECT_THROW(semloc::MotionModelRegistry::create(o), std::exception);
    mrpt::obs::CActionCollection none;
    EXPECT_THROW(model->prepare({none, nullptr, n, nullptr}, rng), std::exception);
}

struct SurveyRun
{
    std::vector<TPose2D> particles;
    double error = 0, headingError = 0;
};

/** 300 s of a lawnmower leg at 1.5 m/s from a dive point known to 3 m: the DVL's increments
 *  carry a 1 % scale error and the compass 2 deg of noise; a USBL fix (3 m) every 20 s. */
SurveyRun usblSurvey(size_t threads, bool fixes)
{
    auto multi = mrpt::maps::CMultiMetricMap::Create();
    auto compass = std::make_shared<semloc::CCompassMap>();
    compass->likelihoodOptions.sigma_deg = 2;
    auto fixMap = std::make_shared<semloc::CPoseFixMap>();
    multi->maps.push_back(compass);
    multi->maps.push_back(fixMap);
    semloc::CParallelMonteCarloLocalization2D pdf;
    pdf.options.metricMap = multi;
    pdf.setExecutor(std::make_shared<semloc::ParallelExecutor>(threads));
    semloc::MotionModelConfig::TOptions o;
    o.kind = "dvl";
    o.a1 = 0.02;
    o.a3 = 0.2;
    pdf.setMotionModel(semloc::MotionModelRegistry::create(o));
    mrpt::random::getRandomGenerator().randomize(8);
    pdf.resetUniform(-5, 5, -5, 5, -0.2, 0.2, 2000);
    mrpt::bayes::CParticleFilter pf;
    pf.m_options.resamplingMethod = mrpt::bayes::CParticleFilter::prSystematic;
    std::mt19937 rng(2);
    std::normal_distribution<double> n(0, 1);
    TPose2D truth(0, 0, 0);
    for (int k = 1; k <= 300; k++)
    {
        const double dpsi = (k % 100 == 0) ? M_PI / 2 : 0;
        const double du = 1.5, dv = 0.3;  // crabbing in a current
        const double c = std::cos(truth.phi), s = std::sin(truth.phi);
        truth.x += c * du - s * dv;
        truth.y += s * du + c * dv;
        truth.phi = std::remainder(truth.phi + dpsi, 2 * M_PI);
        mrpt::obs::CSensoryFrame sf;
        sf.insert(compassReading(truth.phi + 2 * kDeg * n(rng)));
        if (fixes && k % 20 == 0)
        {
            sf.insert(fix(truth.x + 3 * n(rng), truth.y + 3 * n(rng), 9, 0, 9));
        }
        const auto acts = dvlStep(1.01 * du, 1.01 * dv, dpsi);
        pf.executeOn(pdf, &acts, &sf);
    }
    SurveyRun r;
    const auto mean = pdf.getMeanVal();
    r.error = std::hypot(mean.x() - truth.x, mean.y() - truth.y);
    r.headingError = std::abs(std::remainder(mean.phi() - truth.phi, 2 * M_PI));
    for (size_t i = 0; i < pdf.size(); i++)
    {
        r.particles.push_back(pdf.m_particles[i].d);
    }
    return r;
}

TEST(HeadingAndFixes, UsblFixesHoldADvlSurvey)
{
    const auto one = usblSurvey(1, true), two = usblSurvey(2, true);
    const auto alone = usblSurvey(1, false);
    EXPECT_LT(one.error, 2.5);
    EXPECT_LT(one.headingError, 2 * kDeg);
    EXPECT_GT(alone.error, one.error) << "dead reckoning drifts without the fixes";
    ASSERT_EQ(one.particles.size(), two.particles.size());
    for (size_t i = 0; i < one.particles.size(); i++)
    {
        ASSERT_EQ(one.particles[i].x, two.particles[i].x) << i;
        ASSERT_EQ(one.particles[i].phi, two.particles[i].phi) << i;
    }
}

}  // namespace
