/* semloc — the particle-filter localizer: MRPT's Monte Carlo localization over a metric map,
 * step by step from a robot's loop, parallel and deterministic. */
#pragma once

#include <mrpt/bayes/CParticleFilter.h>
#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/slam/TKLDParams.h>
#include <mrpt/system/COutputLogger.h>
#include <semloc/filter/AugmentedMCL.h>
#include <semloc/filter/CParallelMonteCarloLocalization2D.h>
#include <semloc/filter/FreeSpaceSampler.h>
#include <semloc/filter/MotionModelConfig.h>
#include <semloc/filter/OdometryDelay.h>
#include <semloc/filter/SensoryFrameLikelihood.h>
#include <semloc/filter/StepRecord.h>
#include <semloc/world/World.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

namespace semloc
{
class ParallelExecutor;

/** True when `map` has maps and every one gives the likelihood with nothing of it in view
 *  (BatchLikelihood::weighsWithoutMap(): semantic maps): what the evidence recovery trigger
 *  (recovery_trigger = evidence) needs, as it weighs the frame against it. */
bool weighsWithoutMaps(const mrpt::maps::CMultiMetricMap& map);

/** A 2D particle-filter localizer: CParallelMonteCarloLocalization2D driven by MRPT's
 *  CParticleFilter over the maps of a CMultiMetricMap (the mix of maps is the variant).
 *
 *  Use it from a robot's loop: step(action, frame) with odometry actions (MRPT's
 *  action / sensory-frame format), or setOdometry() + step(frame) with raw odometry
 *  readings (the observations-only format); then read pdf(), mean(), covariance().
 *
 *  Deterministic: the constructor seeds MRPT's global random generator
 *  (mrpt::random::getRandomGenerator(), which MRPT's particle filter draws from) with
 *  `seed`; the same options, map and inputs give the same particles, for any `threads`. */
class Localizer : public mrpt::system::COutputLogger
{
public:
    /** How the particles start (`init_PDF_mode`). */
    enum class InitMode
    {
        /** 0: uniform over the free space (the world's, else the occupancy grid's free
         *  cells), within the init_PDF box if one is given: global localization. */
        FreeSpace = 0,
        /** 1: uniform in the init_PDF box (MRPT's resetUniform). */
        Box = 1,
        /** 2: Gaussian around init_PDF_mean_x/y/yaw_deg. */
        Gaussian = 2,
        /** 3: as 0, then, at the first frame with a semantic detection the map can
         *  associate, a share init_PDF_from_detections of the particles drawn from that
         *  frame's detections (the first sensor model's BatchLikelihood::proposal(), the
         *  semantic map's DetectionPoseSampler: poses from which the detection could have
         *  been seen, placed one odometry increment back so that this step's prediction
         *  brings them to the detection's time) before the frame weighs them. Needs a map
         *  that proposes poses (a semantic map). */
        FromDetections = 3
    };

