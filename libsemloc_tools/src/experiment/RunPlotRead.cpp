/* semloc — RunPlot: a semloc-localize output directory read back (steps.csv, summary.yaml,
 * config.ini, particles.csv). */
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/io/vector_loadsave.h>
#include <mrpt/system/filesystem.h>
#include <semloc/experiment/RunPlot.h>
#include <semloc/io/InputFile.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "dataset/CsvTable.h"
#include "io/Text.h"

namespace semloc
{
namespace
{
namespace fs = std::filesystem;

const std::vector<std::string> kStepsColumns = {
    "step",    "t",      "gt_x",    "gt_y",   "gt_phi", "est_x",       "est_y",
    "est_phi", "err_xy", "err_phi", "var_xy", "ess",    "n_particles", "update_us"};
/** The columns a run written before the pose covariance did not have. */
const std::vector<std::string> kStepsCovarianceColumns = {
    "nees", "var_x", "var_y", "var_phi", "cov_xy", "cov_xphi", "cov_yphi"};

/** The pose covariance of row `i` (0 where the file lacks it). */
void readCovariance(const detail::CsvTable& csv, size_t i, TStepRecord& r)
{
    r.var_x = csv.numberOr(i, "var_x", 0);
    r.var_y = csv.numberOr(i, "var_y", 0);
    r.var_phi = csv.numberOr(i, "var_phi", 0);
    r.cov_xy = csv.numberOr(i, "cov_xy", 0);
    r.cov_xphi = csv.numberOr(i, "cov_xphi", 0);
    r.cov_yphi = csv.numberOr(i, "cov_yphi", 0);
}

std::vector<TStepRecord> readSteps(const std::string& path)
{
    const auto csv = detail::CsvTable::FromFile(path, kStepsColumns, kStepsCovarianceColumns);
    if (csv.rows() == 0)
    {
        THROW_EXCEPTION("'" + path + "' holds no step");
    }
    std::vector<TStepRecord> records(csv.rows());
    for (size_t i = 0; i < csv.rows(); i++)
    {
        auto& r = records[i];
        const double step = csv.number(i, "step");
        if (step != static_cast<double>(i))
        {
            csv.fail(i, "step",
                     "steps must count 0, 1, 2, ... (expected " + std::to_string(i) + ")");
        }
        r.step = i;
        r.t = csv.numberOr(i, "t", NAN);
        if (!csv.empty(i, "gt_x"))
        {
            r.gt = mrpt::math::TPose2D(csv.number(i, "gt_x"), csv.number(i, "gt_y"),
                                       csv.number(i, "gt_phi"));
        }
        r.est = mrpt::math::TPose2D(csv.number(i, "est_x"), csv.number(i, "est_y"),
                                    csv.number(i, "est_phi"));
        r.var_xy = csv.number(i, "var_xy");
        readCovariance(csv, i, r);
        r.ess = csv.numberOr(i, "ess", 1);
        const double n = csv.number(i, "n_particles");
        if (n < 1 || n != std::floor(n))
        {
            csv.fail(i, "n_particles", "not a positive whole number");
        }
        r.n_particles = static_cast<size_t>(n);
        r.update_us = csv.numberOr(i, "update_us", 0);
    }
    return records;
}

/** The value of `key: value` in summary.yaml (one line, top level); "" if absent. */
std::string summaryValue(const std::string& text, const std::string& key)
{
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line))
    {
        if (line.rfind(key + ":", 0) == 0)
        {
            std::string v = detail::trim(line.substr(key.size() + 1));
            if (v.size() >= 2 && v.front() == '"' && v.back() == '"')
            {
                v = v.substr(1, v.size() - 2);
            }
            return v;
        }
    }
    return {};
}

/** A row of particles.csv: step, t, x, y, phi, weight. */
struct ParticleRow
{
    size_t step = 0;
    double x = 0, y = 0;
};

/** Parses line `lineNo` of particles.csv; throws naming the file, line and column. */
ParticleRow parseParticleRow(const std::string& line, const std::string& path, size_t lineNo)
{
    static const char* names[] = {"step", "t", "x", "y", "phi", "weight"};
    double v[6];
    const char* p = line.c_str();
    for (int k = 0; k < 6; k++)
    {
        char* end = nullptr;
        errno = 0;
        v[k] = std::strtod(p, &end);
        const bool emptyTime = (k == 1 && end == p && (*p == ',' || *p == '\0'));
        if ((end == p && !emptyTime) || (k < 5 && *end != ',') || (k == 5 && *end != '\0') ||
            (!emptyTime && !std::isfinite(v[k])))
        {
            THROW_EXCEPTION(path + ":" + std::to_string(lineNo) + ": column " +
                            std::to_string(k + 1) + " '" + names[k] +
                            "': not a finite number (or not 6 columns)");
        }
        p = (k < 5) ? end + 1 : end;
    }
    if (v[0] < 0 || v[0] != std::floor(v[0]) || v[0] > 1e15)
    {
        THROW_EXCEPTION(path + ":" + std::to_string(lineNo) + ": column 1 'step': not a step");
    }
    return {static_cast<size_t>(v[0]), v[2], v[3]};
}

