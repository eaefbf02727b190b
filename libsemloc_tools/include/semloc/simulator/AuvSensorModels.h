/* semloc — the simulated sensors of an AUV: depth, compass, USBL fixes, DVL, and the object
 * detectors of the water column (side-scan, forward-looking sonar, camera). */
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <string>

namespace semloc
{
/** Section [Depth]: a pressure sensor (and a DVL's altitude) every `period_steps` steps. */
struct TDepthSensorOptions : public mrpt::config::CLoadableOptions
{
    bool enabled = false;
    /** The vehicle's true depth [m]: it flies level (and the detectors see from there, the
     *  depth sensor on or off). */
    double depth_m = 25;
    /** The reading's noise [m]. */
    double noise_std_m = 0.05;
    /** The seabed's depth [m] for the altitude reading (seabed - depth + noise); 0: no
     *  altitude (NaN). */
    double seabed_depth_m = 30;
    double altitude_noise_std_m = 0.1;
    int period_steps = 1;
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                          const std::string& section) const override;
};

/** Section [Compass]: MRPT's CObservationIMU with its yaw. */
struct TCompassSimOptions : public mrpt::config::CLoadableOptions
{
    bool enabled = false;
    std::string sensor_label = "compass";
    /** Noise [deg], a constant bias [deg], and the share of readings disturbed (uniform). */
    double sigma_deg = 2, bias_deg = 0, p_outlier = 0;
    /** The residual deviation of a calibrated magnetic compass: deviation_deg
     *  cos(heading - deviation_phase_deg) added to every reading (the ship's iron: a bias
     *  that changes with the heading, so that a lawnmower's legs do not cancel it) [deg]. */
    double deviation_deg = 0, deviation_phase_deg = 0;
    int period_steps = 1;
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                          const std::string& section) const override;
};

/** Section [USBL]: position fixes from a ship (MRPT's CObservationRobotPose). */
struct TFixSimOptions : public mrpt::config::CLoadableOptions
{
    bool enabled = false;
    std::string sensor_label = "usbl";
    /** A fix every this many steps (the first at step period_steps). */
    int period_steps = 20;
    /** The fixes' noise in x and y [m] (also the covariance they carry). */
    double sigma_m = 3;
    /** The share of fixes off by N(0, outlier_sigma_m) instead (multipath). */
    double p_outlier = 0, outlier_sigma_m = 30;
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                          const std::string& section) const override;
};

/** Section [DVL]: the odometry as a DVL's body-frame increments (replaces [Odometry]'s). */
struct TDvlSimOptions : public mrpt::config::CLoadableOptions
{
    bool enabled = false;
    /** Each body axis' noise as a share of the distance travelled [m/m], with a floor [m]. */
    double xy_std_per_m = 0.01, min_xy_std_m = 0.002;
    /** A scale error of the velocities (the sound speed, the bottom lock), e.g. 0.005. */
    double scale_error = 0;
    /** The heading change's noise per metre [deg/m], with a floor [deg]. */
    double phi_std_deg_per_m = 0.1, min_phi_std_deg = 0.05;
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                          const std::string& section) const override;
};

/** Sections [SideScan], [ForwardSonar], [Camera]: a detector of the seabed's objects
 *  (CObservationSemantic under `sensor_label`), the geometry semloc's detector models score
 *  (docs/design.md, "The detector models"), ranges always slant. */
struct TObjectDetectorSimOptions : public mrpt::config::CLoadableOptions
{
    enum class Kind
    {
        SideScan,
        ForwardSonar,
        Camera
    };
    explicit TObjectDetectorSimOptions(Kind k);
    Kind kind;
    bool enabled = false;
    std::string sensor_label;
    double min_range_m = 0, max_range_m = 50;
    double p_detect_near = 0.8, p_detect_far = 0.4;
    /** Poisson mean of false alarms per scan, uniform over the measurement space and the
     *  world's labels. */
    double clutter_per_scan = 0.1;
    double range_noise_std_m = 0.5, bearing_noise_std_deg = 1;
    /** Side-scan: the fan's along-track width [deg] and the nadir gap [m]. */
    double beam_width_deg = 4, nadir_gap_m = 3;
    /** Forward-looking sonar and camera: the fan [deg]. */
    double fov_deg = 120, tilt_deg = 0, vertical_fov_deg = 180;
    /** The sensor on the vehicle: forward, left, up [m], yaw [deg]. */
    double sensor_x_m = 0, sensor_y_m = 0, sensor_z_m = 0, sensor_yaw_deg = 0;
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                          const std::string& section) const override;
};

/** Every AUV sensor of a simulation (all off by default: a dataset without them is as it
 *  was, byte for byte). */
struct TAuvSensorOptions
{
    TDepthSensorOptions depth;                                                      //!< [Depth]
    TCompassSimOptions compass;                                                     //!< [Compass]
    TFixSimOptions usbl;                                                            //!< [USBL]
    TDvlSimOptions dvl;                                                             //!< [DVL]
    TObjectDetectorSimOptions sidescan{TObjectDetectorSimOptions::Kind::SideScan};  //!< [SideScan]
    TObjectDetectorSimOptions fls{
        TObjectDetectorSimOptions::Kind::ForwardSonar};                         //!< [ForwardSonar]
    TObjectDetectorSimOptions camera{TObjectDetectorSimOptions::Kind::Camera};  //!< [Camera]

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& source);
    void saveToConfigFile(mrpt::config::CConfigFileBase& target) const;
};

}  // namespace semloc
