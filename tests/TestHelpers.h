/* semloc tests — shared helpers: a small world and an ideal/noisy semantic detector. */
#pragma once

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/random/RandomGenerators.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/io/Interrupt.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/observation/CObservationSemantic.h>
#include <semloc/world/World.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace semloc::test
{
/** One step's odometry: the increment `u` with MRPT's default Gaussian motion model. */
inline mrpt::obs::CActionCollection gaussianOdometry(const mrpt::poses::CPose2D& u)
{
    mrpt::obs::CActionRobotMovement2D act;
    mrpt::obs::CActionRobotMovement2D::TMotionModelOptions mo;
    mo.modelSelection = mrpt::obs::CActionRobotMovement2D::mmGaussian;
    act.computeFromOdometry(u, mo);
    mrpt::obs::CActionCollection acts;
    acts.insert(act);
    return acts;
}

/** An ini file in memory holding `text`. */
inline mrpt::config::CConfigFileMemory iniText(const std::string& text)
{
    mrpt::config::CConfigFileMemory c;
    c.setContent(text);
    return c;
}

/** The ini file at `p` with its bases resolved, as one text (semloc::config::readIniText): a
 *  shipped configuration to change with withKeys() and write elsewhere. */
inline std::string resolvedIni(const std::filesystem::path& p)
{
    return semloc::config::readIniText(p.string());
}

/** The whole file at `p`, byte for byte (empty when it cannot be read). */
inline std::string readText(const std::filesystem::path& p)
{
    std::ifstream f(p, std::ios::binary);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

/** The ini `text` (read from `name`) with the line of each key of `keys` (the first line
 *  that starts with the key and a blank or '=') replaced by `key = value`; a key it does not
 *  have fails the test. */
inline std::string withKeys(const std::string& text, const std::string& name,
                            std::vector<std::pair<std::string, std::string>> keys)
{
    std::istringstream in(text);
    std::string line, out;
    while (std::getline(in, line))
    {
        for (auto it = keys.begin(); it != keys.end(); ++it)
        {
            if (line.rfind(it->first + " ", 0) == 0 || line.rfind(it->first + "=", 0) == 0)
            {
                line = it->first + " = " + it->second;
                keys.erase(it);
                break;
            }
        }
        out += line + "\n";
    }
    EXPECT_TRUE(keys.empty()) << keys.front().first << " is not in " << name;
    return out;
}

/** steps.csv without the update_us column, the 14th (the only one that may differ between
 *  runs). */
inline std::string stepsWithoutTiming(const std::filesystem::path& dir)
{
    std::istringstream in(readText(dir / "steps.csv"));
    std::string line, out;
    while (std::getline(in, line))
    {
        size_t begin = 0;
        for (int k = 0; k < 13; k++)
        {
            begin = line.find(',', begin) + 1;
        }
        const size_t end = line.find(',', begin);
        EXPECT_NE(end, std::string::npos) << line;
        out += line.substr(0, begin) + line.substr(end + 1) + "\n";
    }
    return out;
}

/** A 30 x 30 m world with 12 objects in 4 labels, some labels repeated. */
inline World smallWorld()
{
    return World::FromText(R"(
name: small
bounds: {x_min: 0, x_max: 30, y_min: 0, y_max: 30}
objects:
  - {id: 1, label: wellhead, shape: box, center: [5, 5], size: [1, 1]}
  - {id: 2, label: pillar,   shape: cylinder, center: [12, 4], radius: 0.4}
  - {id: 3, label: pillar,   shape: cylinder, center: [20, 6], radius: 0.4}
  - {id: 4, label: anchor,   shape: point, center: [26, 3]}
  - {id: 5, label: wreck,    shape: polygon, points: [[4, 14], [7, 14], [6, 17]]}
  - {id: 6, label: pillar,   shape: cylinder, center: [15, 15], radius: 0.4}
  - {id: 7, label: wellhead, shape: box, center: [24, 14], size: [1, 1]}
  - {id: 8, label: anchor,   shape: point, center: [10, 22]}
  - {id: 9, label: wreck,    shape: polygon, points: [[18, 23], [21, 23], [20, 26]]}
  - {id: 10, label: pillar,  shape: cylinder, center: [27, 25], radius: 0.4}
  - {id: 11, label: wellhead, shape: box, center: [3, 27], size: [1, 1]}
  - {id: 12, label: anchor,  shape: point, center: [14, 9]}
)",
                           "smallWorld");
}

/** A detection of `label` at range `r` [m] and bearing `b` [rad]; `id` -1: no object id. */
inline TSemanticDetection detection(const std::string& label, double r, double b, int id = -1)
{
    TSemanticDetection d;
    d.label = label;
    d.range_m = r;
    d.bearing_rad = b;
    d.object_id = id;
    return d;
}

/** Detector settings for the test observations. */
struct DetectorSim
{
    double maxRange_m = 12;
    double fov_rad = 2 * M_PI / 3;
    double sigma_range_m = 0;
    double sigma_bearing_rad = 0;
    bool reportIds = false;
};

/** Ideal detector (plus optional Gaussian noise): every map object in range and FOV. */
inline CObservationSemantic observe(const World& w, const mrpt::math::TPose2D& pose,
                                    const DetectorSim& d = {},
                                    mrpt::random::CRandomGenerator* rng = nullptr)
{
    CObservationSemantic obs;
    obs.sensorLabel = "SEMANTIC";
    obs.maxRange_m = d.maxRange_m;
    obs.fov_rad = d.fov_rad;
    for (const auto& o : w.objects)
    {
        const double dx = o.center.x - pose.x, dy = o.center.y - pose.y;
        const double r = std::hypot(dx, dy);
        const double b = mrpt::math::wrapToPi(std::atan2(dy, dx) - pose.phi);
        if (r > d.maxRange_m || std::abs(b) > 0.5 * d.fov_rad)
        {
            continue;
        }
        TSemanticDetection det;
        det.label = o.label;
        det.range_m = r;
        det.bearing_rad = b;
        if (rng)
        {
            det.range_m = std::max(0.0, r + rng->drawGaussian1D(0, d.sigma_range_m));
            det.bearing_rad = b + rng->drawGaussian1D(0, d.sigma_bearing_rad);
        }
        det.object_id = d.reportIds ? o.id : -1;
        if (obs.isValid(det))
        {
            obs.detections.push_back(det);
        }
    }
    return obs;
}

/** The message of the exception `f` throws, as the apps print it ("" if none). */
template <typename F>
std::string errorOf(F&& f)
{
    try
    {
        f();
    }
    catch (const std::exception& e)
    {
        return semloc::errorMessage(e);
    }
    return "";
}

/** A progress callback (done, total) for a long job that records the last `done` in `seen`
 *  and asks the job to stop (semloc::requestInterrupt) when it reaches `at`: Ctrl-C at a
 *  known point. */
inline std::function<void(size_t, size_t)> interruptAt(size_t at, size_t& seen)
{
    return [at, &seen](size_t done, size_t)
    {
        seen = done;
        if (done == at)
        {
            semloc::requestInterrupt();
        }
    };
}

/** The bytes `o` takes in an MRPT archive (CArchive::WriteObject). */
inline std::string archiveBytes(const mrpt::serialization::CSerializable& o)
{
    mrpt::io::CMemoryStream mem;
    mrpt::serialization::archiveFrom(mem).WriteObject(&o);
    return std::string(static_cast<const char*>(mem.getRawBufferData()), mem.getTotalBytesCount());
}

/** Offset in `bytes` of the first of the three flags of a serialized map's
 *  mrpt::maps::TMapGenericParams (after its class name and version byte), or npos. */
inline size_t genericMapFlagsAt(const std::string& bytes)
{
    const std::string params = "TMapGenericParams";
    const size_t at = bytes.find(params);
    return at == std::string::npos ? at : at + params.size() + 1;
}

/** The message of reading `bytes` into `target` from an MRPT archive ("" if it reads). */
inline std::string readArchiveInto(const std::string& bytes,
                                   mrpt::serialization::CSerializable& target)
{
    mrpt::io::CMemoryStream in;
    in.assignMemoryNotOwn(bytes.data(), bytes.size());
    return errorOf([&] { mrpt::serialization::archiveFrom(in).ReadObject(&target); });
}
}  // namespace semloc::test
