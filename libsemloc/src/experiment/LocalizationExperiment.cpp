/* semloc — LocalizationExperiment: pf-localization's ini strictly, the run, the outputs. */
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/Clock.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/system/filesystem.h>
#include <semloc/experiment/LocalizationExperiment.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/io/Interrupt.h>
#include <semloc/io/OutputPaths.h>
#include <semloc/io/RawlogReader.h>
#include <semloc/io/StagedDirectory.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include <sys/resource.h>
#include <unistd.h>

#include "experiment/Statistics.h"
#include "io/ExactConfigWrite.h"
#include "io/Text.h"
#include "io/TextFiles.h"
#include "world/Geometry2D.h"

namespace semloc
{
namespace
{
using detail::finitePose;
using detail::median;
using detail::trimValue;
using detail::writeFile;
using detail::writeText;
const std::string kSection = "LocalizationExperiment";

/** Sections semloc-localize reads; [MetricMap_...] are checked by LocalizationMap. */
const std::vector<std::string> kSections = {kSection, "PF_options", "KLD_options",
                                            "DummyOdometryParams", "MetricMap"};

/** pf-localization keys about its 3D display, repetitions or 3D particles: accepted,
 *  carried over to the effective configuration, not used. */
const std::vector<std::string> kCarriedKeys = {"3DSceneFrequency",
                                               "3DSceneFollowRobot",
                                               "experimentTestConvergenceAtStep",
                                               "SAVE_STATS_ONLY",
                                               "DO_RELIABILITY_ESTIMATE",
                                               "DO_SCAN_LIKELIHOOD_DEBUG",
                                               "SHOW_PROGRESS_3D_REAL_TIME",
                                               "SHOW_PROGRESS_3D_REAL_TIME_DELAY_MS",
                                               "STATS_CONF_INTERVAL",
                                               "initial_odo_x",
                                               "initial_odo_y",
                                               "initial_odo_phi",
                                               "init_PDF_min_z",
                                               "init_PDF_max_z",
                                               "init_PDF_min_pitch_deg",
                                               "init_PDF_max_pitch_deg",
                                               "init_PDF_min_roll_deg",
                                               "init_PDF_max_roll_deg"};

/** Our own [LocalizationExperiment] keys besides the filter's. */
const std::vector<std::string> kRunKeys = {"rawlog_file",
                                           "map_file",
                                           "ground_truth_path_file",
                                           "logOutput_dir",
                                           "rawlog_offset",
                                           "variant",
                                           "convergence_max_err_xy_m",
                                           "convergence_max_var_xy_m2",
                                           "convergence_min_steps",
                                           "use_3D_poses",
                                           "experimentRepetitions"};

/** Shortest round-trip text of a number; "" for NaN (steps.csv's empty cells). */
std::string num(double v)
{
    return std::isnan(v) ? std::string() : detail::shortestText(v);
}

/** A YAML value: `null` for NaN. */
std::string yamlNum(double v)
{
    return std::isnan(v) ? "null" : num(v);
}

std::string yamlString(const std::string& s)
{
    std::string q = "\"";
    for (const char ch : s)
    {
        if (ch == '"' || ch == '\\')
        {
            q += '\\';
        }
        q += ch;
    }
    return q + "\"";
}

std::string stepsCsv(const std::vector<TStepRecord>& records)
{
    std::ostringstream o;
    o << "step,t,gt_x,gt_y,gt_phi,est_x,est_y,est_phi,err_xy,err_phi,var_xy,ess,n_particles,"
         "update_us\n";
    for (const auto& r : records)
    {
        o << r.step << ',' << (std::isnan(r.t) ? "" : mrpt::format("%.6f", r.t)) << ','
          << (r.gt ? num(r.gt->x) : "") << ',' << (r.gt ? num(r.gt->y) : "") << ','
          << (r.gt ? num(r.gt->phi) : "") << ',' << num(r.est.x) << ',' << num(r.est.y) << ','
          << num(r.est.phi) << ',' << num(r.errXY()) << ',' << num(r.errPhi()) << ','
          << num(r.var_xy) << ',' << num(r.ess) << ',' << r.n_particles << ','
          << mrpt::format("%.1f", r.update_us) << '\n';
    }
    return o.str();
}

std::string summaryYaml(const LocalizationExperiment::TResult& res,
                        const LocalizationExperiment::TOptions& o)
{
    const auto& m = res.metrics;
    const auto& c = o.convergence;
    std::ostringstream y;
    y << "# semloc-localize run summary (docs/design.md); null: not available\n"
      << "variant: " << yamlString(res.variant) << "\n"
      << "particles: " << o.filter.particles_count << "\n"
      << "seed: " << o.filter.seed << "\n"
      << "threads: " << res.threads << "\n"
      << "steps: " << m.steps << "\n"
      << "steps_with_ground_truth: " << m.steps_with_ground_truth << "\n"
      << "converged: " << (m.converged ? "true" : "false") << "\n"
      << "convergence_step: " << (m.converged ? std::to_string(m.convergence_step) : "null") << "\n"
      << "convergence_time_s: " << yamlNum(m.convergence_time_s) << "\n"
      << "mean_err_after_conv_m: " << yamlNum(m.mean_err_after_conv_m) << "\n"
      << "rmse_m: " << yamlNum(m.rmse_m) << "\n"
      << "final_err_m: " << yamlNum(m.final_err_m) << "\n"
      << "total_update_s: " << yamlNum(m.total_update_s) << "\n"
      << "mean_update_us_per_particle: " << yamlNum(m.mean_update_us_per_particle) << "\n"
      << "final_particles: " << (res.records.empty() ? 0 : res.records.back().n_particles) << "\n"
      << "convergence_criterion: {max_err_xy_m: " << num(c.max_err_xy_m)
      << ", max_var_xy_m2: " << num(c.max_var_xy_m2) << ", min_steps: " << c.min_steps << "}\n"
      << "# observations and detections the maps could not use, non-finite likelihoods\n"
      << "observations_used: " << res.likelihood.observations_used << "\n"
      << "observations_skipped: " << res.likelihood.observations_skipped << "\n"
      << "detections_invalid: " << res.likelihood.detections_invalid << "\n"
      << "detections_unknown: " << res.likelihood.detections_unknown << "\n"
      << "nonfinite_likelihoods: " << res.likelihood.nonfinite_likelihoods << "\n"
      << "# every weight zero: particles re-initialized over the free space\n"
      << "reinitializations: " << res.recovery.reinitializations << "\n"
      << "reinitialized_from_detections: " << res.recovery.reinitialized_from_detections << "\n"
      << "# augmented MCL (recovery_alpha_slow / recovery_alpha_fast)\n"
      << "injection_steps: " << res.recovery.injection_steps << "\n"
      << "injected_particles: " << res.recovery.injected_particles << "\n"
      << "injected_from_detections: " << res.recovery.injected_from_detections << "\n"
      << "# free_space_prior: particle updates found outside the free space (weight 0)\n"
      << "outside_free_space: " << res.recovery.outside_free_space << "\n"
      << "# range-scan beams with a NaN, infinite, negative or beyond-max range (skipped)\n"
      << "beams_invalid: " << res.likelihood.beams_invalid << "\n"
      << "# observations that cannot be scored (a non-finite sensor pose, aperture or range\n"
      << "# limit, a scan without beams...), left out whole\n"
      << "observations_invalid: " << res.likelihood.observations_invalid << "\n"
      << "rawlog_format: " << yamlString(res.rawlogFormat) << "\n"
      << "# --allow-truncated: index of the first unreadable entry (null: rawlog complete)\n"
      << "rawlog_truncated_at_entry: "
      << (res.rawlogTruncatedAtEntry ? std::to_string(*res.rawlogTruncatedAtEntry) : "null") << "\n"
      << "rawlog_file: " << yamlString(o.rawlog_file) << "\n"
      << "map_file: " << yamlString(o.map_file) << "\n"
      << "ground_truth_path_file: " << yamlString(o.ground_truth_path_file) << "\n"
      << "wall_time_s: " << yamlNum(res.wallTime_s) << "\n";
    return y.str();
}

bool finiteMatrix(const mrpt::math::CMatrixDouble33& m)
{
    for (int r = 0; r < 3; r++)
    {
        for (int c = 0; c < 3; c++)
        {
            if (!std::isfinite(m(r, c)))
            {
                return false;
            }
        }
    }
    return true;
}

/** A time as steps.csv writes it. */
std::string timeText(double t)
{
    return mrpt::format("%.6f", t);
}

/** The steps run() makes of a rawlog, grouped as run() groups them: the entry each starts at
 *  and its time (its first observation's; NaN without a timestamp). */
struct StepTime
{
    size_t entry = 0;
    double t = 0;
};

double timeOf(const mrpt::obs::CObservation& obs)
{
    return obs.timestamp != INVALID_TIMESTAMP ? mrpt::Clock::toDouble(obs.timestamp)
                                              : std::numeric_limits<double>::quiet_NaN();
}

std::vector<StepTime> stepTimes(const mrpt::obs::CRawlog& rawlog)
{
    std::vector<StepTime> steps;
    std::optional<StepTime> group;  // observations-only: one timestamp, one step
    mrpt::Clock::time_point groupStamp;
    auto flush = [&]
    {
        if (group)
        {
            steps.push_back(*group);
            group.reset();
        }
    };
    for (size_t i = 0; i < rawlog.size(); i++)
    {
        switch (rawlog.getType(i))
        {
            case mrpt::obs::CRawlog::etActionCollection:
                flush();
                break;
            case mrpt::obs::CRawlog::etSensoryFrame:
            {
                flush();
                const auto sf = rawlog.getAsObservations(i);
                steps.push_back({i, sf->size() > 0 ? timeOf(*sf->getObservationByIndex(0))
                                                   : std::numeric_limits<double>::quiet_NaN()});
                break;
            }
            case mrpt::obs::CRawlog::etObservation:
            {
                const auto obs = rawlog.getAsObservation(i);
                if (obs && IS_CLASS(*obs, mrpt::obs::CObservationOdometry))
                {
                    flush();
                }
                else if (obs)
                {
                    if (group && groupStamp != obs->timestamp)
                    {
                        flush();
                    }
                    if (!group)
                    {
                        group = StepTime{i, timeOf(*obs)};
                        groupStamp = obs->timestamp;
                    }
                }
                break;
            }
            default:
                break;
        }
    }
    flush();
    return steps;
}

/** The ground-truth row of each step time (null: none): the nearest row within half the
 *  median step period (the rows' median period if the steps have none). */
std::vector<const GroundTruthRow*> matchGroundTruth(const GroundTruth& gt,
                                                    const std::vector<double>& times)
{
    std::vector<const GroundTruthRow*> rows(times.size(), nullptr);
    if (gt.empty())
    {
        return rows;
    }
    std::vector<double> dt;
    for (size_t k = 1; k < times.size(); k++)
    {
        const double d = times[k] - times[k - 1];
        if (std::isfinite(d) && d > 0)
        {
            dt.push_back(d);
        }
    }
    double tol = 0.5 * (dt.empty() ? gt.medianPeriod() : median(dt));
    if (!(tol > 0))
    {
        tol = 1e-6;
    }
    for (size_t k = 0; k < times.size(); k++)
    {
        rows[k] = gt.nearest(times[k], tol);
    }
    return rows;
}

/** With ground truth matched by time: the times of the steps run (from rawlog_offset on)
 *  must increase, and at least one must match a row. */
void checkGroundTruthTimes(const std::vector<StepTime>& steps, const GroundTruth& gt,
                           const std::string& gtPath, const std::string& rawlogPath)
{
    const StepTime* prev = nullptr;
    std::vector<double> times;
    double tMin = std::numeric_limits<double>::infinity(), tMax = -tMin;
    for (const auto& s : steps)
    {
        times.push_back(s.t);
        if (std::isnan(s.t))
        {
            continue;  // no timestamp: no ground truth for that step
        }
        if (prev && !(s.t > prev->t))
        {
            THROW_EXCEPTION(mrpt::format(
                "rawlog '%s': entry %zu: time %s is not after %s, the time of entry %zu (the "
                "step before): ground truth ('%s') is matched by time, so step times must "
                "increase",
                rawlogPath.c_str(), s.entry, timeText(s.t).c_str(), timeText(prev->t).c_str(),
                prev->entry, gtPath.c_str()));
        }
        prev = &s;
        tMin = std::min(tMin, s.t);
        tMax = std::max(tMax, s.t);
    }
    const auto rows = matchGroundTruth(gt, times);
    if (std::none_of(rows.begin(), rows.end(), [](const GroundTruthRow* r) { return r; }))
    {
        THROW_EXCEPTION(mrpt::format(
            "ground truth '%s' (%zu rows, times %s to %s) matches no step of rawlog '%s' (%s): "
            "are both in seconds of the same clock?",
            gtPath.c_str(), gt.size(), timeText(gt.rows().front().t).c_str(),
            timeText(gt.rows().back().t).c_str(), rawlogPath.c_str(),
            prev ? mrpt::format("%zu steps, times %s to %s", steps.size(), timeText(tMin).c_str(),
                                timeText(tMax).c_str())
                       .c_str()
                 : "no step has a timestamp"));
    }
}

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

/** Refuses a particle count whose memory (Localizer::TOptions::particleMemoryBytes) exceeds
 *  what the process may use; `fromCommandLine`: particles_count came from -n. A warning
 *  (else "") when it takes more than half of it. */
std::string checkParticleMemory(const Localizer::TOptions& f, bool fromCommandLine)
{
    const uint64_t need = f.particleMemoryBytes();
    const auto [have, limit] = availableMemory();
    if (need <= have / 2)
    {
        return "";
    }
    std::string what =
        (fromCommandLine ? "--particles " : "ini [" + kSection + "] particles_count ") +
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

/** What the filter needs of a rawlog, checked before the run: finite odometry somewhere
 *  (or allow_no_odometry), and at least one observation a map can score. */
void checkRawlog(const mrpt::obs::CRawlog& rawlog, const std::string& path,
                 const mrpt::maps::CMetricMap& maps, const Localizer::TOptions& filter)
{
    bool odometry = false;
    size_t observations = 0, usable = 0, invalid = 0;
    std::string firstInvalid;
    std::set<std::string> classes;
    auto badOdometry = [&](size_t i)
    {
        THROW_EXCEPTION(
            mrpt::format("rawlog '%s': entry %zu: the odometry is not finite", path.c_str(), i));
    };
    auto observe = [&](const mrpt::obs::CObservation& obs, size_t entry)
    {
        observations++;
        classes.insert(obs.GetRuntimeClass()->className);
        if (const std::string why = Localizer::invalidObservation(obs, maps); !why.empty())
        {
            if (invalid++ == 0)
            {
                firstInvalid = mrpt::format("entry %zu, a %s: %s", entry,
                                            obs.GetRuntimeClass()->className, why.c_str());
            }
            return;
        }
        usable += maps.canComputeObservationLikelihood(obs) ? 1 : 0;
    };
    for (size_t i = 0; i < rawlog.size(); i++)
    {
        const auto obj = rawlog.getAsGeneric(i);
        if (const auto acts = std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(obj))
        {
            for (size_t k = 0; k < acts->size(); k++)
            {
                const auto a = acts->get(k);
                if (const auto m2 = std::dynamic_pointer_cast<mrpt::obs::CActionRobotMovement2D>(a))
                {
                    odometry = true;
                    if (!m2->poseChange || !finitePose(m2->poseChange->getMeanVal().asTPose()) ||
                        !finiteMatrix(m2->poseChange->getCovariance()))
                    {
                        badOdometry(i);
                    }
                }
                odometry = odometry || IS_CLASS(*a, mrpt::obs::CActionRobotMovement3D);
            }
        }
        else if (const auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj))
        {
            for (const auto& obs : *sf)
            {
                if (obs)
                {
                    observe(*obs, i);
                }
            }
        }
        else if (const auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(obj))
        {
            odometry = true;
            if (!finitePose(odo->odometry.asTPose()))
            {
                badOdometry(i);
            }
        }
        else if (const auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj))
        {
            observe(*obs, i);
        }
    }
    if (!odometry && !filter.allow_no_odometry)
    {
        THROW_EXCEPTION("rawlog '" + path +
                        "' holds no odometry (no CActionRobotMovement2D/3D, no "
                        "CObservationOdometry); set [DummyOdometryParams] allow_no_odometry = "
                        "true to localize it with zero motion plus minStdXY/minStdPHI noise");
    }
    if (usable == 0)
    {
        std::string list;
        for (const auto& c : classes)
        {
            list += (list.empty() ? "" : ", ") + c;
        }
        THROW_EXCEPTION(mrpt::format(
            "rawlog '%s': none of its %zu observations (%s) can be used by the maps in "
            "[MetricMap]%s",
            path.c_str(), observations, observations ? list.c_str() : "none",
            invalid ? mrpt::format("; %zu cannot be scored at all (the first: %s)", invalid,
                                   firstInvalid.c_str())
                          .c_str()
                    : ""));
    }
}

void requireFile(const std::string& key, const std::string& path)
{
    if (!path.empty() && !mrpt::system::fileExists(path))
    {
        THROW_EXCEPTION("ini [" + kSection + "] " + key + ": file '" + path + "' does not exist");
    }
}
}  // namespace

