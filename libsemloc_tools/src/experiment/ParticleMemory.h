/* semloc — the memory the particles of a localization run need against what the process
 * may use (private). */
#pragma once

#include <semloc/filter/Localizer.h>

#include <string>

namespace semloc::detail
{
/** Refuses a particle count whose memory (Localizer::TOptions::particleMemoryBytes) exceeds
 *  what the process may use (the physical memory, `ulimit -v`, `ulimit -m`);
 *  `fromCommandLine`: particles_count came from -n, else from ini [`section`]. A warning
 *  (else "") when it takes more than half of it. */
std::string checkParticleMemory(const Localizer::TOptions& f, bool fromCommandLine,
                                const std::string& section);

}  // namespace semloc::detail
