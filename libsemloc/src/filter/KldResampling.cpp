/* semloc — KLD-sampling at the resampling steps (private). */
#include "filter/KldResampling.h"

#include <mrpt/core/exceptions.h>
#include <mrpt/math/distributions.h>
#include <mrpt/random/RandomGenerators.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <tuple>

#include "filter/Resampling.h"

namespace semloc::detail
{
namespace
{
/** The bin index of coordinate v for bins of size `size` (non-finite: one bin of its own). */
int64_t binOf(double v, double size)
{
    const double b = std::floor(v / size);
    constexpr double kLimit = 9.0e18;
    return std::isfinite(b) ? static_cast<int64_t>(std::clamp(b, -kLimit, kLimit))
                            : std::numeric_limits<int64_t>::min();
}
}  // namespace

size_t kldBound(size_t bins, const mrpt::slam::TKLDParams& p)
{
    if (bins < 2)
    {
        return 0;
    }
    const double n = 0.5 / p.KLD_epsilon *
                     mrpt::math::chi2inv(1.0 - p.KLD_delta, static_cast<unsigned>(bins - 1));
    return std::isfinite(n) && n > 0 ? static_cast<size_t>(std::llround(n)) : 0;
}

void kldResample(const std::vector<double>& w, const ParticleList& particles,
                 const mrpt::slam::TKLDParams& p, double u, mrpt::random::CRandomGenerator& rng,
                 std::vector<size_t>& idx)
{
    ASSERT_EQUAL_(w.size(), particles.size());
    const size_t maxN = std::max<size_t>(1, p.KLD_maxSampleSize);
    const size_t minN = std::min<size_t>(p.KLD_minSampleSize, maxN);
    // Systematic candidates: pointers (u + j) W / maxN into the cumulative weights.
    std::vector<size_t> cand = systematicResamplingIndices(w, u, maxN);

    // Fox's rule over the candidates in a random order.
    std::set<std::tuple<int64_t, int64_t, int64_t>> bins;
    size_t needed = minN;
    idx.clear();
    for (size_t j = 0; j < maxN; j++)
    {
        const size_t r = j + static_cast<size_t>(rng.drawUniform32bit() % (maxN - j));
        std::swap(cand[j], cand[r]);
        const auto& d = particles[cand[j]].d;
        if (bins.emplace(binOf(d.x, p.KLD_binSize_XY), binOf(d.y, p.KLD_binSize_XY),
                         binOf(d.phi, p.KLD_binSize_PHI))
                .second)
        {
            needed = std::max(minN, kldBound(bins.size(), p));
        }
        idx.push_back(cand[j]);
        if (idx.size() >= needed)
        {
            break;
        }
    }
}
}  // namespace semloc::detail