// ------------------------------------------------------------------ options

void LocalizationExperiment::TOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                                          const std::string& s)
{
    using namespace semloc::config;
    {
        auto known = Localizer::TOptions::experimentKeys();
        known.insert(known.end(), kRunKeys.begin(), kRunKeys.end());
        known.insert(known.end(), kCarriedKeys.begin(), kCarriedKeys.end());
        rejectUnknownKeys(c, s, known);
    }
    filter.loadFromConfigFile(c, s);
    rawlog_file = resolveNextToIni(c, trimValue(c.read_string(s, "rawlog_file", rawlog_file)));
    map_file = resolveNextToIni(c, trimValue(c.read_string(s, "map_file", map_file)));
    ground_truth_path_file = resolveNextToIni(
        c, trimValue(c.read_string(s, "ground_truth_path_file", ground_truth_path_file)));
    logOutput_dir = trimValue(c.read_string(s, "logOutput_dir", logOutput_dir));
    readInt(c, s, "rawlog_offset", rawlog_offset, 0, std::numeric_limits<int>::max());
    variant = trimValue(c.read_string(s, "variant", variant));
    readDouble(c, s, "convergence_max_err_xy_m", convergence.max_err_xy_m, 0, 1e9);
    readDouble(c, s, "convergence_max_var_xy_m2", convergence.max_var_xy_m2, 0, 1e9);
    readInt(c, s, "convergence_min_steps", convergence.min_steps, 1,
            std::numeric_limits<int>::max());
    bool use3D = false;
    readBool(c, s, "use_3D_poses", use3D);
    if (use3D)
    {
        THROW_EXCEPTION("ini [" + s + "] use_3D_poses: only 2D localization (false) is supported");
    }
    int reps = 1;
    readInt(c, s, "experimentRepetitions", reps, 0, std::numeric_limits<int>::max());
    if (reps != 1)
    {
        THROW_EXCEPTION("ini [" + s +
                        "] experimentRepetitions: one run per invocation (1); semloc-benchmark "
                        "repeats runs over seeds");
    }
}

