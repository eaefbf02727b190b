/* semloc — stopping a long job cleanly (Ctrl-C): the request its loops check. */
#include <semloc/io/Interrupt.h>

#include <atomic>

namespace semloc
{
namespace
{
std::atomic<bool> g_interrupt{false};
/** Incremented by clearInterrupt(). */
std::atomic<unsigned> g_generation{0};
static_assert(std::atomic<bool>::is_always_lock_free, "used from a signal handler");
static_assert(std::atomic<unsigned>::is_always_lock_free, "used from a signal handler");
}  // namespace

Interrupted::Interrupted() : std::runtime_error("interrupted; no output written") {}

void requestInterrupt() noexcept
{
    g_interrupt.store(true);
}

bool interruptRequested() noexcept
{
    return g_interrupt.load();
}

void clearInterrupt() noexcept
{
    g_interrupt.store(false);
    g_generation.fetch_add(1);
}

unsigned interruptGeneration() noexcept
{
    return g_generation.load();
}

}  // namespace semloc
