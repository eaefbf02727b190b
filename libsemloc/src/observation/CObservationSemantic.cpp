/* semloc — CObservationSemantic: serialization and text output. */
#include <mrpt/core/format.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/datetime.h>
#include <semloc/observation/CObservationSemantic.h>
#include <semloc/observation/Labels.h>

#include <cmath>
#include <ostream>

#include "io/BoundedRead.h"

IMPLEMENTS_SERIALIZABLE(CObservationSemantic, CObservation, semloc)

namespace semloc
{
namespace
{
/** Upper bound on detections per scan accepted from a file: a corrupted count
 *  must not make us allocate gigabytes. */
constexpr uint32_t kMaxSerializedDetections = 1u << 20;
}  // namespace

// Every label a writer accepts (labelLengthProblem) is read back (readString).
static_assert(kMaxLabelLength <= detail::kMaxSerializedString,
              "the readers must take the longest label the writers write");

uint8_t CObservationSemantic::serializeGetVersion() const
{
    return 0;
}

void CObservationSemantic::serializeTo(mrpt::serialization::CArchive& out) const
{
    // Nothing the readers (serializeFrom) would refuse: checked before the first byte.
    if (sensorLabel.size() > detail::kMaxSerializedString)
    {
        THROW_EXCEPTION_FMT(
            "CObservationSemantic: cannot write a sensor label of %zu bytes (the readers take "
            "at most %zu)",
            sensorLabel.size(), static_cast<size_t>(detail::kMaxSerializedString));
    }
    if (detections.size() > kMaxSerializedDetections)
    {
        THROW_EXCEPTION_FMT(
            "CObservationSemantic: cannot write %zu detections (the readers take at most %u)",
            detections.size(), static_cast<unsigned>(kMaxSerializedDetections));
    }
    for (size_t i = 0; i < detections.size(); i++)
    {
        if (const std::string p = labelLengthProblem(detections[i].label); !p.empty())
        {
            THROW_EXCEPTION_FMT("CObservationSemantic: cannot write detection %zu: its %s", i,
                                p.c_str());
        }
    }
    out << sensorLabel << timestamp;
    out << sensorPose.x() << sensorPose.y() << sensorPose.z() << sensorPose.yaw()
        << sensorPose.pitch() << sensorPose.roll();
    out << maxRange_m << fov_rad;
    out.WriteAs<uint32_t>(detections.size());
    for (const auto& d : detections)
    {
        out << d.label << d.range_m << d.bearing_rad << d.confidence << d.object_id;
    }
}

void CObservationSemantic::serializeFrom(mrpt::serialization::CArchive& in, uint8_t version)
{
    switch (version)
    {
        case 0:
        {
            detail::readString(in, sensorLabel, "CObservationSemantic sensor label");
            in >> timestamp;
            double x, y, z, yaw, pitch, roll;
            in >> x >> y >> z >> yaw >> pitch >> roll;
            sensorPose = mrpt::poses::CPose3D(x, y, z, yaw, pitch, roll);
            in >> maxRange_m >> fov_rad;
            const uint32_t n =
                detail::readCount(in, kMaxSerializedDetections, "CObservationSemantic detections");
            detections.clear();
            for (uint32_t i = 0; i < n; i++)
            {
                TSemanticDetection d;
                detail::readString(in, d.label, "CObservationSemantic detection label");
                in >> d.range_m >> d.bearing_rad >> d.confidence >> d.object_id;
                detections.push_back(std::move(d));
            }
            break;
        }
        default:
            MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
    }
}

void CObservationSemantic::getDescriptionAsText(std::ostream& o) const
{
    CObservation::getDescriptionAsText(o);
    o << "Sensor pose on the vehicle: " << sensorPose << "\n";
    o << mrpt::format("Max range: %.3f m, field of view: %.2f deg\n", maxRange_m,
                      fov_rad * 180.0 / M_PI);
    o << "Detections: " << detections.size() << "\n";
    if (!detections.empty())
    {
        o << mrpt::format("  %-3s %-16s %10s %12s %10s %9s %s\n", "#", "label", "range_m",
                          "bearing_deg", "confidence", "object_id", "");
    }
    for (size_t i = 0; i < detections.size(); i++)
    {
        const auto& d = detections[i];
        o << mrpt::format("  %-3u %-16s %10.3f %12.3f %10.3f %9d %s\n", static_cast<unsigned>(i),
                          d.label.c_str(), d.range_m, d.bearing_rad * 180.0 / M_PI, d.confidence,
                          d.object_id, isValid(d) ? "" : "(invalid)");
    }
}

std::string CObservationSemantic::exportTxtHeader() const
{
    return mrpt::format("%14s %14s %14s %8s %16s %14s %14s %12s %10s", "MAX_RANGE_M", "FOV_RAD",
                        "SENSOR_YAW_RAD", "N_DET", "LABEL_i", "RANGE_M_i", "BEARING_RAD_i",
                        "CONFIDENCE_i", "OBJ_ID_i");
}

std::string CObservationSemantic::exportTxtDataRow() const
{
    std::string row = mrpt::format("%14.6f %14.6f %14.6f %8u", maxRange_m, fov_rad,
                                   sensorPose.yaw(), static_cast<unsigned>(detections.size()));
    for (const auto& d : detections)
    {
        // Labels are written verbatim; blanks would break the columns, so they become '_'.
        std::string label = d.label.empty() ? std::string("-") : d.label;
        for (auto& c : label)
        {
            if (std::isspace(static_cast<unsigned char>(c)))
            {
                c = '_';
            }
        }
        row += mrpt::format(" %16s %14.6f %14.6f %12.4f %10d", label.c_str(), d.range_m,
                            d.bearing_rad, d.confidence, d.object_id);
    }
    return row;
}

}  // namespace semloc
