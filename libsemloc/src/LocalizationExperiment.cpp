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
#include <semloc/ConfigHelpers.h>
#include <semloc/Interrupt.h>
#include <semloc/LocalizationExperiment.h>
#include <semloc/RawlogReader.h>
#include <semloc/StagedDirectory.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include "ExactConfigWrite.h"
#include "TextFiles.h"

namespace semloc
{
namespace
{
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

std::string trim(std::string s)
{
    s.erase(0, s.find_first_not_of(" \t"));
    s.erase(s.find_last_not_of(" \t\r") + 1);
    return s;
}

/** Shortest round-trip text of a number; "" for NaN (steps.csv's empty cells). */
std::string num(double v)
{
    if (std::isnan(v))
    {
        return "";
    }
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof(buf), v);
    return std::string(buf, r.ptr);
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

double median(std::vector<double> v)
{
    if (v.empty())
    {
        return 0;
    }
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
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
    y << "# semloc-localize run summary (DESIGN.md); null: not available\n"
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

bool finitePose(const mrpt::poses::CPose2D& p)
{
    return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.phi());
}

/** What the filter needs of a rawlog, checked before the run: finite odometry somewhere
 *  (or allow_no_odometry), and at least one observation a map can score. */
void checkRawlog(const mrpt::obs::CRawlog& rawlog, const std::string& path,
                 const mrpt::maps::CMetricMap& maps, const Localizer::TOptions& filter)
{
    bool odometry = false;
    size_t observations = 0, usable = 0;
    std::set<std::string> classes;
    auto badOdometry = [&](size_t i)
    {
        THROW_EXCEPTION(
            mrpt::format("rawlog '%s': entry %zu: the odometry is not finite", path.c_str(), i));
    };
    auto observe = [&](const mrpt::obs::CObservation& obs)
    {
        observations++;
        classes.insert(obs.GetRuntimeClass()->className);
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
                    if (!m2->poseChange || !finitePose(m2->poseChange->getMeanVal()))
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
                    observe(*obs);
                }
            }
        }
        else if (const auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(obj))
        {
            odometry = true;
            if (!finitePose(odo->odometry))
            {
                badOdometry(i);
            }
        }
        else if (const auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj))
        {
            observe(*obs);
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
            "[MetricMap]",
            path.c_str(), observations, observations ? list.c_str() : "none"));
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
    rawlog_file = resolveNextToIni(c, trim(c.read_string(s, "rawlog_file", rawlog_file)));
    map_file = resolveNextToIni(c, trim(c.read_string(s, "map_file", map_file)));
    ground_truth_path_file = resolveNextToIni(
        c, trim(c.read_string(s, "ground_truth_path_file", ground_truth_path_file)));
    logOutput_dir = trim(c.read_string(s, "logOutput_dir", logOutput_dir));
    readInt(c, s, "rawlog_offset", rawlog_offset, 0, std::numeric_limits<int>::max());
    variant = trim(c.read_string(s, "variant", variant));
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
            e.m_carried.emplace_back(k, trim(ini->read_string(kSection, k, "")));
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
        (void)GroundTruth::FromFile(o.ground_truth_path_file);  // a bad file fails here
    }
    // Absolute inputs: the effective configuration runs again from any directory.
    for (std::string* f : {&o.rawlog_file, &o.map_file, &o.ground_truth_path_file})
    {
        if (!f->empty())
        {
            *f = std::filesystem::absolute(*f).lexically_normal().string();
        }
    }

    e.m_maps = LocalizationMap::FromConfig(*ini, o.map_file);
    if (o.variant.empty())
    {
        o.variant = e.m_maps.variant();
    }

    auto read = RawlogReader::Read(o.rawlog_file);
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
    }
    if (read.rawlog.empty())
    {
        THROW_EXCEPTION("rawlog '" + o.rawlog_file + "' holds no entries");
    }
    checkRawlog(read.rawlog, o.rawlog_file, *e.m_maps.map, o.filter);
    e.m_rawlog = std::move(read.rawlog);
    return e;
}

LocalizationExperiment::TResult LocalizationExperiment::run(
    const std::function<void(size_t, size_t)>& progress) const
{
    const auto wall0 = std::chrono::steady_clock::now();
    const auto& o = m_options;

    const mrpt::obs::CRawlog& rawlog = m_rawlog;
    const GroundTruth gt = o.ground_truth_path_file.empty()
                               ? GroundTruth()
                               : GroundTruth::FromFile(o.ground_truth_path_file);

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
        std::vector<double> dt;
        for (size_t k = 1; k < res.records.size(); k++)
        {
            const double d = res.records[k].t - res.records[k - 1].t;
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
        for (auto& r : res.records)
        {
            if (const auto* row = gt.nearest(r.t, tol))
            {
                r.gt = row->pose();
            }
        }
    }

    res.metrics = RunMetrics::compute(res.records, o.convergence);
    res.likelihood = loc.likelihoodStats();
    res.recovery = loc.recoveryStats();

    StagedDirectory out(o.logOutput_dir);
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