    /** The filter's settings, in the sections of MRPT's pf-localization plus ours.
     *  loadFromConfigFile() reads `section` (normally [LocalizationExperiment]) and the fixed
     *  sections [PF_options], [KLD_options], [DummyOdometryParams], [MotionModel]; it rejects
     *  unknown keys
     *  of those sections and bad values, naming [section] key. Keys of
     *  [LocalizationExperiment] that are not the filter's are LocalizationExperiment's. */
    struct TOptions : public mrpt::config::CLoadableOptions
    {
        /** @name [LocalizationExperiment]: the initial cloud and the seed
         *  @{ */
        /** Largest particles_count and threads accepted (the ini keys and the tools'
         *  overrides alike). */
        static constexpr int kMaxParticles = 100000000, kMaxThreads = 1024;
        /** Number of particles (the initial number with KLD), 1..kMaxParticles. */
        int particles_count = 10000;
        /** init_PDF_mode: 0 free space, 1 box, 2 Gaussian, 3 free space then detections. */
        InitMode init_PDF_mode = InitMode::FreeSpace;
        /** The box of modes 0 and 1: min x [m]; for mode 0 an empty box (min >= max, the
         *  default) means the whole free space. */
        double init_PDF_min_x = 0;
        /** The box of modes 0 and 1: max x [m]. */
        double init_PDF_max_x = 0;
        /** The box of modes 0 and 1: min y [m]. */
        double init_PDF_min_y = 0;
        /** The box of modes 0 and 1: max y [m]. */
        double init_PDF_max_y = 0;
        /** Heading interval of modes 0 and 1: min [deg]. */
        double init_PDF_min_yaw_deg = -180;
        /** Heading interval of modes 0 and 1: max [deg]. */
        double init_PDF_max_yaw_deg = 180;
        /** Mode 2: mean x [m]. */
        double init_PDF_mean_x = 0;
        /** Mode 2: mean y [m]. */
        double init_PDF_mean_y = 0;
        /** Mode 2: mean heading [deg]. */
        double init_PDF_mean_yaw_deg = 0;
        /** Mode 2: standard deviation of x and of y [m]. */
        double init_PDF_std_xy = 1.0;
        /** Mode 2: standard deviation of the heading [deg]. */
        double init_PDF_std_yaw_deg = 10.0;
        /** Mode 3: the share of the particles drawn from the first detections, in [0, 1]. */
        double init_PDF_from_detections = 0.8;
        /** Seed of MRPT's global random generator. */
        uint32_t seed = 1;
        /** @} */

        /** @name [PF_options]: MRPT's TParticleFilterOptions plus ours
         *  @{ */
        /** MRPT's particle-filter options (PF_algorithm, resamplingMethod, BETA, ...). */
        mrpt::bayes::CParticleFilter::TParticleFilterOptions pf;
        /** Threads of the per-particle work, 0..kMaxThreads; 0 = every hardware thread. */
        int threads = 0;
        /** Weight zero for particles outside the free space (free_space_prior). */
        bool free_space_prior = false;
        /** With adaptiveSampleSize = 1: KLD-sampling at the resampling steps instead of
         *  MRPT's at every step (kld_at_resampling; CParallelMonteCarloLocalization2D). */
        bool kld_at_resampling = false;
        /** @} */

        /** [Recovery]: the trigger (off, amcl, evidence) and the injected particles (off by
         *  default). Read from [PF_options] recovery_<key> too, the keys' former place,
         *  with a warning in `warnings`. */
        AugmentedMCL::TOptions recovery;

        /** [KLD_options]: MRPT's KLD-sampling parameters (adaptiveSampleSize = 1). */
        mrpt::slam::TKLDParams kld;

        /** @name [DummyOdometryParams]: odometry noise of observations-only rawlogs
         *  @{ */
        /** Minimum std. dev. of x and y of every odometry increment [m] (minStdXY). */
        double odometry_min_std_xy = 0.04;
        /** Minimum std. dev. of the heading of every increment [deg] (minStdPHI). */
        double odometry_min_std_phi_deg = 2.0;
        /** A rawlog without any odometry (no CActionRobotMovement2D/3D, no
         *  CObservationOdometry) is an error unless this is true; then every step moves the
         *  particles by a zero increment with the noise above (allow_no_odometry). */
        bool allow_no_odometry = false;
        /** @} */

        /** [MotionModel]: the odometry's noise as the rawlog carries it (source = rawlog, the
         *  default) or re-derived from every raw increment with MRPT's Gaussian model a1..a4,
         *  minStdXY, minStdPHI (source = gaussian; then the [DummyOdometryParams] noise above
         *  is not used). See MotionModelConfig. */
        MotionModelConfig::TOptions motion_model;

        /** What loadFromConfigFile() found that still works but should change (a key under
         *  its deprecated name): one message per finding, naming the key and its place. */
        std::vector<std::string> warnings;

