/* semloc — LocalizationExperiment's configuration: pf-localization's ini read strictly, the
 * command-line overrides, the inputs read and checked before any output is written. */
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/system/filesystem.h>
#include <semloc/dataset/GroundTruthFile.h>
#include <semloc/experiment/LocalizationExperiment.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/io/OutputPaths.h>
#include <semloc/io/RawlogReader.h>
#include <semloc/models/semantic/CSemanticMap.h>

#include <algorithm>
#include <filesystem>
#include <limits>
#include <optional>
#include <thread>

#include "experiment/LocalizationConfig.h"
#include "experiment/ParticleMemory.h"
#include "experiment/RawlogChecks.h"
#include "experiment/StepTimes.h"
#include "io/ExactConfigWrite.h"
#include "io/Text.h"

namespace semloc
{
namespace
{
using detail::trimValue;
using detail::writeText;
const std::string kSection = "LocalizationExperiment";

/** Sections semloc-localize reads; [MetricMap_...] are checked by LocalizationMap. */
const std::vector<std::string> kSections = {kSection,      "PF_options",
                                            "KLD_options", "DummyOdometryParams",
                                            "Recovery",    MotionModelConfig::kSection,
                                            "MetricMap"};

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
                                           "particles_save_every",
                                           "detections_trace",
                                           "variant",
                                           "convergence_max_err_xy_m",
                                           "convergence_max_var_xy_m2",
                                           "convergence_min_steps",
                                           "use_3D_poses",
                                           "experimentRepetitions"};

/** Throws if `path` (the value of `key`, resolved next to the ini) does not exist; when it is
 *  the ini's own value, the message gives the paths tried (config::missingFileMessage). */
void requireFile(const std::string& key, const std::string& path,
                 const mrpt::config::CConfigFileBase& ini)
{
    if (path.empty() || mrpt::system::fileExists(path))
    {
        return;
    }
    const bool fromIni = trimValue(ini.read_string(kSection, key, "")) == path;
    THROW_EXCEPTION(
        "ini [" + kSection + "] " + key + ": " +
        (fromIni ? config::missingFileMessage(ini, path) : "file '" + path + "' does not exist"));
}

/** Refuses a section semloc-localize does not read, and an ini without [LocalizationExperiment]. */
void checkSections(const mrpt::config::CConfigFileBase& ini, const std::string& iniPath)
{
    std::vector<std::string> sections;
    ini.getAllSections(sections);
    for (const auto& s : sections)
    {
        if (!s.empty())
        {
            detail::checkLocalizeSection(s);
        }
    }
    if (!ini.sectionExists(kSection))
    {
        THROW_EXCEPTION("ini '" + iniPath + "': no [" + kSection + "] section");
    }
}

/** The pf-localization keys (kCarriedKeys) the ini sets, with their values. */
std::vector<std::pair<std::string, std::string>> carriedKeys(
    const mrpt::config::CConfigFileBase& ini)
{
    std::vector<std::pair<std::string, std::string>> carried;
    for (const auto& k : kCarriedKeys)
    {
        if (ini.keyExists(kSection, k))
        {
            carried.emplace_back(k, trimValue(ini.read_string(kSection, k, "")));
        }
    }
    return carried;
}

/** The command line's values replace the ini's. */
void applyOverrides(LocalizationExperiment::TOptions& o,
                    const LocalizationExperiment::TOverrides& ov)
{
    if (!ov.rawlog_file.empty())
    {
        o.rawlog_file = ov.rawlog_file;
    }
    if (!ov.logOutput_dir.empty())
    {
        o.logOutput_dir = ov.logOutput_dir;
    }
    if (!ov.ground_truth_path_file.empty())
    {
        o.ground_truth_path_file = ov.ground_truth_path_file;
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
    if (ov.particles_save_every)
    {
        ASSERTMSG_(*ov.particles_save_every >= 0, "--save-particles must be 0 or more");
        o.particles_save_every = *ov.particles_save_every;
    }
    if (ov.detections_trace)
    {
        o.detections_trace = *ov.detections_trace;
    }
    if (ov.seed)
    {
        ASSERTMSG_(*ov.seed <= static_cast<uint32_t>(std::numeric_limits<int>::max()),
                   "seed must be in [0, 2147483647]");
        o.filter.seed = *ov.seed;
    }
}

/** Warnings about the machine's resources: particles taking more than half the memory (an
 *  error when more than all of it), more threads than the machine has. */
std::vector<std::string> resourceWarnings(const Localizer::TOptions& f,
                                          const LocalizationExperiment::TOverrides& ov)
{
    std::vector<std::string> warnings;
    if (auto w = detail::checkParticleMemory(f, ov.particles_count.has_value(), kSection);
        !w.empty())
    {
        warnings.push_back(std::move(w));
    }
    if (const size_t cores = std::thread::hardware_concurrency();
        cores > 0 && f.effectiveThreads() > cores)
    {
        warnings.push_back(mrpt::format(
            "%s %d exceeds the %zu hardware threads of this machine: the run is slower, not "
            "faster",
            ov.threads ? "--threads" : "[PF_options] threads", f.threads, cores));
    }
    return warnings;
}

/** The rawlog and the output directory are set, the input files exist; an empty
 *  ground_truth_path_file takes semloc-simulate's `<rawlog stem>_gt.txt` if it exists. */
void checkInputFiles(LocalizationExperiment::TOptions& o, const mrpt::config::CConfigFileBase& ini)
{
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
    requireFile("rawlog_file", o.rawlog_file, ini);
    if (o.ground_truth_path_file.empty() &&
        mrpt::system::fileExists(GroundTruthFile::PathFor(o.rawlog_file)))
    {
        o.ground_truth_path_file = GroundTruthFile::PathFor(o.rawlog_file);  // semloc-simulate's
    }
    requireFile("map_file", o.map_file, ini);
    requireFile("ground_truth_path_file", o.ground_truth_path_file, ini);
}

/** What the streamed check of a rawlog found (its entries are not kept). */
struct RawlogScan
{
    /** Intact entries (those the run uses). */
    size_t entries = 0;
    std::optional<size_t> truncatedAt;
    /** What was wrong and what is used; empty for a complete rawlog. */
    std::string warning;
    /** How far from a step's time its ground-truth row may be (groundTruthTolerance). */
    double gtTolerance = 0;
};

/** The defect of the rawlog `reader` read: an error unless `allowTruncated` and an entry
 *  before it is intact; else what `scan` records of it. */
void acceptDefect(const RawlogReader& reader, bool allowTruncated, RawlogScan& scan)
{
    RawlogReader::TResult read;  // for its defectMessage()
    read.path = reader.path();
    read.defect = reader.defect();
    if (!read.defect)
    {
        return;
    }
    if (read.defect->entry == 0)
    {
        THROW_EXCEPTION(read.defectMessage() + ": nothing to localize");  // with or without
    }                                                                     // --allow-truncated
    if (!allowTruncated)
    {
        THROW_EXCEPTION(read.defectMessage() +
                        " (semloc-localize --allow-truncated uses the intact entries)");
    }
    scan.truncatedAt = read.defect->entry;
    scan.warning = read.defectMessage() + mrpt::format(
                                              ": --allow-truncated: localizing with the %zu "
                                              "intact entries",
                                              read.defect->entry);
}

/** Reads the rawlog entry by entry (nothing is kept: memory does not grow with its length)
 *  and checks what the run needs of it (detail::checkRawlog), a rawlog_offset that leaves a
 *  step, and with ground truth step times that increase and match it. A defect is an error
 *  unless `allowTruncated` and an entry before it is intact. */
RawlogScan scanRawlog(const LocalizationExperiment::TOptions& o, bool allowTruncated,
                      const mrpt::maps::CMetricMap& maps, const GroundTruth& gt)
{
    RawlogReader reader(o.rawlog_file);
    RawlogScan scan;
    detail::StepTimer timer;
    scan.entries = detail::checkRawlog(
        [&]
        {
            auto obj = reader.next();
            if (!obj)
            {
                acceptDefect(reader, allowTruncated, scan);  // before the whole-file checks
                if (reader.entriesRead() == 0)
                {
                    THROW_EXCEPTION("rawlog '" + o.rawlog_file + "' holds no entries");
                }
            }
            return obj;
        },
        [&](const mrpt::serialization::CSerializable::Ptr& obj, size_t i) { timer.add(obj, i); },
        o.rawlog_file, maps, o.filter);
    auto steps = timer.finish();
    if (o.rawlog_offset > 0 && static_cast<size_t>(o.rawlog_offset) >= steps.size())
    {
        THROW_EXCEPTION(mrpt::format(
            "ini [%s] rawlog_offset: %d skips every step: rawlog '%s' holds %zu step%s (%zu "
            "entries)",
            kSection.c_str(), o.rawlog_offset, o.rawlog_file.c_str(), steps.size(),
            steps.size() == 1 ? "" : "s", scan.entries));
    }
    if (!gt.empty())
    {
        steps.erase(steps.begin(), steps.begin() + o.rawlog_offset);
        detail::checkGroundTruthTimes(steps, gt, o.ground_truth_path_file, o.rawlog_file);
        std::vector<double> times;
        times.reserve(steps.size());
        for (const auto& st : steps)
        {
            times.push_back(st.t);
        }
        scan.gtTolerance = detail::groundTruthTolerance(gt, times);
    }
    return scan;
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
    readInt(c, s, "particles_save_every", particles_save_every, 0, std::numeric_limits<int>::max());
    readBool(c, s, "detections_trace", detections_trace);
    variant = trimValue(c.read_string(s, "variant", variant));
    // MRPT's ini reader ends a value at "//" inconsistently (an inline comment): such a value
    // would not read back from the effective config.ini.
    for (const auto& [key, value] :
         {std::pair<const char*, const std::string*>{"rawlog_file", &rawlog_file},
          {"map_file", &map_file},
          {"ground_truth_path_file", &ground_truth_path_file},
          {"logOutput_dir", &logOutput_dir},
          {"variant", &variant}})
    {
        if (value->find("//") != std::string::npos)
        {
            THROW_EXCEPTION("ini [" + s + "] " + key + ": '" + *value +
                            "' holds '//', which starts a comment in an ini file");
        }
    }
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
    writeText(c, s, "particles_save_every", std::to_string(particles_save_every),
              "particles.csv: every N-th step and the last (0: none)");
    writeText(c, s, "detections_trace", detections_trace ? "1" : "0",
              "detections.csv: each semantic detection's gain at the estimate and the truth");
    writeText(c, s, "variant", variant, "name in summary.yaml");
    detail::writeExact(c, s, "convergence_max_err_xy_m", convergence.max_err_xy_m, "[m]");
    detail::writeExact(c, s, "convergence_max_var_xy_m2", convergence.max_var_xy_m2, "[m^2]");
    writeText(c, s, "convergence_min_steps", std::to_string(convergence.min_steps), "steps");
    writeText(c, s, "use_3D_poses", "false", "2D only");
    writeText(c, s, "experimentRepetitions", "1", "one run");
    filter.saveToConfigFile(c, s);
}

// ------------------------------------------------------------------ loading

LocalizationExperiment LocalizationExperiment::FromConfigFile(const std::string& iniPath,
                                                              const TOverrides& ov)
{
    config::checkIniFile(iniPath);
    LocalizationExperiment e;
    e.m_iniPath = iniPath;
    auto ini = std::make_shared<config::IniFileInMemory>(iniPath);
    e.m_ini = ini;
    checkSections(*ini, iniPath);

    auto& o = e.m_options;
    o.loadFromConfigFile(*ini, kSection);
    e.m_carried = carriedKeys(*ini);
    applyOverrides(o, ov);
    e.m_warnings = ini->warnings();  // deprecated keys (in the files, and as read)
    e.m_warnings.insert(e.m_warnings.end(), o.filter.warnings.begin(), o.filter.warnings.end());
    for (auto& w : resourceWarnings(o.filter, ov))
    {
        e.m_warnings.push_back(std::move(w));
    }
    checkInputFiles(o, *ini);
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
    if (o.detections_trace && !e.m_maps.map->mapByClass<CSemanticMap>())
    {
        THROW_EXCEPTION("ini [" + kSection +
                        "] detections_trace: 1 (or --trace-detections) needs a semantic map "
                        "in [MetricMap] (semanticMap_count = 1): it explains semantic detections");
    }
    if (o.variant.empty())
    {
        o.variant = e.m_maps.variant();
    }

    const auto scan = scanRawlog(o, ov.allow_truncated, *e.m_maps.map, e.m_groundTruth);
    e.m_entries = scan.entries;
    e.m_truncatedAt = scan.truncatedAt;
    e.m_gtTolerance = scan.gtTolerance;
    if (!scan.warning.empty())
    {
        e.m_rawlogWarning = scan.warning;
        e.m_warnings.push_back(e.m_rawlogWarning);
    }
    return e;
}

void LocalizationExperiment::CheckConfig(const std::string& iniPath, const std::string& mapFile)
{
    try
    {
        config::checkIniFile(iniPath);
        const config::IniFileInMemory ini(iniPath);
        checkSections(ini, iniPath);
        TOptions o;
        o.loadFromConfigFile(ini, kSection);
        if (!mapFile.empty())
        {
            o.map_file = mapFile;
        }
        requireFile("map_file", o.map_file, ini);
        (void)LocalizationMap::FromConfig(ini, o.map_file);
    }
    catch (const std::exception& e)
    {
        std::string m = errorMessage(e);
        if (m.rfind("ini [", 0) == 0)
        {
            m = "ini '" + iniPath + "': " + m.substr(4);
        }
        else if (m.find(iniPath) == std::string::npos)
        {
            m = "ini '" + iniPath + "': " + m;
        }
        THROW_EXCEPTION(m);
    }
}

std::vector<std::string> LocalizationExperiment::inputFiles() const
{
    const auto& o = m_options;
    auto files = config::iniFileAndBases(m_iniPath);
    files.insert(files.end(), {o.rawlog_file, o.map_file, o.ground_truth_path_file});
    return files;
}

namespace detail
{
void checkLocalizeSection(const std::string& section)
{
    if (std::find(kSections.begin(), kSections.end(), section) != kSections.end() ||
        section.rfind("MetricMap_", 0) == 0)
    {
        return;
    }
    std::string list;
    for (const auto& k : kSections)
    {
        list.append(list.empty() ? "[" : ", [").append(k).append("]");
    }
    THROW_EXCEPTION(
        mrpt::format("ini [%s]: unknown section (semloc-localize reads %s and "
                     "[MetricMap_<map>_<NN>_...])",
                     shownValue(section).c_str(), list.c_str()));
}

std::string effectiveConfigText(const LocalizationExperiment::TOptions& o,
                                const std::vector<std::pair<std::string, std::string>>& carried,
                                const LocalizationMap& maps,
                                const mrpt::config::CConfigFileBase& ini)
{
    mrpt::config::CConfigFileMemory eff;
    o.saveToConfigFile(eff, kSection);
    for (const auto& [k, v] : carried)
    {
        writeText(eff, kSection, k, v, "pf-localization only, not used");
    }
    return "# semloc-localize: the effective configuration of this run (every key of our "
           "sections,\n# defaults included). Rerun: semloc-localize config.ini -o "
           "<another directory>\n" +
           eff.getContent() + "\n" + maps.effectiveConfig(ini);
}
}  // namespace detail

}  // namespace semloc