void LocalizationExperiment::TOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                                        const std::string& s) const
{
    writeText(c, s, "rawlog_file", rawlog_file, "the dataset");
    writeText(c, s, "map_file", map_file, "world YAML, .simplemap or .gridmap");
    writeText(c, s, "ground_truth_path_file", ground_truth_path_file, "t x y phi per line");
    writeText(c, s, "logOutput_dir", logOutput_dir, "outputs");
    writeText(c, s, "rawlog_offset", std::to_string(rawlog_offset), "steps skipped");
    writeText(c, s, "variant", variant, "name in summary.yaml");
    detail::writeExact(c, s, "convergence_max_err_xy_m", convergence.max_err_xy_m, "[m]");
    detail::writeExact(c, s, "convergence_max_var_xy_m2", convergence.max_var_xy_m2, "[m^2]");
    writeText(c, s, "convergence_min_steps", std::to_string(convergence.min_steps), "steps");
    writeText(c, s, "use_3D_poses", "false", "2D only");
    writeText(c, s, "experimentRepetitions", "1", "one run");
    filter.saveToConfigFile(c, s);
}

// ------------------------------------------------------------------ experiment

LocalizationExperiment LocalizationExperiment::FromConfigFile(const std::string& iniPath,
                                                              const TOverrides& ov)
{
    config::checkIniFile(iniPath);
    LocalizationExperiment e;
    e.m_iniPath = iniPath;
    auto ini = std::make_shared<mrpt::config::CConfigFile>(iniPath);
    e.m_ini = ini;

    std::vector<std::string> sections;
    ini->getAllSections(sections);
    for (const auto& s : sections)
    {
        if (!s.empty() && std::find(kSections.begin(), kSections.end(), s) == kSections.end() &&
            s.rfind("MetricMap_", 0) != 0)
        {
            std::string list;
            for (const auto& k : kSections)
            {
                list.append(list.empty() ? "[" : ", [").append(k).append("]");
            }
            THROW_EXCEPTION(
                mrpt::format("ini [%s]: unknown section (semloc-localize reads %s and "
                             "[MetricMap_<map>_<NN>_...])",
                             s.c_str(), list.c_str()));
        }
    }
    if (!ini->sectionExists(kSection))
    {
        THROW_EXCEPTION("ini '" + iniPath + "': no [" + kSection + "] section");
    }

    auto& o = e.m_options;
    o.loadFromConfigFile(*ini, kSection);
    for (const auto& k : kCarriedKeys)
    {
        if (ini->keyExists(kSection, k))
        {
            e.m_carried.emplace_back(k, trimValue(ini->read_string(kSection, k, "")));
        }
    }
    if (!ov.rawlog_file.empty())
    {
        o.rawlog_file = ov.rawlog_file;
    }
    if (!ov.logOutput_dir.empty())
    {
        o.logOutput_dir = ov.logOutput_dir;
    }
    if (ov.threads)
    {
        ASSERTMSG_(
            *ov.threads >= 0 && *ov.threads <= Localizer::TOptions::kMaxThreads,
            "threads must be in [0, " + std::to_string(Localizer::TOptions::kMaxThreads) + "]");
        o.filter.threads = *ov.threads;
    }
    if (ov.particles_count)
    {
        ASSERTMSG_(
            *ov.particles_count >= 1 && *ov.particles_count <= Localizer::TOptions::kMaxParticles,
            "the number of particles must be in [1, " +
                std::to_string(Localizer::TOptions::kMaxParticles) + "]");
        o.filter.particles_count = *ov.particles_count;
    }
    if (ov.seed)
    {
        ASSERTMSG_(*ov.seed <= static_cast<uint32_t>(std::numeric_limits<int>::max()),
                   "seed must be in [0, 2147483647]");
        o.filter.seed = *ov.seed;
    }
    if (auto w = checkParticleMemory(o.filter, ov.particles_count.has_value()); !w.empty())
    {
        e.m_warnings.push_back(std::move(w));
    }
    if (const size_t cores = std::thread::hardware_concurrency();
        cores > 0 && o.filter.effectiveThreads() > cores)
    {
        e.m_warnings.push_back(mrpt::format(
            "%s %d exceeds the %zu hardware threads of this machine: the run is slower, not "
            "faster",
            ov.threads ? "--threads" : "[PF_options] threads", o.filter.threads, cores));
    }

    if (o.rawlog_file.empty())
    {
        THROW_EXCEPTION("ini [" + kSection +
                        "] rawlog_file: missing (or give the rawlog on the "
                        "command line)");
    }
    if (o.logOutput_dir.empty())
    {
        THROW_EXCEPTION("ini [" + kSection + "] logOutput_dir: missing");
    }
    requireFile("rawlog_file", o.rawlog_file);
    if (o.ground_truth_path_file.empty() &&
        mrpt::system::fileExists(Simulator::groundTruthPath(o.rawlog_file)))
    {
        o.ground_truth_path_file = Simulator::groundTruthPath(o.rawlog_file);  // semloc-simulate's
    }
    requireFile("map_file", o.map_file);
    requireFile("ground_truth_path_file", o.ground_truth_path_file);
    if (!o.ground_truth_path_file.empty())
    {
        e.m_groundTruth = GroundTruth::FromFile(o.ground_truth_path_file);  // a bad file fails
    }
    // Absolute inputs: the effective configuration runs again from any directory.
    for (std::string* f : {&o.rawlog_file, &o.map_file, &o.ground_truth_path_file})
    {
        if (!f->empty())
        {
            *f = std::filesystem::absolute(*f).lexically_normal().string();
        }
    }
    // Before any work: the output must not replace anything but a previous output.
    checkOutputDirectory(o.logOutput_dir, e.inputFiles());

    e.m_maps = LocalizationMap::FromConfig(*ini, o.map_file);
    if (o.variant.empty())
    {
        o.variant = e.m_maps.variant();
    }

    auto read = RawlogReader::Read(o.rawlog_file);
    if (read.defect && read.defect->entry == 0)
    {
        THROW_EXCEPTION(read.defectMessage() + ": nothing to localize");  // with or without
    }                                                                     // --allow-truncated
    if (read.defect)
    {
        if (!ov.allow_truncated)
        {
            THROW_EXCEPTION(read.defectMessage() +
                            " (semloc-localize --allow-truncated uses the intact entries)");
        }
        e.m_truncatedAt = read.defect->entry;
        e.m_rawlogWarning =
            read.defectMessage() + mrpt::format(
                                       ": --allow-truncated: localizing with the %zu intact "
                                       "entries",
                                       read.defect->entry);
        e.m_warnings.push_back(e.m_rawlogWarning);
    }
    if (read.rawlog.empty())
    {
        THROW_EXCEPTION("rawlog '" + o.rawlog_file + "' holds no entries");
    }
    checkRawlog(read.rawlog, o.rawlog_file, *e.m_maps.map, o.filter);
    auto steps = stepTimes(read.rawlog);
    if (o.rawlog_offset > 0 && static_cast<size_t>(o.rawlog_offset) >= steps.size())
    {
        THROW_EXCEPTION(mrpt::format(
            "ini [%s] rawlog_offset: %d skips every step: rawlog '%s' holds %zu step%s (%zu "
            "entries)",
            kSection.c_str(), o.rawlog_offset, o.rawlog_file.c_str(), steps.size(),
            steps.size() == 1 ? "" : "s", read.rawlog.size()));
    }
    if (!e.m_groundTruth.empty())
    {
        steps.erase(steps.begin(), steps.begin() + o.rawlog_offset);
        checkGroundTruthTimes(steps, e.m_groundTruth, o.ground_truth_path_file, o.rawlog_file);
    }
    e.m_rawlog.swap(read.rawlog);
    return e;
}

