/* semloc — Benchmark's shards: runs first..last written apart (a cluster's task, a machine of
 * GNU parallel) and merged into the outputs of the whole benchmark. */
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <semloc/experiment/Benchmark.h>
#include <semloc/io/StagedDirectory.h>

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "experiment/BenchmarkRunPool.h"
#include "experiment/Digest.h"
#include "io/Text.h"
#include "io/TextFiles.h"

namespace semloc
{
namespace
{
constexpr const char* kShardFile = "shard.txt";
constexpr const char* kShardHeader =
    "# semloc-benchmark shard: runs first..last of the benchmark below (semloc-benchmark "
    "--merge)";

/** The largest shard.txt read [bytes]. */
constexpr uint64_t kMaxShardFileBytes = 1 << 16;

/** A shard's runs as "'dir' (runs a..b)". */
std::string shardText(const Benchmark::TShard& s)
{
    return mrpt::format("'%s' (runs %d..%d)", s.dir.c_str(), s.first, s.last);
}

std::string runsText(int a, int b)
{
    return a == b ? mrpt::format("run %d", a) : mrpt::format("runs %d..%d", a, b);
}

/** The last line of the text file `path` (its last 4 KiB read); empty if none. */
std::string lastLine(const std::string& path)
{
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    std::ifstream f(path, std::ios::binary);
    if (ec || !f)
    {
        return {};
    }
    constexpr uintmax_t kTail = 4096;
    f.seekg(static_cast<std::streamoff>(size > kTail ? size - kTail : 0));
    std::ostringstream tail;
    tail << f.rdbuf();
    std::string t = tail.str();
    while (!t.empty() && t.back() == '\n')
    {
        t.pop_back();
    }
    return t.substr(t.rfind('\n') == std::string::npos ? 0 : t.rfind('\n') + 1);
}

/** Field `k` (from 0) of a CSV line; empty if it has fewer. */
std::string csvField(const std::string& line, size_t k)
{
    std::istringstream in(line);
    std::string f;
    for (size_t i = 0; i <= k; i++)
    {
        if (!std::getline(in, f, ','))
        {
            return {};
        }
    }
    return f;
}

/** The runs of a whole benchmark's outputs: the run of results.csv's last row, or the `runs`
 *  of scenarios.csv's first row; empty if unreadable. */
std::string runsOf(const std::filesystem::path& csv, bool scenarios)
{
    if (!scenarios)
    {
        return csvField(lastLine(csv.string()), 0);
    }
    std::ifstream f(csv);
    std::string header, row;
    std::getline(f, header);
    std::getline(f, row);
    return csvField(row, 2);
}

/** What the directory `dir` holds of semloc-benchmark's outputs: "a shard of runs A:B" (its
 *  shard.txt; `shard` set), "a whole benchmark of N runs" (results.csv, or scenarios.csv with
 *  scenarios), or nothing (empty). */
std::string heldOutputs(const std::string& dir, bool& shard)
{
    namespace fs = std::filesystem;
    std::error_code ec;
    shard = fs::exists(fs::path(dir) / kShardFile, ec);
    if (shard)
    {
        try
        {
            const auto s = Benchmark::ReadShard(dir);
            return mrpt::format("a shard of runs %d:%d of a benchmark of %d (%s)", s.first, s.last,
                                s.runs, kShardFile);
        }
        catch (const std::exception&)
        {
            return std::string("a shard (") + kShardFile + ")";
        }
    }
    for (const char* file : {"results.csv", "scenarios.csv"})
    {
        const fs::path p = fs::path(dir) / file;
        if (fs::is_regular_file(p, ec))
        {
            const std::string n = runsOf(p, file == std::string("scenarios.csv"));
            return "a whole benchmark" + (n.empty() ? std::string() : " of " + n + " runs") + " (" +
                   file + ")";
        }
    }
    return {};
}

/** Throws unless the shards are of one benchmark and cover its runs once each. */
void checkShards(std::vector<Benchmark::TShard>& shards)
{
    const auto& a = shards.front();
    for (const auto& s : shards)
    {
        if (s.digest != a.digest || s.runs != a.runs)
        {
            THROW_EXCEPTION(mrpt::format(
                "the shards %s and %s are not of one benchmark: digest %s of %d runs of '%s' "
                "against digest %s of %d runs of '%s'",
                shardText(a).c_str(), shardText(s).c_str(), a.digest.c_str(), a.runs, a.ini.c_str(),
                s.digest.c_str(), s.runs, s.ini.c_str()));
        }
    }
    std::stable_sort(shards.begin(), shards.end(),
                     [](const auto& x, const auto& y) { return x.first < y.first; });
    int next = 1;  // the first run not covered yet
    for (size_t i = 0; i < shards.size(); i++)
    {
        const auto& s = shards[i];
        if (i > 0 && s.first <= shards[i - 1].last)
        {
            const auto& p = shards[i - 1];
            THROW_EXCEPTION("the shards " + shardText(p) + " and " + shardText(s) + " overlap on " +
                            runsText(s.first, std::min(p.last, s.last)));
        }
        if (s.first > next)
        {
            THROW_EXCEPTION(runsText(next, s.first - 1) + " of the " + std::to_string(a.runs) +
                            " are in no shard (the next shard is " + shardText(s) + ")");
        }
        next = s.last + 1;
    }
    if (next <= a.runs)
    {
        THROW_EXCEPTION(runsText(next, a.runs) + " of the " + std::to_string(a.runs) +
                        " are in no shard (the last shard is " + shardText(shards.back()) + ")");
    }
}
}  // namespace

std::string Benchmark::effectiveConfiguration() const
{
    TOptions o = m_options;
    o.output_dir.clear();  // where the outputs go, not what they are
    mrpt::config::CConfigFileMemory c;
    o.saveToConfigFile(c, "Benchmark");
    m_simulation.saveToConfigFile(c);
    if (!m_scenario.name.empty())
    {
        m_scenario.saveToConfigFile(c, "Scenario");
    }
    std::string text = c.getContent();
    for (const auto& [section, key, value] : m_variantOverlay)
    {
        text.append("overlay [").append(section).append("] ").append(key).append(" = ");
        text.append(value).append("\n");
    }
    for (const auto& v : m_variants)
    {
        text += "variant " + v.name() + " (" + v.iniPath + ")\n" + runConfiguration(v);
    }
    for (const auto& sc : m_scenarios)
    {
        text += "scenario " + sc.m_scenario.name + "\n" + sc.effectiveConfiguration();
    }
    return text;
}

std::string Benchmark::digest() const
{
    uint64_t h = detail::fnv1a("semloc-benchmark inputs\n");
    const std::string config = effectiveConfiguration();
    h = detail::fnv1a(std::to_string(config.size()) + "\n", h);
    h = detail::fnv1a(config, h);
    for (const auto& f : inputFiles())
    {
        if (!f.empty() && std::filesystem::is_regular_file(f))
        {
            std::ifstream in(f, std::ios::binary);
            std::ostringstream bytes;
            bytes << in.rdbuf();
            if (!in)
            {
                THROW_EXCEPTION("cannot read '" + f + "'");
            }
            h = detail::fnv1a(std::to_string(bytes.str().size()) + "\n", h);
            h = detail::fnv1a(bytes.str(), h);
        }
    }
    return detail::digestText(h);
}

std::string Benchmark::shardRunsDir(const std::string& shardDir) const
{
    return shardDir + "/" + (m_scenario.name.empty() ? std::string() : m_scenario.name + "/") +
           "runs";
}

void Benchmark::checkShardRuns(int first, int last) const
{
    if (!(first >= 1 && first <= last && last <= m_options.runs))
    {
        THROW_EXCEPTION(
            mrpt::format("--runs %d:%d: a shard is runs A:B with 1 <= A <= B <= %d "
                         "(the benchmark's runs)",
                         first, last, m_options.runs));
    }
}

void Benchmark::checkOutputKind(int first, int last) const
{
    const std::string& dir = m_options.output_dir;
    bool shard = false;
    const std::string held = heldOutputs(dir, shard);
    if (held.empty() || shard == (first > 0))
    {
        return;  // nothing of ours, or of the same kind: replaced as any previous output
    }
    const std::string what =
        first > 0 ? mrpt::format("a shard (--runs %d:%d) does not", first, last)
                  : std::string("the outputs of a whole benchmark (a run or a merge) do not");
    THROW_EXCEPTION("output directory '" + dir + "' holds " + held + ": " + what +
                    " replace it; remove it first (rm -r '" + dir +
                    "') or name another directory (-o)");
}

Benchmark::TShard Benchmark::runShard(int first, int last,
                                      const std::function<void(size_t, size_t)>& progress) const
{
    const int runs = m_options.runs;
    checkShardRuns(first, last);
    checkOutputKind(first, last);
    const std::string inputs = digest();
    StagedDirectory out(m_options.output_dir, inputFiles());
    const std::vector<const Benchmark*> parts = [&]
    {
        std::vector<const Benchmark*> p;
        for (const auto& sc : m_scenarios)
        {
            p.push_back(&sc);
        }
        return p.empty() ? std::vector<const Benchmark*>{this} : p;
    }();
    const size_t n = static_cast<size_t>(last - first) + 1, total = n * parts.size();
    for (size_t i = 0; i < parts.size(); i++)
    {
        const Benchmark& b = *parts[i];
        const detail::RunFiles files(b.shardRunsDir(out.path("")), inputs);
        std::filesystem::create_directories(files.dir());
        detail::runInChildProcesses(
            files, first, last, effectiveJobs(), b.m_scenario.name,
            [&b](int run) { return b.runOne(run); },
            [&](size_t done, size_t)
            {
                if (progress && (done > 0 || i == 0))
                {
                    progress(i * n + done, total);
                }
            });
    }
    TShard s{out.target(), std::filesystem::absolute(m_iniPath).lexically_normal().string(),
             inputs,       runs,
             first,        last};
    detail::writeFile(out.path(kShardFile),
                      std::string(kShardHeader) + "\nbenchmark " + s.ini + "\ndigest " + s.digest +
                          "\nruns " + std::to_string(runs) + "\nfirst " + std::to_string(first) +
                          "\nlast " + std::to_string(last) + "\n");
    out.commit();
    return s;
}

Benchmark::TShard Benchmark::ReadShard(const std::string& dir)
{
    const std::string path = dir + "/" + kShardFile;
    if (!std::filesystem::is_regular_file(path))
    {
        THROW_EXCEPTION("'" + dir + "' is not a shard of semloc-benchmark (no " + kShardFile +
                        "; semloc-benchmark INI --runs A:B -o DIR writes one)");
    }
    std::istringstream in(detail::readBoundedFile(path, kMaxShardFileBytes, "shard file"));
    TShard s;
    s.dir = dir;
    std::string line;
    for (int no = 1; std::getline(in, line); no++)
    {
        if (line.empty() || line[0] == '#')
        {
            continue;
        }
        const auto sp = line.find(' ');
        const std::string key = line.substr(0, sp),
                          value = sp == std::string::npos ? "" : line.substr(sp + 1);
        const auto bad = [&](const std::string& why)
        { THROW_EXCEPTION(mrpt::format("%s line %d: %s", path.c_str(), no, why.c_str())); };
        if (key == "benchmark")
        {
            s.ini = value;
        }
        else if (key == "digest")
        {
            s.digest = value;
        }
        else if (key == "runs" || key == "first" || key == "last")
        {
            int v = 0;
            const auto r = std::from_chars(value.data(), value.data() + value.size(), v);
            if (r.ec != std::errc() || r.ptr != value.data() + value.size() || v < 1)
            {
                bad("'" + value + "' is not a run number");
            }
            (key == "runs" ? s.runs : key == "first" ? s.first : s.last) = v;
        }
        else
        {
            bad("unknown key '" + key + "'");
        }
    }
    if (s.ini.empty() || s.digest.size() != 16 || s.runs < 1 || s.first < 1 || s.last < s.first ||
        s.last > s.runs)
    {
        THROW_EXCEPTION(path + ": incomplete (benchmark, digest, runs, first <= last <= runs)");
    }
    return s;
}

Benchmark::TResult Benchmark::Merge(const std::vector<std::string>& shardDirs,
                                    const std::string& outputDir,
                                    const std::function<void(size_t, size_t)>& progress)
{
    ASSERTMSG_(!shardDirs.empty(), "--merge: no shard");
    std::vector<TShard> shards;
    shards.reserve(shardDirs.size());
    for (const auto& d : shardDirs)
    {
        shards.push_back(ReadShard(d));
    }
    checkShards(shards);
    const auto& a = shards.front();
    const Benchmark b = FromConfigFile(a.ini, outputDir, a.runs);
    b.checkOutputKind();
    if (b.digest() != a.digest)
    {
        THROW_EXCEPTION("the benchmark '" + a.ini + "' is not the one of the shards any more: " +
                        "its files (or semloc's defaults) changed since they were run (digest " +
                        b.digest() + ", the shards' " + a.digest + ")");
    }
    return b.m_scenarios.empty() ? b.runAll(progress, shards) : b.runScenarios(progress, shards);
}

}  // namespace semloc
