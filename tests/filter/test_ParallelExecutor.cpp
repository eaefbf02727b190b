/* semloc tests — ParallelExecutor: every item once, exceptions rethrown, block sums that do
 * not depend on the thread count. */
#include <gtest/gtest.h>
#include <semloc/filter/ParallelExecutor.h>

#include <atomic>
#include <cmath>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

using semloc::ParallelExecutor;

namespace
{
/** Every item was visited exactly once. */
void expectEachOnce(const std::vector<int>& hits, size_t threads)
{
    for (size_t i = 0; i < hits.size(); i++)
    {
        ASSERT_EQ(hits[i], 1) << "item " << i << " of " << hits.size() << ", " << threads
                              << " threads";
    }
}
}  // namespace

TEST(ParallelExecutor, ChunksCoverTheRangeOnceAndRethrow)
{
    for (size_t threads : {1, 2, 3})
    {
        ParallelExecutor ex(threads);
        EXPECT_EQ(ex.threads(), threads);
        for (size_t n : {0, 1, 7, 1000, 4099})
        {
            std::vector<int> hits(n, 0);
            ex.forEachChunk(
                n,
                [&](size_t b, size_t e)
                {
                    for (size_t i = b; i < e; i++)
                    {
                        hits[i]++;
                    }
                },
                1);
            expectEachOnce(hits, threads);
        }
        EXPECT_THROW(
            ex.forEachChunk(
                100, [](size_t b, size_t) { throw std::runtime_error(std::to_string(b)); }, 1),
            std::runtime_error);
        // Still usable after an exception.
        size_t total = 0;
        ex.forEachChunk(1, [&](size_t b, size_t e) { total += e - b; });
        EXPECT_EQ(total, 1u);
    }
}

TEST(ParallelExecutor, RangesCoverTheRangeOnceOnNamedThreadsAndRethrow)
{
    for (size_t threads : {1, 2, 3})
    {
        ParallelExecutor ex(threads);
        for (size_t n : {0, 1, 7, 1000, 10007})
        {
            std::vector<int> hits(n, 0);
            std::vector<size_t> itemsOf(threads, 0);  // one slot per thread: no race
            ex.forEachRange(
                n,
                [&](size_t b, size_t e, size_t thread)
                {
                    ASSERT_LT(thread, threads);
                    ASSERT_LE(b, e);
                    itemsOf[thread] += e - b;
                    for (size_t i = b; i < e; i++)
                    {
                        hits[i]++;
                    }
                },
                16);
            expectEachOnce(hits, threads);
            size_t total = 0;
            for (const size_t k : itemsOf)
            {
                total += k;
            }
            EXPECT_EQ(total, n);
        }
        EXPECT_THROW(
            ex.forEachRange(
                1000, [](size_t b, size_t, size_t) { throw std::runtime_error(std::to_string(b)); },
                16),
            std::runtime_error);
        // Back-to-back calls (the workers may still be in the previous one): every item once.
        for (int call = 0; call < 200; call++)
        {
            std::vector<int> hits(5000, 0);
            ex.forEachRange(hits.size(),
                            [&](size_t b, size_t e, size_t)
                            {
                                for (size_t i = b; i < e; i++)
                                {
                                    hits[i]++;
                                }
                            });
            for (const int h : hits)
            {
                ASSERT_EQ(h, 1) << "call " << call;
            }
        }
    }
}

TEST(ParallelExecutor, BlockSumsDoNotDependOnThreads)
{
    std::vector<double> v(10007);
    for (size_t i = 0; i < v.size(); i++)
    {
        v[i] = std::sin(static_cast<double>(i)) * 1e3 + 1e-7 * static_cast<double>(i);
    }
    auto sum = [&](ParallelExecutor& ex)
    {
        return ex.reduceBlocks(v.size(),
                               [&](size_t b, size_t e)
                               {
                                   double s = 0;
                                   for (size_t i = b; i < e; i++)
                                   {
                                       s += v[i];
                                   }
                                   return s;
                               });
    };
    ParallelExecutor one(1), two(2), three(3);
    const double s1 = sum(one);
    EXPECT_EQ(s1, sum(two));
    EXPECT_EQ(s1, sum(three));
}

TEST(ParallelExecutor, CallsMadeWhileAnotherRunsRunAloneWithTheSameResults)
{
    // A work function that calls the executor again (each of its items sums a block through
    // reduceBlocks), and two threads calling it at once: every call covers its items once
    // and sums the same bits as a one-thread executor, and none waits for the other.
    ParallelExecutor one(1);
    const size_t n = 5000;
    const auto blockSum = [](size_t b, size_t e)
    {
        double s = 0;
        for (size_t i = b; i < e; i++)
        {
            s += std::sin(static_cast<double>(i));
        }
        return s;
    };
    const double expected = one.reduceBlocks(n, blockSum);
    for (size_t threads : {2, 3})
    {
        ParallelExecutor ex(threads);
        std::vector<double> inner(64, 0.0);
        std::vector<int> hits(inner.size(), 0);
        ex.forEachRange(
            inner.size(),
            [&](size_t b, size_t e, size_t)
            {
                for (size_t i = b; i < e; i++)
                {
                    hits[i]++;
                    inner[i] = ex.reduceBlocks(n, blockSum);
                }
            },
            1);
        expectEachOnce(hits, threads);
        for (double v : inner)
        {
            ASSERT_EQ(v, expected);
        }

        std::atomic<int> wrong{0};
        auto caller = [&]
        {
            for (int rep = 0; rep < 200; rep++)
            {
                std::vector<int> h(1000, 0);
                ex.forEachRange(
                    h.size(),
                    [&](size_t b, size_t e, size_t)
                    {
                        for (size_t i = b; i < e; i++)
                        {
                            h[i]++;
                        }
                    },
                    16);
                for (int x : h)
                {
                    wrong += x != 1;
                }
                wrong += ex.reduceBlocks(n, blockSum) != expected;
            }
        };
        std::thread other(caller);
        caller();
        other.join();
        EXPECT_EQ(wrong.load(), 0) << threads << " threads";
    }
}
