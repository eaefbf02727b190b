/* semloc — CObservationDepth: serialization, checks and text output. */
#include <mrpt/core/format.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/observation/CObservationDepth.h>

#include <cmath>
#include <ostream>

#include "io/BoundedRead.h"

IMPLEMENTS_SERIALIZABLE(CObservationDepth, CObservation, semloc)

namespace semloc
{
std::string CObservationDepth::problem() const
{
    if (!std::isfinite(depth_m))
    {
        return mrpt::format("its depth_m %g is not finite", depth_m);
    }
    if (depth_m < -100 || depth_m > kMaxDepth_m)
    {
        return mrpt::format("its depth_m %g is outside [-100, %g]", depth_m, kMaxDepth_m);
    }
    if (!std::isnan(altitude_m) && !(altitude_m >= 0 && altitude_m <= kMaxDepth_m))
    {
        return mrpt::format("its altitude_m %g is neither NaN (none) nor in [0, %g]", altitude_m,
                            kMaxDepth_m);
    }
    return {};
}

uint8_t CObservationDepth::serializeGetVersion() const
{
    return 0;
}

void CObservationDepth::serializeTo(mrpt::serialization::CArchive& out) const
{
    if (sensorLabel.size() > detail::kMaxSerializedString)
    {
        THROW_EXCEPTION_FMT(
            "CObservationDepth: cannot write a sensor label of %zu bytes (the readers take at "
            "most %zu)",
            sensorLabel.size(), static_cast<size_t>(detail::kMaxSerializedString));
    }
    out << sensorLabel << timestamp;
    out << sensorPose.x() << sensorPose.y() << sensorPose.z() << sensorPose.yaw()
        << sensorPose.pitch() << sensorPose.roll();
    out << depth_m << altitude_m;
}

void CObservationDepth::serializeFrom(mrpt::serialization::CArchive& in, uint8_t version)
{
    switch (version)
    {
        case 0:
        {
            detail::readString(in, sensorLabel, "CObservationDepth sensor label");
            in >> timestamp;
            double x, y, z, yaw, pitch, roll;
            in >> x >> y >> z >> yaw >> pitch >> roll;
            sensorPose = mrpt::poses::CPose3D(x, y, z, yaw, pitch, roll);
            in >> depth_m >> altitude_m;
        }
        break;
        default:
            MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
    }
}

void CObservationDepth::getDescriptionAsText(std::ostream& o) const
{
    CObservation::getDescriptionAsText(o);
    o << "Sensor pose on the vehicle: " << sensorPose << "\n";
    o << mrpt::format("Depth: %.3f m\n", depth_m);
    if (std::isnan(altitude_m))
    {
        o << "Altitude: not measured\n";
    }
    else
    {
        o << mrpt::format("Altitude: %.3f m\n", altitude_m);
    }
}

std::string CObservationDepth::exportTxtHeader() const
{
    return "DEPTH_M ALTITUDE_M";
}

std::string CObservationDepth::exportTxtDataRow() const
{
    return mrpt::format("%.6f %.6f", depth_m, altitude_m);
}

}  // namespace semloc
