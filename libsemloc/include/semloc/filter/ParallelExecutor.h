/* semloc — the execution policy of the particle filter: per-particle work on a small
 * persistent thread pool, over ranges the threads claim as they go. */
#pragma once

#include <cstddef>
#include <functional>
#include <memory>

namespace semloc
{
/** Runs per-item work (one item = one particle) on a fixed set of threads.
 *
 *  The calling thread and the pool's threads claim the work as they go: a thread that
 *  starts late (woken from sleep, descheduled by another process) takes less, and the
 *  call returns as soon as every item is done, without waiting for threads that found
 *  nothing left. Every item's result is written by the work function to the item's own
 *  slot, so the results do not depend on the thread count (no shared accumulator, no
 *  atomics). Reductions that must not depend on the thread count use reduceBlocks(), whose
 *  blocks are fixed by n alone; forEachRange() serves partition-free reductions (maximum,
 *  integer counts) through per-thread partial results.
 *
 *  One executor serves one call at a time on its threads: a call made while another runs
 *  (from another thread, or from a work function) runs its work on its calling thread
 *  alone, with the same results (forEachRange: one range; forEachChunk: the same chunks in
 *  order). */
class ParallelExecutor
{
public:
    /** `threads` = 0 uses every hardware thread (std::thread::hardware_concurrency()). */
    explicit ParallelExecutor(size_t threads = 0);
    ~ParallelExecutor();
    ParallelExecutor(const ParallelExecutor&) = delete;
    ParallelExecutor& operator=(const ParallelExecutor&) = delete;

    /** Number of threads, the caller's included (>= 1). */
    size_t threads() const { return m_threads; }

    /** Calls `work(begin, end)` once per chunk of [0, n): at most threads() chunks, fixed
     *  by n and threads() (chunkRange()), none smaller than `minChunk` items unless n is;
     *  returns when all are done. An exception thrown by any chunk is rethrown here (the
     *  lowest chunk's). */
    void forEachChunk(size_t n, const std::function<void(size_t begin, size_t end)>& work,
                      size_t minChunk = 256);

    /** Calls `work(begin, end, thread)` over disjoint ranges covering [0, n), claimed by the
     *  threads as they go (guided: large ranges first, then smaller ones, none smaller than
     *  `grain` items unless at the end), `thread` in [0, threads()) naming the thread that
     *  runs it (for per-thread partial results). The ranges, and which thread runs which,
     *  change from call to call: only for work whose result does not depend on them. An
     *  exception is rethrown here (the one of the lowest range). */
    void forEachRange(size_t n,
                      const std::function<void(size_t begin, size_t end, size_t thread)>& work,
                      size_t grain = 64);

    /** Size of the blocks of reduceBlocks(): fixed, so block sums never depend on threads. */
    static constexpr size_t kReduceBlock = 1024;

    /** Sum over [0, n) of `blockSum(begin, end)` evaluated on the fixed blocks
     *  [k kReduceBlock, (k + 1) kReduceBlock), the blocks spread over the threads and
     *  their partial sums added in block order: the same bits for any thread count. Threads
     *  get at least `minBlocksPerThread` blocks (fewer threads for cheap sums). */
    double reduceBlocks(size_t n, const std::function<double(size_t begin, size_t end)>& blockSum,
                        size_t minBlocksPerThread = 1);

    /** Chunk `k` of `chunks` over [0, n): [k n / chunks, (k + 1) n / chunks). */
    static void chunkRange(size_t n, size_t chunks, size_t k, size_t& begin, size_t& end);

private:
    struct Pool;
    size_t m_threads = 1;
    std::unique_ptr<Pool> m_pool;
};

}  // namespace semloc
