/* semloc — the odometry's motion model of the ini ([MotionModel]): the noise of every odometry
 * increment as the rawlog carries it, or re-derived from the raw increment with MRPT's Gaussian
 * model. */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <semloc/io/ConfigHelpers.h>

#include <string>

namespace semloc
{
/** A heading drift rate in the ini's deg/min, in the filter's rad/s (and back: divide). */
constexpr double kRadPerSecondPerDegPerMinute = 3.14159265358979323846 / 180.0 / 60.0;

/** Where the noise of the odometry comes from ([MotionModel] source).
 *
 *  - `rawlog` (default, as MRPT's pf-localization): the Gaussian every CActionRobotMovement2D
 *    of the rawlog carries; the increments of CObservationOdometry readings (and the zero
 *    increments of allow_no_odometry) get pf-localization's model: MRPT's default a1..a4 with
 *    [DummyOdometryParams] minStdXY, minStdPHI.
 *  - `gaussian`: every increment's Gaussian is computed again by MRPT's own
 *    CActionRobotMovement2D::computeFromOdometry() with the Gaussian model a1..a4, minStdXY,
 *    minStdPHI of this section: the rawOdometryIncrementReading of each
 *    CActionRobotMovement2D, and the increments of CObservationOdometry readings
 *    ([DummyOdometryParams] minStdXY/minStdPHI are then not used). An action that cannot be
 *    re-derived (problem()) is an error.
 *
 *  The keys are MRPT's names of TMotionModelOptions::TOptions_GaussianModel, in the units of
 *  that struct's documentation and of MRPT's RawLogViewer motion-model dialog (MRPT 2.5 has no
 *  ini loader for it): a2 in m/deg, a3 in deg/m, minStdPHI in deg, as MRPT's ini files give
 *  minStdPHI. */
class MotionModelConfig
{
public:
    /** semloc's motion model's name ([MotionModel] kind). */
    static constexpr const char* kOdometryModel = "odometry";
    /** [MotionModel] source. */
    enum class Source
    {
        /** The rawlog's own noise. */
        Rawlog = 0,
        /** MRPT's Gaussian model with a1..a4, minStdXY, minStdPHI. */
        Gaussian = 1
    };

    /** The section's keys; the defaults of a1..minStdPHI are MRPT's own. */
    struct TOptions : public mrpt::config::CLoadableOptions
    {
        /** kind: the prediction's motion model by name (MotionModelRegistry): "odometry"
         *  (OdometryMotionModel, the default), "dvl" (DvlMotionModel) or one a program
         *  registered. */
        std::string kind = kOdometryModel;
        /** source: rawlog | gaussian. */
        Source source = Source::Rawlog;
        /** Position std per metre travelled [m/m]. */
        double a1 = 0.01;
        /** Position std per degree turned [m/deg]. */
        double a2 = 0.001;
        /** Heading std per metre travelled [deg/m]. */
        double a3 = 1.0;
        /** Heading std per degree turned [deg/deg]. */
        double a4 = 0.05;
        /** Minimum position std of every increment [m]. */
        double minStdXY = 0.01;
        /** Minimum heading std of every increment [deg]. */
        double minStdPHI = 0.2;
        /** The odometry's heading drift as a state of every particle
         *  (CParallelMonteCarloLocalization2D::setHeadingDrift): the standard deviation of a
         *  particle's initial drift rate [deg/min] (what a gyro's bias or a DVL's heading
         *  gains per minute beyond the truth); 0 with heading_drift_walk_deg_per_min = 0: no
         *  drift state. Needs timestamped frames and PF_algorithm = 0. */
        double heading_drift_std_deg_per_min = 0;
        /** The standard deviation of a drift rate's change over one minute [deg/min] (a random
         *  walk: over dt, this times sqrt(dt / 60 s)). */
        double heading_drift_walk_deg_per_min = 0;
        /** How late the vehicle follows its odometry [s] (OdometryDelay): each step's
         *  increment is re-cut to cover what the odometry said `odometry_delay_s` earlier
         *  (commanded speeds executed after the drive's latency; clocks that differ). 0: the
         *  increments as they come. Needs timestamped actions and Gaussian odometry. */
        double odometry_delay_s = 0;
        /** The walk semloc-calibrate sets when the odometry's heading drifts, and
         *  config/localize/semantic.ini's [deg/min]. */
        static constexpr double kCalibratedDriftWalkDegPerMin = 5;
        /** True when the filter keeps a heading drift per particle. */
        bool headingDrift() const
        {
            return heading_drift_std_deg_per_min > 0 || heading_drift_walk_deg_per_min > 0;
        }

        /** The values loadFromConfigFile() accepts for the numeric key `key` (throws for a
         *  key that is not a number): what a tool writing the key must keep to. */
        static config::TValueRange range(const std::string& key);

        /** Reads `section` strictly: an unknown key, a value out of range or not finite is an
         *  error naming [section] key. */
        void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                                const std::string& section) override;
        /** Writes every key, defaults included. */
        void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                              const std::string& section) const override;
    };

    /** The section's name. */
    static constexpr const char* kSection = "MotionModel";

    explicit MotionModelConfig(const TOptions& options) : m_options(options) {}

    /** True when every increment's noise is re-derived (source = gaussian). */
    bool rederives() const { return m_options.source == Source::Gaussian; }
    /** MRPT's options of the Gaussian model with a1..minStdPHI (converted to radians). */
    mrpt::obs::CActionRobotMovement2D::TMotionModelOptions gaussian() const;
    /** Why the movements of `acts` cannot be re-derived, as a phrase, or "" when they can (or
     *  nothing is re-derived): a CActionRobotMovement2D whose estimationMethod is not
     *  emOdometry (a scan-matching estimate has no raw odometry increment), one without a raw
     *  increment (rawOdometryIncrementReading zero while its pose change's mean is not: the
     *  writer set the pose change only), a CActionRobotMovement3D (2D odometry only). */
    std::string problem(const mrpt::obs::CActionCollection& acts) const;
    /** `acts` when nothing is re-derived, else `copy` filled with `acts` and each
     *  CActionRobotMovement2D recomputed by computeFromOdometry(rawOdometryIncrementReading,
     *  gaussian()). Throws when problem() is not empty. */
    const mrpt::obs::CActionCollection& apply(const mrpt::obs::CActionCollection& acts,
                                              mrpt::obs::CActionCollection& copy) const;

    /** The options. */
    const TOptions& options() const { return m_options; }

private:
    TOptions m_options;
};

}  // namespace semloc
