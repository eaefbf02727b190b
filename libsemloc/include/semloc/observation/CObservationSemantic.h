/* semloc — semantic observation: the objects a detector recognized in one scan. */
#pragma once

#include <mrpt/obs/CObservation.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CSerializable.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace semloc
{
/** One recognized object: the paper's Object_i(rho_i, theta_i) plus its class. */
struct TSemanticDetection
{
    /** Object class reported by the detector (e.g. "wellhead"). */
    std::string label;
    /** Range from the sensor [m] (the paper's rho). */
    double range_m = 0;
    /** Bearing in the sensor frame [rad], counter-clockwise from its x axis (theta). */
    double bearing_rad = 0;
    /** Detector confidence in [0, 1]. */
    double confidence = 1.0;
    /** Map object id when the detector knows which object it is, else -1. */
    int32_t object_id = -1;

    /** Field-by-field equality. */
    bool operator==(const TSemanticDetection& o) const
    {
        return label == o.label && range_m == o.range_m && bearing_rad == o.bearing_rad &&
               confidence == o.confidence && object_id == o.object_id;
    }
};

/** The output of an object detector for one scan (the paper's z^r): a list of
 *  labelled (range, bearing) detections, the detector's pose on the vehicle and
 *  its coverage (max range and horizontal field of view).
 *
 *  Serializable into MRPT rawlogs; registered with MRPT's class registry when
 *  libsemloc is loaded, so `rawlog-edit -p libsemloc.so` reads it. */
class CObservationSemantic : public mrpt::obs::CObservation
{
    DEFINE_SERIALIZABLE(CObservationSemantic, semloc)

public:
    /** Pose of the detector on the vehicle. */
    mrpt::poses::CPose3D sensorPose;
    /** Maximum detection range [m]. */
    double maxRange_m = 20.0;
    /** Horizontal field of view [rad], centred on the sensor's x axis (2*pi = all around). */
    double fov_rad = 2.0 * M_PI / 3.0;
    /** The detections of this scan (possibly empty: nothing recognized). */
    std::vector<TSemanticDetection> detections;

    /** True if the detection has a finite range in [0, maxRange_m], a bearing within
     *  +-4 pi that wraps inside the field of view, a confidence in [0, 1] and a label. */
    bool isValid(const TSemanticDetection& d) const { return isValid(d, maxRange_m, fov_rad); }
    /** The same check against a given max range [m] and field of view [rad]
     *  (inline: it runs once per detection per particle). */
    static bool isValid(const TSemanticDetection& d, double maxRange_m, double fov_rad)
    {
        // NaN fails every comparison below, so no separate isfinite is needed.
        if (d.label.empty() || !(d.range_m >= 0 && d.range_m <= maxRange_m) ||
            !(d.confidence >= 0 && d.confidence <= 1) || !(std::abs(d.bearing_rad) <= 4 * M_PI))
        {
            return false;  // beyond two turns a bearing is garbage, not an angle
        }
        const double b = (d.bearing_rad >= -M_PI && d.bearing_rad <= M_PI)
                             ? d.bearing_rad
                             : std::remainder(d.bearing_rad, 2 * M_PI);
        return std::abs(b) <= 0.5 * fov_rad + 1e-9;
    }

    /** The detector pose on the vehicle (sensorPose). */
    void getSensorPose(mrpt::poses::CPose3D& out_sensorPose) const override
    {
        out_sensorPose = sensorPose;
    }
    /** Sets the detector pose on the vehicle (sensorPose). */
    void setSensorPose(const mrpt::poses::CPose3D& newSensorPose) override
    {
        sensorPose = newSensorPose;
    }
    /** Human-readable dump: pose, coverage and one line per detection (rawlog-edit --describe). */
    void getDescriptionAsText(std::ostream& o) const override;

    /** Text export (rawlog-edit --export-txt): one row per observation with the
     *  detection count followed by 5 columns per detection. */
    bool exportTxtSupported() const override { return true; }
    /** Column names of exportTxtDataRow(). */
    std::string exportTxtHeader() const override;
    /** One row: coverage, detection count, then label, range, bearing, confidence, id per
     * detection. */
    std::string exportTxtDataRow() const override;
};

}  // namespace semloc
