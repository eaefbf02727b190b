/* semloc — random draws of the simulator's sensor models (private). */
#pragma once

#include <mrpt/random/RandomGenerators.h>

#include <cmath>
#include <cstddef>
#include <cstdint>

namespace semloc::detail
{
/** Independent random streams of one simulation, one generator each: changing one sensor's
 *  settings leaves the other sensors' noise unchanged (common random numbers). */
enum class SimStream : uint64_t
{
    Odometry = 1,
    Sonar = 2,
    Detector = 3,
    Kidnapping = 4,
    DetectorGaps = 5,
    Distractors = 6,
    BeaconRanging = 7,
    Depth = 8,
    Compass = 9,
    Usbl = 10,
    Dvl = 11,
    SideScan = 12,
    ForwardSonar = 13,
    Camera = 14
};

/** 32-bit MT19937 seed of a stream: the splitmix64 finalizer (Steele, Lea & Flood 2014) of
 *  (seed, stream), so nearby seeds and streams start far apart in the generator's state. */
inline uint32_t streamSeed(uint32_t seed, SimStream stream)
{
    uint64_t z = (static_cast<uint64_t>(seed) << 8) + static_cast<uint64_t>(stream);
    z += 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return static_cast<uint32_t>(z >> 32);
}

/** Uniform in [0, 1) (drawUniform(0, 1) may return 1, which breaks `u < p` for p = 1). */
inline double uniform01(mrpt::random::CRandomGenerator& rng)
{
    return rng.drawUniform32bit() * (1.0 / 4294967296.0);
}

/** True with probability p (exactly never for p = 0, always for p = 1). */
inline bool bernoulli(mrpt::random::CRandomGenerator& rng, double p)
{
    return uniform01(rng) < p;
}

/** Uniform over {0, ..., n - 1}, n >= 1. */
inline size_t uniformIndex(mrpt::random::CRandomGenerator& rng, size_t n)
{
    const auto i = static_cast<size_t>(uniform01(rng) * static_cast<double>(n));
    return i < n ? i : n - 1;
}

/** Poisson-distributed count of mean `lambda` (Knuth's product of uniforms: O(lambda) draws,
 *  fine for the few false positives per scan; lambda <= 100 keeps exp(-lambda) normal). */
inline unsigned poisson(mrpt::random::CRandomGenerator& rng, double lambda)
{
    const double limit = std::exp(-lambda);
    unsigned k = 0;
    double p = 1.0 - uniform01(rng);  // (0, 1]
    while (p > limit)
    {
        k++;
        p *= 1.0 - uniform01(rng);
    }
    return k;
}

}  // namespace semloc::detail
