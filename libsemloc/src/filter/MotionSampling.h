/* semloc — the motion model's samples: Gaussian odometry increments drawn from per-particle
 * streams and composed onto the particles (private). */
#pragma once

#include <mrpt/math/TPose2D.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/poses/CPosePDFGaussian.h>

#include <cstddef>
#include <cstdint>
#include <optional>

#include "filter/WrapToPi.h"
#include "math/FastMath.h"
#include "math/Ziggurat.h"

namespace semloc::detail
{
/** The odometry of `actions` when it is a CPosePDFGaussian, else none. */
std::optional<mrpt::poses::CPosePDFGaussian> gaussianMotion(
    const mrpt::obs::CActionCollection& actions);

/** Standard normal draws of one particle: a splitmix64 sequence (Steele, Lea & Flood 2014)
 *  started from (step key, particle index), turned into normals by the ziggurat method. A
 *  particle's numbers depend on nothing else, so any thread may draw them: the same bits for
 *  any thread count, and no shared generator to serialize on. */
class ParticleNormals
{
public:
    ParticleNormals(uint64_t key, size_t particle)
        : m_state(key ^ (static_cast<uint64_t>(particle) * 0xD1B54A32D192ED03ull))
    {
    }

    /** One N(0, 1). */
    double operator()()
    {
        return Ziggurat::draw([this] { return next(); });
    }

private:
    uint64_t next()
    {
        uint64_t z = (m_state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    uint64_t m_state;
};

/** Draws pose increments from a CPosePDFGaussian as MRPT's CPoseRandomSampler does
 *  (setPosePDF, do_sample_2D: mean + Z sqrt(D) n for the eigen-decomposition Z D Z^T of
 *  the covariance), with the normals n of ParticleNormals. */
class GaussianIncrementDrawer
{
public:
    explicit GaussianIncrementDrawer(const mrpt::poses::CPosePDFGaussian& pdf);

    mrpt::math::TPose2D draw(ParticleNormals& rng) const
    {
        const double n0 = rng(), n1 = rng(), n2 = rng();
        // r = ((0 + Z(:,0) n0) + Z(:,1) n1) + Z(:,2) n2, x and y side by side (the same
        // operations, in the same order, as one coordinate at a time).
        const Vec2 rxy = ((Vec2{0, 0} + m_zxy[0] * n0) + m_zxy[1] * n1) + m_zxy[2] * n2;
        const double rphi = ((0 + m_zphi[0] * n0) + m_zphi[1] * n1) + m_zphi[2] * n2;
        const Vec2 xy = m_meanXY + rxy;
        return {xy[0], xy[1], wrapToPiExact(m_meanPhi + rphi)};
    }

private:
    Vec2 m_meanXY;
    double m_meanPhi;
    /** Columns of Z sqrt(D): rows x, y as pairs, row phi apart. */
    Vec2 m_zxy[3];
    double m_zphi[3];
};

/** p (+) u for 2D poses, (s, c) = sin, cos of p.phi: (x + c ux - s uy, y + s ux + c uy), x
 *  and y side by side. */
inline mrpt::math::TPose2D compose(const mrpt::math::TPose2D& p, double s, double c,
                                   const mrpt::math::TPose2D& u)
{
    // a - b is a + (-b) exactly: the same bits as the formula one coordinate at a time.
    const Vec2 xy = (Vec2{p.x, p.y} + Vec2{c, s} * u.x) + Vec2{-s, c} * u.y;
    return {xy[0], xy[1], wrapToPiExact(p.phi + u.phi)};
}

/** The heading drift of a prediction step: the particles' rates [rad/s] (rates[k] the rate
 *  of the k-th particle moved), the step's seconds and the std of a rate's change over them
 *  [rad/s]. */
struct DriftStep
{
    double* rates;
    double dt;
    double walk;
};

/** Moves the n poses poses[0..n) (particles i0...) in place by their increments drawn from
 *  `drawer` with step key `key`. With `drift`, each increment's heading loses its particle's
 *  rate times dt, and the rate walks by a fourth normal of the particle's stream. The
 *  headings' sin and cos two particles at a time (fastSinCos2: the same bits as one at a
 *  time). */
template <typename Drawer>
inline void movePoses(const Drawer& drawer, uint64_t key, mrpt::math::TPose2D* poses, size_t i0,
                      size_t n, const DriftStep* drift = nullptr)
{
    forEachSinCos(
        n, [&](size_t k) { return poses[k].phi; },
        [&](size_t k, double s, double c)
        {
            ParticleNormals normals(key, i0 + k);
            mrpt::math::TPose2D u = drawer.draw(normals);
            if (drift)
            {
                double& rate = drift->rates[k];
                u.phi -= rate * drift->dt;
                rate += drift->walk * normals();
            }
            poses[k] = compose(poses[k], s, c, u);
        });
}
}  // namespace semloc::detail
