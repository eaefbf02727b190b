/* semloc — semloc-localize's engine: an ini in MRPT pf-localization's format, a rawlog, a
 * localizer over it, and the outputs of docs/design.md (steps.csv, summary.yaml, config.ini). */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/obs/CRawlog.h>
#include <semloc/dataset/GroundTruthFile.h>
#include <semloc/experiment/GroundTruth.h>
#include <semloc/experiment/RunMetrics.h>
#include <semloc/filter/Localizer.h>
#include <semloc/maps/LocalizationMap.h>

#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace semloc
{
/** One localization run as configured by an ini file.
 *
 *  ## The ini
 *  MRPT pf-localization's sections: [LocalizationExperiment] (rawlog_file, map_file,
 *  ground_truth_path_file, logOutput_dir, particles_count, init_PDF_*, ...), [PF_options],
 *  [KLD_options], [DummyOdometryParams], [MetricMap] and its map sections, read strictly: an
 *  unknown section, an unknown key of our sections, a bad value, an unknown map name or a
 *  missing file is an error naming it (Localizer::TOptions, LocalizationMap). pf-localization
 *  keys that only concern its display or 3D mode are accepted and ignored; `use_3D_poses`
 *  must be false and `experimentRepetitions` 1. Ours, in [LocalizationExperiment]: `seed`,
 *  `variant`, `convergence_max_err_xy_m`, `convergence_max_var_xy_m2`,
 *  `convergence_min_steps`; in [PF_options]: `threads`, `free_space_prior`,
 *  `kld_at_resampling`; [Recovery]; [MotionModel]. Relative input paths are resolved next to the
 * ini first (config::resolveNextToIni), `logOutput_dir` from the working directory (as MRPT). An
 *  empty `ground_truth_path_file` takes semloc-simulate's `<rawlog stem>_gt.txt` if it
 *  exists (GroundTruthFile::PathFor).
 *
 *  ## The rawlog
 *  Either format: action / sensory-frame pairs (one step each), or observations only, where
 *  CObservationOdometry readings give the motion (Localizer::setOdometry) and consecutive
 *  other observations with the same timestamp form one step's sensory frame.
 *
 *  ## The outputs (in `logOutput_dir`, replaced as a whole, never left partial)
 *  `steps.csv` (docs/design.md's header; ground truth matched by timestamp: the nearest row within
 *  half the median step period, columns empty when there is none), `summary.yaml`
 *  (RunMetrics and counters; unknown values are `null`), `config.ini` (the effective
 *  configuration: every key of our sections with its value, defaults included). */
class LocalizationExperiment
{
public:
    /** The run's settings: [LocalizationExperiment]'s own keys plus the filter's. */
    struct TOptions : public mrpt::config::CLoadableOptions
    {
        /** Rawlog to localize in (resolved path). */
        std::string rawlog_file;
        /** World YAML, .simplemap(.gz) or .gridmap(.gz) (resolved path; may be empty). */
        std::string map_file;
        /** `t x y phi` ground truth (resolved path; may be empty). */
        std::string ground_truth_path_file;
        /** Output directory. */
        std::string logOutput_dir;
        /** Steps skipped at the start (pf-localization's meaning: action / sensory-frame
         *  pairs, or observation frames). */
        int rawlog_offset = 0;
        /** Write the particles of every N-th step (step 0, N, 2N, ... and the last step) to
         *  particles.csv; 0: not written. */
        int particles_save_every = 0;
        /** Write detections.csv: what each semantic detection adds to the weight at the
         *  estimate and at the true pose, and the map object it is most like there (a run's
         *  diagnosis; docs/design.md, "Output contract of semloc-localize"). */
        bool detections_trace = false;
        /** Name of the variant in summary.yaml; empty: from the maps (LocalizationMap). */
        std::string variant;
        /** Convergence criterion (docs/design.md). */
        RunMetrics::TConvergenceCriterion convergence;
        /** The filter. */
        Localizer::TOptions filter;

        /** Reads [section] and the filter's sections; see the class documentation. */
        void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                                const std::string& section) override;
        /** Writes every key of the section, defaults included, with a comment. */
        void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                              const std::string& section) const override;
    };

    /** Command-line overrides of the ini. */
    struct TOverrides
    {
        /** Rawlog (the command line's rawlog argument); empty: the ini's. */
        std::string rawlog_file;
        /** Output directory (-o); empty: the ini's. */
        std::string logOutput_dir;
        /** Ground truth; empty: the ini's. */
        std::string ground_truth_path_file;
        /** [PF_options] threads (-t). */
        std::optional<int> threads;
        /** particles_count (-n). */
        std::optional<int> particles_count;
        /** seed (-s). */
        std::optional<uint32_t> seed;
        /** particles_save_every (--save-particles). */
        std::optional<int> particles_save_every;
        /** detections_trace (--trace-detections). */
        std::optional<bool> detections_trace;
        /** Use the intact entries before a truncated or corrupted one (--allow-truncated)
         *  instead of refusing the rawlog. */
        bool allow_truncated = false;
    };

    /** What a run produced. */
    struct TResult
    {
        /** The variant's name. */
        std::string variant;
        /** Where the outputs are. */
        std::string outputDir;
        /** Convergence, errors, timing. */
        RunMetrics metrics;
        /** One record per step (the rows of steps.csv) when run() was asked to keep them
         *  (Records::Keep); empty otherwise. */
        std::vector<TStepRecord> records;
        /** Particles after the last step (0 without a step). */
        size_t final_particles = 0;
        /** Observations used/skipped, invalid/unknown detections. */
        SensoryFrameLikelihood::TStats likelihood;
        /** Re-initializations, injected particles. */
        CParallelMonteCarloLocalization2D::TRecoveryStats recovery;
        /** init_PDF_mode = 3: the particles drawn from the first detections. */
        size_t initialized_from_detections = 0;
        /** [MotionModel] heading_drift_*: the particles' mean heading drift rate after the
         *  last step [deg/min] (0 when off). */
        double heading_drift_deg_per_min = 0;
        /** The detector's Cramér–Rao bound along the true path (docs/design.md, "The
         *  detector's bound"): the mean of its mean position error over the steps with ground
         *  truth [m]; NaN without ground truth or without a semantic map. */
        double detector_bound_mean_m = std::numeric_limits<double>::quiet_NaN();
        /** The same over the steps of metrics.mean_err_after_conv_m (from the convergence
         *  step on); NaN also when not converged. */
        double detector_bound_after_conv_m = std::numeric_limits<double>::quiet_NaN();
        /** Threads of the per-particle work. */
        size_t threads = 1;
        /** "action/sensory-frame", "observations-only" or "mixed". */
        std::string rawlogFormat;
        /** Index of the rawlog's first unreadable entry when allow_truncated let the run use
         *  the entries before it; empty for a complete rawlog. */
        std::optional<size_t> rawlogTruncatedAtEntry;
        /** Wall time of run() [s]. */
        double wallTime_s = 0;

        /** A one-paragraph summary for the terminal. */
        std::string summaryParagraph() const;
    };

    /** Reads and validates everything (ini, files, maps, the whole rawlog) before any
     *  output is written. Throws on any error; in the rawlog: a truncated or corrupted entry
     *  (unless `allow_truncated` and an entry before it is intact), an entry of an unknown
     *  class, no odometry at all (unless [DummyOdometryParams] allow_no_odometry), a
     *  non-finite odometry reading (mean or covariance), no observation any map in
     *  [MetricMap] can use, a rawlog_offset that skips every step; with ground truth, step
     *  times that do not increase (from rawlog_offset on) or match no row. Also throws when
     *  the particles (Localizer::TOptions::particleMemoryBytes) need more memory than the
     *  machine has (or `ulimit -v` / `ulimit -m` allows). */
    static LocalizationExperiment FromConfigFile(const std::string& iniPath,
                                                 const TOverrides& overrides);
    /** FromConfigFile() without overrides. */
    static LocalizationExperiment FromConfigFile(const std::string& iniPath)
    {
        return FromConfigFile(iniPath, TOverrides());
    }

    /** Checks the ini `iniPath` as FromConfigFile() checks it, without a rawlog, a ground
     *  truth or an output directory (a tool that writes an ini from it, the command line of
     *  semloc-localize giving those): its text (config::checkIniText), its sections, every key
     *  of [LocalizationExperiment] and the filter's sections, and the maps of [MetricMap]
     *  built with `mapFile` as map_file (its own when empty). Throws the error FromConfigFile()
     *  would, naming `iniPath`. */
    static void CheckConfig(const std::string& iniPath, const std::string& mapFile);

    /** Whether run() keeps every step's record in TResult::records (memory that grows with
     *  the rawlog's length) or only streams them to steps.csv and the metrics. */
    enum class Records
    {
        Keep,
        Stream
    };

    /** Runs the filter over the rawlog, read again entry by entry, and writes the outputs as
     *  it goes (steps.csv, particles.csv); `progress(done, total)` is called after every
     *  rawlog entry. On error nothing is left in logOutput_dir. */
    TResult run(const std::function<void(size_t, size_t)>& progress = {},
                Records records = Records::Keep) const;

    /** The validated options (overrides applied, input paths absolute). */
    const TOptions& options() const { return m_options; }
    /** The maps. */
    const LocalizationMap& maps() const { return m_maps; }
    /** With allow_truncated and a defective rawlog: what was wrong and what is used (to be
     *  shown to the user); empty otherwise. */
    const std::string& rawlogWarning() const { return m_rawlogWarning; }
    /** What the user should know before the run (to be shown on stderr): rawlogWarning(),
     *  particles taking more than half the memory, more threads than the machine has. */
    const std::vector<std::string>& warnings() const { return m_warnings; }

private:
    LocalizationExperiment() = default;
    /** The files the run reads (the ini, rawlog, map, ground truth; empty when unset): the
     *  output directory must not hold any of them. */
    std::vector<std::string> inputFiles() const;

    std::string m_iniPath;
    TOptions m_options;
    LocalizationMap m_maps;
    /** The rawlog's intact entries (run() reads them again, one at a time). */
    size_t m_entries = 0;
    /** See detail::groundTruthTolerance. */
    double m_gtTolerance = 0;
    /** See TResult::rawlogTruncatedAtEntry. */
    std::optional<size_t> m_truncatedAt;
    std::string m_rawlogWarning;
    std::vector<std::string> m_warnings;
    /** The ground truth (empty without ground_truth_path_file). */
    GroundTruth m_groundTruth;
    /** The ini's text with its [MetricMap...] sections, for the effective configuration. */
    std::shared_ptr<mrpt::config::CConfigFileBase> m_ini;
    /** Keys pf-localization reads that we only carry over (display, 3D). */
    std::vector<std::pair<std::string, std::string>> m_carried;
};

}  // namespace semloc