std::vector<std::string> LocalizationExperiment::inputFiles() const
{
    const auto& o = m_options;
    return {m_iniPath, o.rawlog_file, o.map_file, o.ground_truth_path_file};
}

LocalizationExperiment::TResult LocalizationExperiment::run(
    const std::function<void(size_t, size_t)>& progress) const
{
    const auto wall0 = std::chrono::steady_clock::now();
    const auto& o = m_options;
    // Created first: an output location that cannot be written fails before the run.
    StagedDirectory out(o.logOutput_dir, inputFiles());

    const mrpt::obs::CRawlog& rawlog = m_rawlog;
    const GroundTruth& gt = m_groundTruth;

    Localizer loc(o.filter, m_maps.map, m_maps.world ? &*m_maps.world : nullptr);
    TResult res;
    res.variant = o.variant;
    res.threads = loc.threads();

    auto record = [&](const mrpt::obs::CSensoryFrame& sf)
    {
        TStepRecord r = loc.lastStepRecord(sf);
        r.step = res.records.size();
        res.records.push_back(r);
    };

    // pf-localization's rawlog_offset skips steps (pairs, or observations), not entries. An
    // odometry reading met while skipping is handed over when the first step runs, so that
    // step moves by zero and the next by the increment since it.
    size_t skip = static_cast<size_t>(o.rawlog_offset);
    std::optional<mrpt::obs::CObservationOdometry> heldOdometry;

    // Observations-only rawlogs: consecutive observations with one timestamp are one frame.
    mrpt::obs::CSensoryFrame group;
    auto flush = [&]
    {
        if (group.size() == 0)
        {
            return;
        }
        if (skip > 0)
        {
            skip--;
        }
        else
        {
            if (heldOdometry)
            {
                loc.setOdometry(*heldOdometry);
                heldOdometry.reset();
            }
            loc.step(group);
            record(group);
        }
        group.clear();
    };
    bool sawPairs = false, sawObservations = false;
    mrpt::obs::CActionCollection::Ptr action;
    const size_t n = rawlog.size();
    for (size_t i = 0; i < n; i++)
    {
        if (interruptRequested())
        {
            throw Interrupted();  // Ctrl-C (installInterruptHandlers): no output directory
        }
        switch (rawlog.getType(i))
        {
            case mrpt::obs::CRawlog::etActionCollection:
                flush();
                action = rawlog.getAsAction(i);
                break;
            case mrpt::obs::CRawlog::etSensoryFrame:
            {
                flush();
                const auto sf = rawlog.getAsObservations(i);
                if (skip > 0)
                {
                    skip--;
                }
                else
                {
                    if (action)
                    {
                        loc.step(*action, *sf);
                        sawPairs = true;
                    }
                    else
                    {
                        loc.step(*sf);  // a frame without its action: the odometry since the last
                    }
                    record(*sf);
                }
                action.reset();
                break;
            }
            case mrpt::obs::CRawlog::etObservation:
            {
                sawObservations = true;
                const auto obs = rawlog.getAsObservation(i);
                if (const auto odo =
                        std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(obs))
                {
                    flush();
                    if (skip > 0)
                    {
                        heldOdometry = *odo;
                    }
                    else
                    {
                        heldOdometry.reset();
                        loc.setOdometry(*odo);
                    }
                }
                else if (obs)
                {
                    if (group.size() > 0 &&
                        group.getObservationByIndex(0)->timestamp != obs->timestamp)
                    {
                        flush();
                    }
                    group.insert(obs);
                }
                break;
            }
            default:
                break;
        }
        if (progress)
        {
            progress(i + 1, n);
        }
    }
    flush();
    res.rawlogTruncatedAtEntry = m_truncatedAt;
    res.rawlogFormat = sawPairs && sawObservations ? "mixed"
                       : sawObservations           ? "observations-only"
                                                   : "action/sensory-frame";

    // Ground truth by timestamp: the nearest row within half a step.
    if (!gt.empty())
    {
        std::vector<double> times;
        for (const auto& r : res.records)
        {
            times.push_back(r.t);
        }
        const auto rows = matchGroundTruth(gt, times);
        for (size_t k = 0; k < rows.size(); k++)
        {
            if (rows[k])
            {
                res.records[k].gt = rows[k]->pose();
            }
        }
    }

    res.metrics = RunMetrics::compute(res.records, o.convergence);
    res.likelihood = loc.likelihoodStats();
    res.recovery = loc.recoveryStats();

    res.outputDir = out.target();
    res.wallTime_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    writeFile(out.path("steps.csv"), stepsCsv(res.records));
    writeFile(out.path("summary.yaml"), summaryYaml(res, o));
    {
        mrpt::config::CConfigFileMemory eff;
        o.saveToConfigFile(eff, kSection);
        for (const auto& [k, v] : m_carried)
        {
            writeText(eff, kSection, k, v, "pf-localization only, not used");
        }
        writeFile(out.path("config.ini"),
                  "# semloc-localize: the effective configuration of this run (every key of our "
                  "sections,\n# defaults included). Rerun: semloc-localize config.ini -o "
                  "<another directory>\n" +
                      eff.getContent() + "\n" + m_maps.effectiveConfig(*m_ini));
    }
    if (interruptRequested())
    {
        throw Interrupted();  // the staging directory goes, a previous output stays
    }
    out.commit();
    return res;
}

