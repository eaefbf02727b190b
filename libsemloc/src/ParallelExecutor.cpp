/* semloc — ParallelExecutor: a persistent pool of worker threads woken once per call. */
#include <mrpt/core/exceptions.h>
#include <semloc/ParallelExecutor.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace semloc
{
namespace
{
/** How long a thread polls for the next job or for the others to finish before sleeping on
 *  the condition variable. The filter calls the pool a few times per step in quick
 *  succession, and waking a sleeping thread costs tens of microseconds on a loaded machine
 *  (more than the per-particle loops it would parallelize); a short poll avoids it without
 *  burning a core between steps. */
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
}  // namespace

struct ParallelExecutor::Pool
{
    std::mutex mtx;
    std::condition_variable wake, done;
    std::vector<std::thread> workers;
    /** The current job: chunk k of `chunks` over [0, n) for worker k (1-based); written
     *  under `mtx` before `generation` is increased. */
    const std::function<void(size_t, size_t)>* work = nullptr;
    size_t n = 0, chunks = 0;
    std::atomic<uint64_t> generation{0};
    /** Workers still running the current job (their writes are visible once it is 0). */
    std::atomic<size_t> pending{0};
    std::atomic<bool> stop{false};
    std::vector<std::exception_ptr> errors;

    void workerLoop(size_t k)
    {
        uint64_t seen = 0;
        for (;;)
        {
            spinUntil([&] { return stop.load() || generation.load() != seen; });
            std::unique_lock lk(mtx);
            wake.wait(lk, [&] { return stop.load() || generation.load() != seen; });
            if (stop)
            {
                return;
            }
            seen = generation.load();
            if (k >= chunks)
            {
                continue;  // this job has fewer chunks than threads: not counted in `pending`
            }
            const auto* job = work;
            const size_t jobN = n, jobChunks = chunks;
            lk.unlock();

            std::exception_ptr err;
            try
            {
                size_t b = 0, e = 0;
                chunkRange(jobN, jobChunks, k, b, e);
                (*job)(b, e);
            }
            catch (...)
            {
                err = std::current_exception();
            }

            lk.lock();
            errors[k] = err;
            if (pending.fetch_sub(1, std::memory_order_acq_rel) == 1)
            {
                done.notify_one();
            }
        }
    }
};

ParallelExecutor::ParallelExecutor(size_t threads)
    : m_threads(threads > 0 ? threads : std::max<size_t>(1, std::thread::hardware_concurrency())),
      m_pool(std::make_unique<Pool>())
{
    m_pool->errors.resize(m_threads);
    for (size_t k = 1; k < m_threads; k++)
    {
        m_pool->workers.emplace_back([p = m_pool.get(), k] { p->workerLoop(k); });
    }
}

ParallelExecutor::~ParallelExecutor()
{
    {
        std::lock_guard lk(m_pool->mtx);
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

void ParallelExecutor::forEachChunk(size_t n, const std::function<void(size_t, size_t)>& work,
                                    size_t minChunk)
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
    {
        std::lock_guard lk(p.mtx);
        p.work = &work;
        p.n = n;
        p.chunks = chunks;
        p.pending.store(chunks - 1);
        std::fill(p.errors.begin(), p.errors.end(), nullptr);
        p.generation.fetch_add(1);
    }
    p.wake.notify_all();

    std::exception_ptr first;
    try
    {
        size_t b = 0, e = 0;
        chunkRange(n, chunks, 0, b, e);
        work(b, e);
    }
    catch (...)
    {
        first = std::current_exception();
    }

    spinUntil([&] { return p.pending.load(std::memory_order_acquire) == 0; });
    std::unique_lock lk(p.mtx);
    p.done.wait(lk, [&] { return p.pending.load() == 0; });
    p.work = nullptr;
    for (size_t k = 1; k < chunks && !first; k++)
    {
        first = p.errors[k];
    }
    lk.unlock();
    if (first)
    {
        std::rethrow_exception(first);
    }
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