/** particles.csv: each saved step's cloud, thinned evenly to kMaxCloudPoints particles. */
std::vector<RunPlot::Cloud> readClouds(const std::string& path,
                                       const std::vector<TStepRecord>& records)
{
    (void)checkInputFile(path, "particles file", InputKind::Text);
    std::ifstream in(path, std::ios::binary);
    if (!in)
    {
        THROW_EXCEPTION("cannot read '" + path + "': " + std::strerror(errno));
    }
    std::string line;
    if (!std::getline(in, line) || detail::trim(line) != "step,t,x,y,phi,weight")
    {
        THROW_EXCEPTION(path + ":1: the header must be 'step,t,x,y,phi,weight'");
    }
    std::vector<RunPlot::Cloud> clouds;
    size_t lineNo = 1, index = 0, stride = 1;
    while (std::getline(in, line))
    {
        lineNo++;
        const auto row = parseParticleRow(line, path, lineNo);
        if (clouds.empty() || row.step != clouds.back().step)
        {
            if (row.step >= records.size() || (!clouds.empty() && row.step < clouds.back().step))
            {
                THROW_EXCEPTION(path + ":" + std::to_string(lineNo) + ": step " +
                                std::to_string(row.step) +
                                (row.step >= records.size() ? " is not in steps.csv"
                                                            : " comes after a later step"));
            }
            clouds.push_back({row.step, {}});
            index = 0;
            const size_t n = records[row.step].n_particles;
            stride = (n + RunPlot::kMaxCloudPoints - 1) / RunPlot::kMaxCloudPoints;
        }
        if (index++ % stride == 0)
        {
            clouds.back().points.emplace_back(row.x, row.y);
        }
    }
    return clouds;
}

/** A world without objects spanning the records and clouds, with a margin. */
World boundsWorld(const std::vector<TStepRecord>& records,
                  const std::vector<RunPlot::Cloud>& clouds)
{
    double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
    const auto add = [&](double x, double y)
    {
        x0 = std::min(x0, x);
        x1 = std::max(x1, x);
        y0 = std::min(y0, y);
        y1 = std::max(y1, y);
    };
    for (const auto& r : records)
    {
        add(r.est.x, r.est.y);
        if (r.gt)
        {
            add(r.gt->x, r.gt->y);
        }
    }
    for (const auto& c : clouds)
    {
        for (const auto& p : c.points)
        {
            add(p.x, p.y);
        }
    }
    const double m = std::max({1.0, 0.05 * (x1 - x0), 0.05 * (y1 - y0)});
    World w;
    w.name = "run";
    w.bounds = {x0 - m, x1 + m, y0 - m, y1 + m};
    return w;
}

bool isWorldFile(const std::string& path)
{
    const auto ext = fs::path(path).extension().string();
    return ext == ".yaml" || ext == ".yml";
}
}  // namespace

RunPlot RunPlot::FromDirectory(const std::string& runDir, const std::string& worldFile)
{
    RunPlot p;
    p.m_runDir = runDir;
    const auto file = [&](const std::string& name) { return (fs::path(runDir) / name).string(); };
    if (!fs::is_directory(runDir))
    {
        THROW_EXCEPTION("'" + runDir + "' is not a directory (a semloc-localize output)");
    }
    for (const char* name : {"steps.csv", "summary.yaml", "config.ini"})
    {
        if (!mrpt::system::fileExists(file(name)))
        {
            THROW_EXCEPTION("'" + runDir + "' has no " + name + " (not a semloc-localize output)");
        }
    }
    p.m_records = readSteps(file("steps.csv"));
    const std::string summary =
        readInputFile(file("summary.yaml"), "run summary", InputKind::Config);
    p.m_variant = summaryValue(summary, "variant");
    const std::string conv = summaryValue(summary, "convergence_step");
    if (!conv.empty() && conv != "null")
    {
        char* end = nullptr;
        const long s = std::strtol(conv.c_str(), &end, 10);
        if (*end != '\0' || s < 0 || static_cast<size_t>(s) >= p.m_records.size())
        {
            THROW_EXCEPTION("'" + file("summary.yaml") + "': convergence_step '" + conv +
                            "' is not a step of steps.csv");
        }
        p.m_convergenceStep = static_cast<size_t>(s);
    }
    if (mrpt::system::fileExists(file("particles.csv")))
    {
        p.m_clouds = readClouds(file("particles.csv"), p.m_records);
    }
    p.m_worldFile = worldFile;
    if (p.m_worldFile.empty())
    {
        const mrpt::config::CConfigFileMemory ini(
            readInputFile(file("config.ini"), "config file", InputKind::Config));
        const std::string map =
            detail::trimValue(ini.read_string("LocalizationExperiment", "map_file", "", false));
        if (isWorldFile(map))
        {
            p.m_worldFile = map;
        }
    }
    p.m_world = p.m_worldFile.empty() ? boundsWorld(p.m_records, p.m_clouds)
                                      : World::FromFile(p.m_worldFile);
    return p;
}

std::vector<std::string> RunPlot::inputFiles() const
{
    std::vector<std::string> in;
    for (const char* name : {"steps.csv", "summary.yaml", "config.ini", "particles.csv"})
    {
        in.push_back((fs::path(m_runDir) / name).string());
    }
    if (!m_worldFile.empty())
    {
        in.push_back(m_worldFile);
    }
    return in;
}

}  // namespace semloc
