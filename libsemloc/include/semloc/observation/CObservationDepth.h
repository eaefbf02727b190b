/* semloc — the vehicle's place in the water column: its depth (a pressure sensor) and, where a
 * DVL or an altimeter measures it, its altitude over the seabed. */
#pragma once

#include <mrpt/obs/CObservation.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CSerializable.h>

#include <cmath>
#include <limits>
#include <string>

namespace semloc
{
/** One reading of the vehicle's depth (docs/design.md, "The water column").
 *
 *  The world's heights are metres up from the sea surface (z = 0), so a vehicle at depth d
 *  is at z = -d, and the objects on a seabed at 30 m lie at z = -30. A model that predicts
 *  slant ranges (the detector models of models/detector/) takes the vehicle's height from the
 *  last depth reading it saw; a log without depth readings keeps the vehicle at z = 0, the
 *  plane every 2D dataset lives in. MRPT has no observation of a depth alone (its GPS and IMU
 *  classes carry a geodetic height or none): this one is semloc's, registered with MRPT's
 *  class registry so rawlogs carry it. */
class CObservationDepth : public mrpt::obs::CObservation
{
    DEFINE_SERIALIZABLE(CObservationDepth, semloc)

public:
    /** The depth of the vehicle's reference point below the surface [m] (positive down). */
    double depth_m = 0;
    /** The vehicle's altitude over the seabed [m], NaN when not measured. */
    double altitude_m = std::numeric_limits<double>::quiet_NaN();
    /** The pressure sensor's pose on the vehicle (the depth is of the vehicle's reference
     *  point, already corrected for it). */
    mrpt::poses::CPose3D sensorPose;

    /** The largest depth [m] semloc accepts (the deepest trench, with margin). */
    static constexpr double kMaxDepth_m = 12000;
    /** "" when the reading can be used: a finite depth in [-100, kMaxDepth_m] m (a vehicle
     *  at the surface may read slightly negative) and an altitude that is NaN or finite in
     *  [0, kMaxDepth_m]; else what is wrong, e.g. "its depth_m nan is not finite". */
    std::string problem() const;

    /** The pressure sensor's pose on the vehicle (sensorPose). */
    void getSensorPose(mrpt::poses::CPose3D& out_sensorPose) const override
    {
        out_sensorPose = sensorPose;
    }
    /** Sets the pressure sensor's pose on the vehicle (sensorPose). */
    void setSensorPose(const mrpt::poses::CPose3D& newSensorPose) override
    {
        sensorPose = newSensorPose;
    }
    /** Human-readable dump (rawlog-edit --describe). */
    void getDescriptionAsText(std::ostream& o) const override;
    /** Text export (rawlog-edit --export-txt): depth and altitude. */
    bool exportTxtSupported() const override { return true; }
    std::string exportTxtHeader() const override;
    std::string exportTxtDataRow() const override;
};

}  // namespace semloc
