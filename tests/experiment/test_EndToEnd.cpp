/* semloc tests — MRPT's CMonteCarloLocalization2D driven by a CSemanticMap: global
 * localization from a uniform start over a small map, on a trajectory simulated here. */
#include <gtest/gtest.h>
#include <mrpt/bayes/CParticleFilter.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/random/RandomGenerators.h>
#include <mrpt/slam/CMonteCarloLocalization2D.h>

#include "TestHelpers.h"

using mrpt::math::TPose2D;
using namespace semloc::test;

TEST(EndToEnd, MonteCarloLocalization2DWithSemanticMapConverges)
{
    mrpt::random::getRandomGenerator().randomize(1234);
    mrpt::random::CRandomGenerator simRng(99);
    const semloc::World world = smallWorld();

    auto sem = semloc::CSemanticMap::Create();
    sem->loadFromWorld(world);
    sem->likelihoodOptions.detector.sigma_range_m = 0.5;
    sem->likelihoodOptions.detector.sigma_bearing_deg = 5;
    auto mm = mrpt::maps::CMultiMetricMap::Create();
    mm->maps.push_back(sem);

    mrpt::slam::CMonteCarloLocalization2D pdf(1);
    pdf.options.metricMap = mm;
    pdf.resetUniform(0, 30, 0, 30, -M_PI, M_PI, 20000);

    mrpt::bayes::CParticleFilter pf;
    pf.m_options.PF_algorithm = mrpt::bayes::CParticleFilter::pfStandardProposal;
    pf.m_options.resamplingMethod = mrpt::bayes::CParticleFilter::prSystematic;
    pf.m_options.adaptiveSampleSize = false;
    pf.m_options.BETA = 0.5;

    DetectorSim ds;
    ds.sigma_range_m = 0.1;
    ds.sigma_bearing_rad = 0.01;

    mrpt::obs::CActionRobotMovement2D::TMotionModelOptions mo;
    mo.modelSelection = mrpt::obs::CActionRobotMovement2D::mmGaussian;
    mo.gaussianModel.a1 = 0.02f;
    mo.gaussianModel.a2 = 0.001f;
    mo.gaussianModel.a3 = 0.02f;
    mo.gaussianModel.a4 = 0.02f;
    mo.gaussianModel.minStdXY = 0.03f;
    mo.gaussianModel.minStdPHI = 0.01f;

    // A loop around the middle of the map: 0.5 m per step, turning slowly.
    mrpt::poses::CPose2D truth(8, 6, 0);
    double err = 1e9;
    const int steps = 90;
    for (int k = 0; k < steps; k++)
    {
        const mrpt::poses::CPose2D u(0.5, 0, (k % 30 < 20) ? 0.0 : M_PI / 20);
        truth = truth + u;
        const mrpt::poses::CPose2D odo(u.x() + simRng.drawGaussian1D(0, 0.02), u.y(),
                                       u.phi() + simRng.drawGaussian1D(0, 0.005));
        mrpt::obs::CActionRobotMovement2D act;
        act.computeFromOdometry(odo, mo);
        mrpt::obs::CActionCollection acts;
        acts.insert(act);
        mrpt::obs::CSensoryFrame sf;
        sf.insert(std::make_shared<semloc::CObservationSemantic>(
            observe(world, truth.asTPose(), ds, &simRng)));
        pf.executeOn(pdf, &acts, &sf);

        mrpt::poses::CPose2D mean;
        pdf.getMean(mean);
        err = std::hypot(mean.x() - truth.x(), mean.y() - truth.y());
    }
    EXPECT_LT(err, 0.3) << "final error after " << steps << " steps";
    const auto [cov, mean] = pdf.getCovarianceAndMean();
    EXPECT_LT(cov(0, 0) + cov(1, 1), 0.25);
}
