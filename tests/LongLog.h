/* semloc tests — a rawlog of any length written entry by entry: a vehicle circling the paper
 * world, detecting (with ids; exactly, or with Gaussian range and bearing noise) the objects
 * within 15 m and 60 deg of its heading. */
#pragma once

#include <mrpt/core/Clock.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/io/RawlogWriter.h>
#include <semloc/observation/CObservationSemantic.h>
#include <semloc/world/World.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>

namespace semloc::test
{
/** The detector's noise of a long log: Gaussian, of these sigmas (0: exact readings), drawn
 *  from a generator seeded with `seed`. */
struct TLongLogNoise
{
    double range_m = 0, bearing_rad = 0;
    uint32_t seed = 1;
};

/** Writes `steps` action / sensory-frame pairs (1 s apart, from t = 1.7e9 s) to `rawlogPath`
 *  and their ground truth (`t x y phi`) to `gtPath`: the vehicle circles the centre of `world`
 *  at radius 12 m and 0.6 m/s, its detections read with `noise`. Nothing is held in memory but
 *  one step. */
inline void writeLongLog(const World& world, size_t steps, const std::string& rawlogPath,
                         const std::string& gtPath, const TLongLogNoise& noise = {})
{
    std::mt19937 rng(noise.seed);
    std::normal_distribution<double> gauss;
    const auto noisy = [&](double v, double sigma)
    { return sigma > 0 ? v + sigma * gauss(rng) : v; };
    GzOutputFile out(rawlogPath);
    auto ar = mrpt::serialization::archiveFrom(out);
    writeRawlogSignature(ar, "a long test log");
    std::FILE* gt = std::fopen(gtPath.c_str(), "w");
    const double cx = 0.5 * (world.bounds.x_min + world.bounds.x_max);
    const double cy = 0.5 * (world.bounds.y_min + world.bounds.y_max);
    const double radius = 12, rate = 0.05;  // rad/s
    auto poseAt = [&](size_t k)
    {
        const double a = rate * static_cast<double>(k);
        return mrpt::math::TPose2D(cx + radius * std::cos(a), cy + radius * std::sin(a),
                                   a + M_PI / 2);
    };
    const mrpt::obs::CActionRobotMovement2D::TMotionModelOptions model;
    for (size_t k = 0; k < steps; k++)
    {
        const double t = 1.7e9 + static_cast<double>(k);
        const mrpt::math::TPose2D pose = poseAt(k);
        mrpt::obs::CActionRobotMovement2D move;
        move.computeFromOdometry(
            mrpt::poses::CPose2D(pose) - mrpt::poses::CPose2D(poseAt(k == 0 ? 0 : k - 1)), model);
        move.timestamp = mrpt::Clock::fromDouble(t);
        mrpt::obs::CActionCollection acts;
        acts.insert(move);
        ar << acts;

        auto obs = CObservationSemantic::Create();
        obs->sensorLabel = "SEMANTIC";
        obs->timestamp = mrpt::Clock::fromDouble(t);
        obs->maxRange_m = 20;
        obs->fov_rad = M_PI * 2 / 3;
        for (const auto& o : world.objects)
        {
            const double dx = o.center.x - pose.x, dy = o.center.y - pose.y;
            const double r = std::hypot(dx, dy);
            const double b = std::remainder(std::atan2(dy, dx) - pose.phi, 2 * M_PI);
            if (r < 15 && std::abs(b) < M_PI / 3)
            {
                obs->detections.push_back({o.label, std::max(0.0, noisy(r, noise.range_m)),
                                           noisy(b, noise.bearing_rad), 0.9, o.id});
            }
        }
        mrpt::obs::CSensoryFrame sf;
        sf.insert(obs);
        ar << sf;
        std::fprintf(gt, "%.6f %.9g %.9g %.9g\n", t, pose.x, pose.y, pose.phi);
    }
    out.close();
    std::fclose(gt);
}

}  // namespace semloc::test
