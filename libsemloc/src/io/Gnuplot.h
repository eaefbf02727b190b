/* semloc — a gnuplot script run in a staged output directory (private). */
#pragma once

#include <semloc/io/StagedDirectory.h>

#include <string>
#include <vector>

namespace semloc::detail
{
/** Runs gnuplot on `script` (a file of `out`) with `out` as working directory; the script
 *  must draw every file of `outputs` there. Throws with gnuplot's output if it is missing,
 *  fails or leaves an output out; semloc::Interrupted at an interrupt request (gnuplot
 *  ended). Its log is removed after a success. */
void runGnuplot(const StagedDirectory& out, const std::string& script,
                const std::vector<std::string>& outputs);
}  // namespace semloc::detail
