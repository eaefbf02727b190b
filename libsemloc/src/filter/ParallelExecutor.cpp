/* semloc — ParallelExecutor: a persistent pool of worker threads that claim the work of each
 * call as they go. */
#include <mrpt/core/exceptions.h>
#include <semloc/filter/ParallelExecutor.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <limits>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace semloc
{
namespace
{
/** How long a thread polls for the next job or for the others to finish before sleeping on
 *  the condition variable (or yielding). The filter calls the pool a few times per step in
 *  quick succession, and waking a sleeping thread costs tens of microseconds on a loaded
 *  machine (more than the per-particle loops it would parallelize); a short poll avoids it
 *  without burning a core between steps. */
constexpr auto kSpin = std::chrono::microseconds(100);

inline void cpuRelax()
{
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#else
    std::this_thread::yield();
#endif
}

/** Polls `ready()` for up to kSpin; true if it became true. */
template <typename F>
bool spinUntil(F&& ready)
{
    const auto until = std::chrono::steady_clock::now() + kSpin;
    for (unsigned i = 0;; i++)
    {
        if (ready())
        {
            return true;
        }
        cpuRelax();
        if ((i & 63) == 63 && std::chrono::steady_clock::now() > until)
        {
            return false;
        }
    }
}

using RangeFn = std::function<void(size_t, size_t, size_t)>;
using ChunkFn = std::function<void(size_t, size_t)>;
}  // namespace

/** The job protocol. The caller publishes job g (fields, then `generation` = g), claims work
 *  like any worker, then closes it (`closed` = g) and waits until no worker is `active`. A
 *  worker counts itself active first and only then checks that job g is still open: with
 *  sequentially consistent operations on `active` and `closed`, either the caller sees it
 *  active (and waits for it) or it sees the job closed (and leaves the fields alone, which
 *  the caller may be rewriting for the next job). So the caller never waits for a thread
 *  that is asleep or descheduled when the work runs out. */
struct ParallelExecutor::Pool
{
    size_t threads = 1;
    std::vector<std::thread> workers;

    // The current job; written by the caller only while no worker may read it.
    const RangeFn* rangeWork = nullptr;
    const ChunkFn* chunkWork = nullptr;
    size_t n = 0;
    /** > 0: the fixed chunks of forEachChunk (claimed by index); 0: guided ranges. */
    size_t chunks = 0;
    size_t grain = 1;

    std::atomic<uint64_t> generation{0};
    std::atomic<uint64_t> closed{0};
    std::atomic<size_t> active{0};
    /** Next unclaimed item (guided) or chunk index. */
    std::atomic<size_t> cursor{0};

    std::mutex errorMtx;
    std::exception_ptr error;
    size_t errorAt = 0;

    std::mutex sleepMtx;
    std::condition_variable wake;
    std::atomic<size_t> sleepers{0};
    std::atomic<bool> stop{false};
    /** A job is running: another call (another thread's, or a work function's) runs alone. */
    std::atomic<bool> busy{false};

    /** Claims the pool for a job; false if it is running one. */
    bool acquire() { return !busy.exchange(true, std::memory_order_acquire); }
    /** Releases an acquire()d pool at the end of the job, returned or thrown. */
    struct Claim
    {
        Pool& pool;
        ~Claim() { pool.busy.store(false, std::memory_order_release); }
    };

    void run(size_t begin, size_t end, size_t thread)
    {
        try
        {
            if (rangeWork)
            {
                (*rangeWork)(begin, end, thread);
            }
            else
            {
                (*chunkWork)(begin, end);
            }
        }
        catch (...)
        {
            std::lock_guard lk(errorMtx);
            if (!error || begin < errorAt)
            {
                error = std::current_exception();
                errorAt = begin;
            }
        }
    }

    /** Claims and runs work of the current job until none is left. */
    void claimAll(size_t thread)
    {
        if (chunks > 0)
        {
            for (;;)
            {
                const size_t k = cursor.fetch_add(1, std::memory_order_relaxed);
                if (k >= chunks)
                {
                    return;
                }
                size_t b = 0, e = 0;
                chunkRange(n, chunks, k, b, e);
                run(b, e, thread);
            }
        }
        size_t c = cursor.load(std::memory_order_relaxed);
        while (c < n)
        {
            // Guided: half of an equal share of what is left, so the last claims are small
            // and the threads finish together.
            const size_t take = std::max(grain, (n - c) / (2 * threads));
            const size_t e = std::min(n, c + take);
            if (cursor.compare_exchange_weak(c, e, std::memory_order_relaxed))
            {
                run(c, e, thread);
                c = cursor.load(std::memory_order_relaxed);
            }
        }
    }

    /** Runs one job on the calling thread (thread 0) and the workers; rethrows. */
    void execute()
    {
        error = nullptr;
        cursor.store(0, std::memory_order_relaxed);
        const uint64_t g = generation.load(std::memory_order_relaxed) + 1;
        generation.store(g);
        if (sleepers.load() > 0)
        {
            std::lock_guard lk(sleepMtx);
            wake.notify_all();
        }
        claimAll(0);
        closed.store(g);
        if (!spinUntil([&] { return active.load() == 0; }))
        {
            while (active.load() != 0)
            {
                std::this_thread::yield();  // a worker descheduled in the middle of a range
            }
        }
        rangeWork = nullptr;
        chunkWork = nullptr;
        if (error)
        {
            std::rethrow_exception(std::exchange(error, nullptr));
        }
    }

    void workerLoop(size_t thread)
    {
        uint64_t seen = 0;
        for (;;)
        {
            auto news = [&] { return stop.load() || generation.load() != seen; };
            if (!spinUntil(news))
            {
                std::unique_lock lk(sleepMtx);
                sleepers.fetch_add(1);
                wake.wait(lk, news);
                sleepers.fetch_sub(1);
            }
            if (stop.load())
            {
                return;
            }
            const uint64_t g = generation.load();
            active.fetch_add(1);
            if (generation.load() == g && closed.load() < g)
            {
                claimAll(thread);
            }
            active.fetch_sub(1);
            seen = g;
        }
    }
};

ParallelExecutor::ParallelExecutor(size_t threads)
    : m_threads(threads > 0 ? threads : std::max<size_t>(1, std::thread::hardware_concurrency())),
      m_pool(std::make_unique<Pool>())
{
    m_pool->threads = m_threads;
    for (size_t k = 1; k < m_threads; k++)
    {
        m_pool->workers.emplace_back([p = m_pool.get(), k] { p->workerLoop(k); });
    }
}

ParallelExecutor::~ParallelExecutor()
{
    {
        std::lock_guard lk(m_pool->sleepMtx);
        m_pool->stop.store(true);
    }
    m_pool->wake.notify_all();
    for (auto& t : m_pool->workers)
    {
        t.join();
    }
}

void ParallelExecutor::chunkRange(size_t n, size_t chunks, size_t k, size_t& begin, size_t& end)
{
    begin = k * n / chunks;
    end = (k + 1) * n / chunks;
}

void ParallelExecutor::forEachChunk(size_t n, const ChunkFn& work, size_t minChunk)
{
    if (n == 0)
    {
        return;
    }
    const size_t chunks = std::clamp<size_t>(n / std::max<size_t>(1, minChunk), 1, m_threads);
    if (chunks == 1)
    {
        work(0, n);
        return;
    }
    Pool& p = *m_pool;
    if (!p.acquire())
    {
        // The pool is busy (a concurrent caller, or a call from a work function): the same
        // chunks, one after the other on this thread.
        for (size_t k = 0; k < chunks; k++)
        {
            size_t b = 0, e = 0;
            chunkRange(n, chunks, k, b, e);
            work(b, e);
        }
        return;
    }
    const Pool::Claim claim{p};
    p.chunkWork = &work;
    p.n = n;
    p.chunks = chunks;
    p.execute();
}

void ParallelExecutor::forEachRange(size_t n, const RangeFn& work, size_t grain)
{
    if (n == 0)
    {
        return;
    }
    grain = std::max<size_t>(1, grain);
    if (m_threads == 1 || n <= grain)
    {
        work(0, n, 0);
        return;
    }
    Pool& p = *m_pool;
    if (!p.acquire())
    {
        work(0, n, 0);  // the pool is busy (see forEachChunk): all on this thread
        return;
    }
    const Pool::Claim claim{p};
    p.rangeWork = &work;
    p.n = n;
    p.chunks = 0;
    p.grain = grain;
    p.execute();
}

double ParallelExecutor::reduceBlocks(size_t n,
                                      const std::function<double(size_t, size_t)>& blockSum,
                                      size_t minBlocksPerThread)
{
    const size_t blocks = (n + kReduceBlock - 1) / kReduceBlock;
    std::vector<double> partial(blocks, 0.0);
    forEachChunk(
        blocks,
        [&](size_t b0, size_t b1)
        {
            for (size_t b = b0; b < b1; b++)
            {
                partial[b] = blockSum(b * kReduceBlock, std::min(n, (b + 1) * kReduceBlock));
            }
        },
        minBlocksPerThread);
    double sum = 0;
    for (const double s : partial)
    {
        sum += s;
    }
    return sum;
}

}  // namespace semloc
