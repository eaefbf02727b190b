/* semloc — the particles' memory against what the process may use. */
#include "experiment/ParticleMemory.h"

#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstdint>
#include <limits>
#include <utility>

namespace semloc::detail
{
namespace
{
/** The memory this process may use [bytes] and what limits it: the physical memory, or less
 *  under `ulimit -v` (RLIMIT_AS) or `ulimit -m` (RLIMIT_RSS). */
std::pair<uint64_t, std::string> availableMemory()
{
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
    std::pair<uint64_t, std::string> m = {std::numeric_limits<uint64_t>::max(), ""};
    if (pages > 0 && page > 0)
    {
        m = {static_cast<uint64_t>(pages) * static_cast<uint64_t>(page), "physical memory"};
    }
    for (const auto& [resource, name] : {std::pair<int, const char*>{RLIMIT_AS, "ulimit -v"},
                                         std::pair<int, const char*>{RLIMIT_RSS, "ulimit -m"}})
    {
        rlimit r{};
        if (::getrlimit(resource, &r) == 0 && r.rlim_cur != RLIM_INFINITY &&
            static_cast<uint64_t>(r.rlim_cur) < m.first)
        {
            m = {static_cast<uint64_t>(r.rlim_cur), name};
        }
    }
    return m;
}

std::string memoryText(uint64_t bytes)
{
    const double b = static_cast<double>(bytes);
    return b < 1e9 ? mrpt::format("%.0f MB", b / 1e6) : mrpt::format("%.1f GB", b / 1e9);
}
}  // namespace

std::string checkParticleMemory(const Localizer::TOptions& f, bool fromCommandLine,
                                const std::string& section)
{
    const uint64_t need = f.particleMemoryBytes();
    const auto [have, limit] = availableMemory();
    if (need <= have / 2)
    {
        return "";
    }
    std::string what =
        (fromCommandLine ? "--particles " : "ini [" + section + "] particles_count ") +
        std::to_string(f.particles_count);
    std::string each = mrpt::format("%llu bytes each",
                                    static_cast<unsigned long long>(Localizer::kBytesPerParticle));
    if (f.pf.adaptiveSampleSize)
    {
        what += " and [KLD_options] KLD_maxSampleSize " + std::to_string(f.kld.KLD_maxSampleSize) +
                " (adaptiveSampleSize = 1)";
        each += mrpt::format(", %llu per KLD particle",
                             static_cast<unsigned long long>(Localizer::kBytesPerKLDParticle));
    }
    const std::string needs =
        what + ": the particles need about " + memoryText(need) + " of memory (" + each + "), ";
    if (need <= have)
    {
        return needs + "more than half of the " + memoryText(have) + " available (" + limit + ")";
    }
    THROW_EXCEPTION(needs + "more than the " + memoryText(have) + " available (" + limit + ")");
}

}  // namespace semloc::detail
