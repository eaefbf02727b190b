/* semloc — the particle set of the filter and its loops over contiguous runs (private). */
#pragma once

#include <mrpt/poses/CPosePDFParticles.h>

#include <algorithm>
#include <cstddef>

namespace semloc::detail
{
/** The particles of CParallelMonteCarloLocalization2D (MRPT's CPosePDFParticles list: a
 *  std::deque of poses with their log-weights). */
using ParticleList = mrpt::poses::PFDataTPose2D::CParticleList;

/** Calls `run(first, i, n)` for the runs of particles [b, e) of `particles` (a std::deque)
 *  that lie contiguously in memory: first points at particle i, the run holds n. The loops
 *  over a run are plain pointer loops, without the deque iterator's end-of-node check (and
 *  its branch) per particle. libstdc++ exposes its node bounds; elsewhere runs of one. */
template <typename Particles, typename Run>
inline void forEachRun(Particles& particles, size_t b, size_t e, Run&& run)
{
    auto it = particles.begin() + static_cast<ptrdiff_t>(b);
    while (b < e)
    {
#if defined(__GLIBCXX__)
        const size_t n = std::min(e - b, static_cast<size_t>(it._M_last - it._M_cur));
#else
        const size_t n = 1;
#endif
        run(&*it, b, n);
        b += n;
        if (b < e)
        {
            it += static_cast<ptrdiff_t>(n);
        }
    }
}
}  // namespace semloc::detail