        TOptions();
        /** Reads the section strictly: an unknown key or a bad value is an error naming it. */
        void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                                const std::string& section) override;
        /** Writes every key (defaults included) of `section` and the four fixed sections. */
        void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                              const std::string& section) const override;
        /** The keys this struct reads in `section` ([LocalizationExperiment]). */
        static std::vector<std::string> experimentKeys();
        /** The thread count `threads` stands for on this machine. */
        size_t effectiveThreads() const;
        /** The memory the particles may take [bytes]: kBytesPerParticle x particles_count,
         *  plus kBytesPerKLDParticle x KLD_maxSampleSize with KLD sampling
         *  (adaptiveSampleSize), which may grow the cloud to that many. The maps, the rawlog
         *  and the program itself come on top. */
        uint64_t particleMemoryBytes() const;
    };

    /** @name Memory of the particles (measured peak resident memory per particle, rounded
     *  up: the particle, its pose, log-likelihood and weight buffers, the resampled copy)
     *  @{ */
    /** Bytes per particle of the filter. */
    static constexpr uint64_t kBytesPerParticle = 144;
    /** Bytes per particle of MRPT's KLD sampling (adaptiveSampleSize = 1), its bins included. */
    static constexpr uint64_t kBytesPerKLDParticle = 192;
    /** @} */

    /** Why `obs` cannot be scored at all, as a phrase ("its sensorPose is not finite"), or ""
     *  when it can: a sensorPose with a non-finite component or a position more than
     *  kMaxSensorOffset_m from the vehicle; a range scan with a non-finite or negative
     *  aperture or without beams; then what a registered kind of map refuses
     *  (SensorModelKind::invalidObservation(): semloc's refuse a one-beam scan where `map`
     *  holds an occupancy grid, which MRPT scores with at least 2 beams, a beacon range that
     *  is not finite, a CObservationSemantic with a non-finite or negative maxRange_m or
     *  fov_rad). step() skips such observations and counts them
     *  (likelihoodStats().observations_invalid). */
    static std::string invalidObservation(const mrpt::obs::CObservation& obs,
                                          const mrpt::maps::CMetricMap& map);
    /** Largest |x|, |y|, |z| of an observation's sensorPose [m] (semloc-simulate's largest
     *  sensor mount). */
    static constexpr double kMaxSensorOffset_m = 1e3;

    /** What one step did. */
    struct TStepInfo
    {
        /** Effective sample size in [0, 1] before resampling. */
        double ess_before_resampling = 1;
        /** Particles after the step. */
        size_t particles = 0;
        /** Wall time of the filter update (CParticleFilter::executeOn) [us]. */
        double update_us = 0;
    };

    /** Builds the filter over `map` and draws the initial particles. `world`, if given, is
     *  the free space of init_PDF_mode = 0 and of recovery; without it the first occupancy
     *  grid of `map` is, else the init_PDF box. Throws if the options are inconsistent. */
    Localizer(const TOptions& options, mrpt::maps::CMultiMetricMap::Ptr map,
              const World* world = nullptr);
    ~Localizer() override;

    /** @name Feeding the filter
     *  @{ */
    /** One step, action / sensory-frame format: the action's odometry moves the particles,
     *  the frame's observations weigh them. Range-scan beams flagged valid with a NaN,
     *  infinite, negative or beyond-maxRange range are made invalid first (in a copy) and
     *  counted (likelihoodStats().beams_invalid), observations that cannot be scored
     *  (invalidObservation()) are left out and counted (observations_invalid): no map ever
     *  sees them. The 2D movement of least uncertainty is used however uncertain it is
     *  (MRPT's CActionCollection::getBestMovementEstimation() ignores one whose covariance
     *  determinant reaches 1e3, and would find no odometry). With [MotionModel] source =
     *  gaussian every CActionRobotMovement2D's Gaussian is first recomputed from its
     *  rawOdometryIncrementReading (MotionModelConfig::apply; an action it cannot re-derive throws,
     *  naming why). */
    void step(const mrpt::obs::CActionCollection& action, const mrpt::obs::CSensoryFrame& sf);
    /** Observations-only format: remembers an odometry reading; the next step(sf) moves the
     *  particles by the increment since the previous step (pf-localization's rule; Gaussian
     *  noise from [DummyOdometryParams], or from [MotionModel] with source = gaussian). The
     *  first reading is the reference. */
    void setOdometry(const mrpt::obs::CObservationOdometry& odo);
    /** One step, observations-only format (see setOdometry()). */
    void step(const mrpt::obs::CSensoryFrame& sf);
    /** A new run: draws the initial particles again (init_PDF_mode) and forgets what the
     *  filter kept from frame to frame (the detector outage, the look-alikes' memory, the
     *  recovery trigger's averages or shortfall and its challenger set, the odometry
     *  delay); the generator is not re-seeded and the counters keep counting. */
    void reset();
    /** @} */

    /** @name The estimate
     *  @{ */
    /** The particles (MRPT's CPosePDFParticles interface: getMean, getCovarianceAndMean...). */
    const CParallelMonteCarloLocalization2D& pdf() const { return *m_pdf; }
    /** Weighted mean pose. */
    mrpt::poses::CPose2D mean() const;
    /** Trace of the x-y covariance of the particles [m^2]. */
    double varianceXY() const;
    /** The last step as a steps.csv row (no ground truth): index, time of `sf`'s first
     *  observation (NaN without a valid timestamp), mean, x-y variance, the pose covariance
     *  (one pass over the particles), ESS, particles, update time. `sf` is the frame that
     *  step used. */
    TStepRecord lastStepRecord(const mrpt::obs::CSensoryFrame& sf) const;
    /** The last step. */
    const TStepInfo& lastStep() const { return m_last; }
    /** The 2D odometry movement the last step moved the particles by: its action's (after
     *  [MotionModel]), or the one made of the odometry readings' increment (observations-only
     *  format); null before the first step and after a step without one (a 3D movement only). */
    const mrpt::obs::CActionRobotMovement2D* lastMovement() const
    {
        return m_lastMovement ? &*m_lastMovement : nullptr;
    }
    /** Steps run. */
    size_t steps() const { return m_steps; }
    /** @} */

    /** @name Diagnostics
     *  @{ */
    /** The localizer options. */
    const TOptions& options() const { return m_options; }
    /** Threads of the per-particle work. */
    size_t threads() const;
    /** Observations used / skipped, invalid and unknown detections, non-finite values. */
    SensoryFrameLikelihood::TStats likelihoodStats() const;
    /** Re-initializations and injected particles. */
    const CParallelMonteCarloLocalization2D::TRecoveryStats& recoveryStats() const
    {
        return m_pdf->recoveryStats();
    }
    /** What the free space is (for logs). */
    std::string freeSpaceDescription() const;
    /** init_PDF_mode = 3: the particles drawn from the first detections (0 before them). */
    size_t initializedFromDetections() const { return m_initializedFromDetections; }
    /** [MotionModel] heading_drift_*: the particles' weighted mean heading drift rate, what the
     *  odometry's heading gains per minute beyond the truth [deg/min] (0 when off). */
    double headingDriftDegPerMin() const;
    /** @} */

