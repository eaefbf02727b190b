/* semloc — resampling: systematic resampling in blocks on the executor's threads, and the
 * substitution of the particles by resampled indices (private). */
#pragma once

#include <cstddef>
#include <vector>

#include "filter/ParticleStore.h"

namespace semloc
{
class ParallelExecutor;
}

namespace semloc::detail
{
/** Systematic resampling (Kitagawa 1996; Thrun et al., Probabilistic Robotics, Table 4.4):
 *  M equally spaced pointers t_i = (u + i) W / M, u in [0, 1), into the cumulative weights
 *  c_j = w_0 + ... + w_j (W = c_{M-1}); particle j takes the pointers in [c_{j-1}, c_j), the
 *  last particle of positive weight those beyond (rounding). The running sum c is one
 *  sequential chain of additions (its bits are the sequential loop's); everything else runs
 *  per block of particles on the executor's threads: the pointers of block [s, e) are those
 *  with c_{s-1} <= t_i < c_{e-1}, found from the chain's values at the block borders. The
 *  same indices as the sequential walk (systematicResamplingIndices), bit for bit, for any
 *  thread count. Buffers are kept from call to call. */
class SystematicResampling
{
public:
    /** Blocks of this many particles (any size gives the same indices; small blocks spread
     *  the copying evenly over the threads). */
    static constexpr size_t kBlock = 256;

    /** Takes the linear weights `w` (not normalized, >= 0, kept by reference until
     *  resample()); throws unless their sum is positive. */
    void setWeights(const std::vector<double>& w);
    /** Writes the resampled particles of `from` (as many as weights) to `to`, log-weights 0,
     *  for the uniform offset `u` in [0, 1); with `carried`, the values of each particle (its
     *  motion state) follow it from carried->from to carried->to. */
    void resample(double u, const ParticleList& from, ParticleList& to, ParallelExecutor& ex,
                  const CarriedValues* carried = nullptr);

private:
    /** The first pointer i of each block (t_i >= c at its border), for the offset u. */
    void findFirstPointers(double u, double step);
    /** Copies the particles the pointers of block `blk` point at. */
    void copyBlock(size_t blk, double u, double step, const ParticleList& from, ParticleList& to,
                   const CarriedValues* carried) const;

    const std::vector<double>* m_w = nullptr;
    size_t m_last = 0;  ///< the last particle of positive weight
    double m_total = 0;
    /** Cumulative weight before each block (and the total at the end). */
    std::vector<double> m_blockCum;
    /** The first pointer of each block (and M at the end). */
    std::vector<size_t> m_blockFirstPointer;
};

/** Systematic resampling (Thrun et al., Probabilistic Robotics, Table 4.4; MRPT's
 *  prSystematic) of the linear weights w (>= 0, positive sum W) into M particles (`count`;
 *  0: as many as weights): the M pointers t_i = (u + i) W / M, u in [0, 1); particle j takes
 *  the pointers in [c_{j-1}, c_j), c_j = w_0 + ... + w_j summed in order, and the last
 *  particle of positive weight those beyond c_{N-1} (rounding). The source index of each
 *  resampled particle, in order: the sequential walk SystematicResampling's blocks reproduce,
 *  and KldResampling's candidate draw. */
std::vector<size_t> systematicResamplingIndices(const std::vector<double>& w, double u,
                                                size_t count = 0);

/** `to` = the particles of `from` at the sorted indices `idx`, log-weights 0 (and the
 *  `carried` values with them). */
void substituteParticles(const std::vector<size_t>& idx, const ParticleList& from, ParticleList& to,
                         ParallelExecutor& ex, const CarriedValues* carried = nullptr);
}  // namespace semloc::detail
