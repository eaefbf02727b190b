/* semloc — linked into every fuzz target: MRPT's exceptions capture and symbolize a call stack
 * of up to 50 frames when they are constructed (mrpt::callStackBackTrace: backtrace_symbols,
 * dladdr and demangling of each frame), which a target never prints: it catches the exception
 * as the rejection of a bad input. Defined in the executable, this empty call stack takes the
 * place of MRPT's for every caller (the dynamic linker looks the executable's symbols up
 * first), so a rejection costs its message only. The messages are unchanged, and a crash or an
 * uncaught exception is still reported with the sanitizer's own stack trace. */
#include <mrpt/core/backtrace.h>

namespace mrpt
{
void callStackBackTrace(TCallStackBackTrace& out_bt, const unsigned int /*framesToSkip*/,
                        const unsigned int /*framesToCapture*/) noexcept
{
    out_bt.backtrace_levels.clear();
}
}  // namespace mrpt