private:
    TOptions m_options;
    mrpt::maps::CMultiMetricMap::Ptr m_map;
    std::shared_ptr<ParallelExecutor> m_executor;
    std::unique_ptr<CParallelMonteCarloLocalization2D> m_pdf;
    mrpt::bayes::CParticleFilter m_pf;
    std::shared_ptr<const FreeSpaceSampler> m_freeSpace, m_initSpace;
    std::optional<mrpt::poses::CPose2D> m_lastOdometry, m_pendingOdometry;
    bool m_seededFromDetections = false;
    size_t m_initializedFromDetections = 0;
    /** The sensor models' approximations() when the particles were last drawn. */
    size_t m_approximatedBefore = 0;
    size_t associationsApproximatedNow() const;
    /** init_PDF_mode = 3 at the first frame whose detections the map can place. */
    void seedFromDetections(const mrpt::obs::CActionCollection& action,
                            const mrpt::obs::CSensoryFrame& sf);
    TStepInfo m_last;
    std::optional<mrpt::obs::CActionRobotMovement2D> m_lastMovement;
    /** [MotionModel] odometry_delay_s: the increments re-cut, from reset() on. */
    OdometryDelay m_odometryDelay;
    size_t m_steps = 0;
    /** Scan beams with impossible ranges, made invalid before the update. */
    size_t m_beamsInvalid = 0;
    /** Observations left out of the update (invalidObservation()). */
    size_t m_observationsInvalid = 0;
};

}  // namespace semloc