std::string LocalizationExperiment::TResult::summaryParagraph() const
{
    const auto& m = metrics;
    std::string s = mrpt::format(
        "%s: %zu steps with %zu particles on %zu thread%s, %.2f s of "
        "filter updates (%.3f us per particle).",
        variant.c_str(), m.steps, records.empty() ? size_t(0) : records.front().n_particles,
        threads, threads == 1 ? "" : "s", m.total_update_s, m.mean_update_us_per_particle);
    if (m.steps_with_ground_truth == 0)
    {
        s += " No ground truth: errors unknown.";
    }
    else if (m.converged)
    {
        s += mrpt::format(
            " Converged at step %ld (%.1f s); mean error after convergence %.3f m, RMSE %.3f m, "
            "final error %.3f m.",
            m.convergence_step, m.convergence_time_s, m.mean_err_after_conv_m, m.rmse_m,
            m.final_err_m);
    }
    else
    {
        s += mrpt::format(" Did not converge; RMSE %.3f m, final error %.3f m.", m.rmse_m,
                          m.final_err_m);
    }
    if (recovery.reinitializations > 0)
    {
        s += mrpt::format(" Re-initialized %zu time(s) after every weight vanished.",
                          recovery.reinitializations);
    }
    if (recovery.injected_particles > 0)
    {
        s += mrpt::format(" Recovery injected %zu particles (%zu from detections) in %zu steps.",
                          recovery.injected_particles, recovery.injected_from_detections,
                          recovery.injection_steps);
    }
    if (likelihood.observations_skipped > 0)
    {
        s += mrpt::format(" %zu observations were ignored: no map in [MetricMap] uses them.",
                          likelihood.observations_skipped);
    }
    return s + " Outputs in " + outputDir + ".";
}

}  // namespace semloc
