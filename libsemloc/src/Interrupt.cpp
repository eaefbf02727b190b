/* semloc — stopping a long job cleanly (Ctrl-C). */
#include <semloc/Interrupt.h>
#include <signal.h>

#include <atomic>

namespace semloc
{
namespace
{
std::atomic<bool> g_interrupt{false};
static_assert(std::atomic<bool>::is_always_lock_free, "used from a signal handler");

void onSignal(int sig)
{
    requestInterrupt();
    ::signal(sig, SIG_DFL);  // a second Ctrl-C ends the process at once
}
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
}

void installInterruptHandlers()
{
    struct sigaction sa = {};
    sa.sa_handler = onSignal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = 0;  // no SA_RESTART: waitpid() returns EINTR
    ::sigaction(SIGINT, &sa, nullptr);
    ::sigaction(SIGTERM, &sa, nullptr);
}

}  // namespace semloc
