/* semloc — Benchmark's run files: a run's results as its child process hands them back (or a
 * shard keeps them), sealed by the digests of the benchmark and of their own content. */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <semloc/io/InputFile.h>

#include <cerrno>
#include <charconv>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string_view>

#include "experiment/BenchmarkRunPool.h"
#include "experiment/Digest.h"

namespace semloc::detail
{
namespace
{
namespace fs = std::filesystem;

constexpr const char* kHeaderStart = "# semloc-benchmark run file";
const std::string kHeader = std::string(kHeaderStart) +
                            ": the results of one run (docs/design.md), sealed by its last line";
/** Fields of a "V" line and of a step line. */
constexpr size_t kResultFields = 13, kStepFields = 19;

std::string exact(double v)
{
    return mrpt::format("%.17g", v);
}

/** A run file's lines, each with its number (from 1) for the errors that name it. */
class Lines
{
public:
    Lines(const std::string& text, std::string path) : m_path(std::move(path))
    {
        size_t b = 0;
        for (size_t e; (e = text.find('\n', b)) != std::string::npos; b = e + 1)
        {
            m_lines.emplace_back(text, b, e - b);
            m_offsets.push_back(b);
        }
        m_cut = b < text.size();
    }
    size_t size() const { return m_lines.size(); }
    const std::string& operator[](size_t i) const { return m_lines[i]; }
    /** Where line `i` starts in the text. */
    size_t offset(size_t i) const { return m_offsets[i]; }
    /** True when the text does not end with a line end. */
    bool cut() const { return m_cut; }
    /** Throws "run file 'PATH' line N: why" (N = i + 1). */
    [[noreturn]] void fail(size_t i, const std::string& why) const
    {
        THROW_EXCEPTION(
            mrpt::format("run file '%s' line %zu: %s", m_path.c_str(), i + 1, why.c_str()));
    }

private:
    std::string m_path;
    std::vector<std::string> m_lines;
    std::vector<size_t> m_offsets;
    bool m_cut = false;
};

/** Line `i`'s fields (split at single blanks); throws unless there are `count` of them. */
std::vector<std::string_view> fields(const Lines& lines, size_t i, size_t count, const char* what)
{
    std::vector<std::string_view> out;
    const std::string_view line = lines[i];
    for (size_t b = 0;;)
    {
        const size_t e = line.find(' ', b);
        out.push_back(line.substr(b, e == std::string_view::npos ? e : e - b));
        if (e == std::string_view::npos)
        {
            break;
        }
        b = e + 1;
    }
    if (out.size() != count)
    {
        lines.fail(i, mrpt::format("%zu fields where %s has %zu", out.size(), what, count));
    }
    return out;
}

/** Field `f` of line `i` as a T (a number, its whole text). */
template <typename T>
T number(const Lines& lines, size_t i, std::string_view f)
{
    T v{};
    const auto r = std::from_chars(f.data(), f.data() + f.size(), v);
    if (f.empty() || r.ec != std::errc() || r.ptr != f.data() + f.size())
    {
        lines.fail(i, "'" + std::string(f) + "' is not a number");
    }
    return v;
}

/** A step of line `i`. */
TStepRecord stepOf(const Lines& lines, size_t i)
{
    const auto f = fields(lines, i, kStepFields, "a step line");
    size_t k = 0;
    const auto real = [&] { return number<double>(lines, i, f[k++]); };
    TStepRecord s;
    s.step = number<size_t>(lines, i, f[k++]);
    s.t = real();
    const int hasGt = number<int>(lines, i, f[k++]);
    const double gx = real(), gy = real(), gphi = real();
    if (hasGt != 0)
    {
        s.gt = mrpt::math::TPose2D(gx, gy, gphi);
    }
    s.est.x = real();
    s.est.y = real();
    s.est.phi = real();
    s.var_xy = real();
    s.ess = real();
    s.n_particles = number<size_t>(lines, i, f[k++]);
    s.update_us = real();
    s.var_x = real();
    s.var_y = real();
    s.var_phi = real();
    s.cov_xy = real();
    s.cov_xphi = real();
    s.cov_yphi = real();
    return s;
}

/** The result whose "V" line is line `i` (its steps and bound follow, before line `end`); `i`
 *  is left on the line after its bound. */
Benchmark::TRunResult resultOf(const Lines& lines, size_t& i, size_t end, int run)
{
    const auto v = fields(lines, i, kResultFields, "a result's V line");
    if (v[0] != "V")
    {
        lines.fail(i, "'" + std::string(v[0]) + "' where a result starts with V");
    }
    Benchmark::TRunResult r;
    r.run = run;
    r.seed = static_cast<uint32_t>(run);
    r.variant = std::string(v[1]);
    r.control = std::string(v[2]);
    r.particles = number<size_t>(lines, i, v[3]);
    r.threads = number<size_t>(lines, i, v[4]);
    r.wallTime_s = number<double>(lines, i, v[5]);
    r.reinitializations = number<size_t>(lines, i, v[6]);
    r.decisions = number<size_t>(lines, i, v[7]);
    r.decisionWall_s = number<double>(lines, i, v[8]);
    r.decisionFilterSteps = number<double>(lines, i, v[9]);
    r.maxDecisionFilterSteps = number<double>(lines, i, v[10]);
    r.stuckDecisions = number<size_t>(lines, i, v[11]);
    const auto n = number<size_t>(lines, i, v[12]);
    if (n >= end - i - 1)  // n step lines and the B line before `end`
    {
        lines.fail(i, mrpt::format("%zu steps, but the file ends before them", n));
    }
    for (size_t k = 0; k < n; k++)
    {
        r.records.push_back(stepOf(lines, ++i));
    }
    const std::string_view b = lines[++i];
    if (b.rfind("B ", 0) != 0)
    {
        lines.fail(i, "not the detector's bound 'B <n> ...' that follows the steps");
    }
    const auto count = number<size_t>(lines, i, b.substr(2, b.find(' ', 2) - 2));
    const auto f = fields(lines, i, count < b.size() ? 2 + 2 * count : 0, "this B line");
    for (size_t k = 0; k < count; k++)
    {
        r.detectorBound.push_back(
            {number<double>(lines, i, f[2 + 2 * k]), number<double>(lines, i, f[3 + 2 * k])});
    }
    i++;
    return r;
}

/** Throws unless the lines are a run file whose last line is its content's digest. */
void checkSeal(const Lines& lines, const std::string& text, const std::string& path)
{
    if (lines.size() == 0 || lines[0] != kHeader)
    {
        THROW_EXCEPTION("run file '" + path + "' line 1: not a run file of semloc-benchmark (no '" +
                        kHeaderStart + "' header)");
    }
    const size_t last = lines.size() - 1;
    if (lines.cut() || last < 3 || lines[last].rfind("content ", 0) != 0)
    {
        lines.fail(lines.cut() ? last + 1 : last,
                   "not the content digest the file ends with ('content <16 hex digits>'): the "
                   "file was cut short or changed");
    }
    const std::string written = lines[last].substr(8);
    const std::string actual = digestText(fnv1a(text.substr(0, lines.offset(last))));
    if (written != actual)
    {
        lines.fail(last, "the file was changed after its run wrote it (content digest " + written +
                             ", but the lines above it hash to " + actual + ")");
    }
}
}  // namespace

std::string runFileText(const std::vector<Benchmark::TRunResult>& rs, int run,
                        const std::string& inputs)
{
    std::ostringstream o;
    o << kHeader << "\nrun " << run << "\ninputs " << inputs << '\n';
    for (const auto& r : rs)
    {
        o << "V " << r.variant << ' ' << r.control << ' ' << r.particles << ' ' << r.threads << ' '
          << exact(r.wallTime_s) << ' ' << r.reinitializations << ' ' << r.decisions << ' '
          << exact(r.decisionWall_s) << ' ' << exact(r.decisionFilterSteps) << ' '
          << exact(r.maxDecisionFilterSteps) << ' ' << r.stuckDecisions << ' ' << r.records.size()
          << '\n';
        for (const auto& s : r.records)
        {
            o << s.step << ' ' << exact(s.t) << ' ' << (s.gt ? 1 : 0) << ' '
              << exact(s.gt ? s.gt->x : 0) << ' ' << exact(s.gt ? s.gt->y : 0) << ' '
              << exact(s.gt ? s.gt->phi : 0) << ' ' << exact(s.est.x) << ' ' << exact(s.est.y)
              << ' ' << exact(s.est.phi) << ' ' << exact(s.var_xy) << ' ' << exact(s.ess) << ' '
              << s.n_particles << ' ' << exact(s.update_us) << ' ' << exact(s.var_x) << ' '
              << exact(s.var_y) << ' ' << exact(s.var_phi) << ' ' << exact(s.cov_xy) << ' '
              << exact(s.cov_xphi) << ' ' << exact(s.cov_yphi) << '\n';
        }
        o << "B " << r.detectorBound.size();
        for (const auto& b : r.detectorBound)
        {
            o << ' ' << exact(b.rms_xy_m) << ' ' << exact(b.mean_err_xy_m);
        }
        o << '\n';
    }
    const std::string body = o.str();
    return body + "content " + digestText(fnv1a(body)) + "\n";
}

std::vector<Benchmark::TRunResult> readRunFile(const std::string& path, int run,
                                               const std::string& inputs, const RunSeries& series)
{
    const std::string text = readBoundedFile(path, kMaxRunFileBytes, "run file");
    const Lines lines(text, path);
    checkSeal(lines, text, path);
    if (lines[1] != "run " + std::to_string(run))
    {
        lines.fail(1, "the results of another run than run " + std::to_string(run) + " ('" +
                          lines[1] + "': a run file copied or renamed?)");
    }
    if (lines[2] != "inputs " + inputs)
    {
        lines.fail(2, "the results of another benchmark ('" + lines[2] + "', this one's inputs " +
                          "digest is " + inputs + "): a run file of another benchmark's shard?");
    }
    std::vector<Benchmark::TRunResult> rs;
    const size_t end = lines.size() - 1;  // the content line
    for (size_t i = 3; i < end;)
    {
        const size_t at = i;
        rs.push_back(resultOf(lines, i, end, run));
        const auto& r = rs.back();
        if (rs.size() > series.size() || series[rs.size() - 1].first != r.variant ||
            series[rs.size() - 1].second != r.control)
        {
            lines.fail(at, "the results of variant '" + r.variant + "' (control " + r.control +
                               "), not a series of this benchmark's runs in its place");
        }
    }
    if (rs.size() != series.size())
    {
        lines.fail(end, mrpt::format("the file ends after %zu of the %zu results of a run",
                                     rs.size(), series.size()));
    }
    return rs;
}

std::string readBoundedFile(const std::string& path, uint64_t maxBytes, const std::string& what)
{
    std::error_code ec;
    if (fs::is_symlink(fs::symlink_status(path, ec)))
    {
        THROW_EXCEPTION(what + " '" + path +
                        "' is a symbolic link, not a regular file: semloc-benchmark reads only "
                        "the files it wrote");
    }
    return readInputFile(path, what, maxBytes);
}

}  // namespace semloc::detail
