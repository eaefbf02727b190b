/* semloc — the options of a detector that looks ahead in a fan (the forward-looking sonar, the
 * bearing-only camera). */
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/config/CLoadableOptions.h>
#include <semloc/models/detector/CObjectDetectorMap.h>

#include <string>
#include <vector>

namespace semloc
{
/** A fan ahead of the sensor, and its bearings' noise. */
struct TFanParam
{
    /** Horizontal field of view, centred on the sensor's x axis [deg]. */
    double fov_deg = 120;
    /** A bearing's noise [deg]. */
    double sigma_bearing_deg = 1;
    /** The fan's depression below the horizontal [deg] and its vertical field of view [deg]
     *  (180: no vertical limit). */
    double tilt_deg = 0, vertical_fov_deg = 180;

    /** The keys, for the strict check of the section. */
    static std::vector<std::string> keys()
    {
        return {"fov_deg", "sigma_bearing_deg", "tilt_deg", "vertical_fov_deg"};
    }
    void load(const mrpt::config::CConfigFileBase& source, const std::string& section);
    void save(mrpt::config::CConfigFileBase& target, const std::string& section) const;
};

/** The `likelihoodOpts` of a detector that looks ahead in a fan: the shared keys and the fan's
 *  (CForwardSonarMap, CBearingCameraMap; the kinds set their defaults). */
struct TFanDetectorOptions : public mrpt::config::CLoadableOptions
{
    /** The keys every detector kind shares. */
    CObjectDetectorMap::TDetectorParam detector;
    /** Its fan and its bearings' noise. */
    TFanParam fan;
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                            const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                          const std::string& section) const override;

protected:
    /** `measuresRange`: the detections carry a range (its keys sigma_range_m and
     *  p_range_outlier are read). */
    explicit TFanDetectorOptions(bool measuresRange) : m_measuresRange(measuresRange) {}

private:
    bool m_measuresRange;
};
}  // namespace semloc
