/* semloc — the AUV's simulated sensors of one run (private; options in AuvSensorModels.h). */
#pragma once

#include <mrpt/core/Clock.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/simulator/AuvSensorModels.h>
#include <semloc/world/World.h>

#include <cstdint>
#include <string>
#include <vector>

namespace semloc::detail
{
/** The AUV sensors' random streams, one each (SimRandom.h). */
struct AuvStreams
{
    explicit AuvStreams(uint32_t seed);
    mrpt::random::CRandomGenerator depth, compass, usbl, dvl, sidescan, fls, camera;
};

/** The AUV's sensors of a run: the DVL's odometry, and each step's depth, compass, fix and
 *  detector observations appended to the frame in that order (the depth first, so that the
 *  detector models see it before the scans of its frame). */
class AuvSensors
{
public:
    AuvSensors(const World& world, const TAuvSensorOptions& options);
    /** True when the odometry is the DVL's. */
    bool dvl() const { return m_o.dvl.enabled; }
    /** The DVL's measurement of the true body-frame `increment`. */
    mrpt::obs::CActionRobotMovement2D measureDvl(const mrpt::poses::CPose2D& increment,
                                                 mrpt::random::CRandomGenerator& rng) const;
    /** Appends step k's observations at the true `pose` to `frame`; returns the detections
     *  made (false alarms included). */
    size_t measure(size_t k, const mrpt::math::TPose2D& pose, mrpt::Clock::time_point stamp,
                   AuvStreams& rng, mrpt::obs::CSensoryFrame& frame) const;

private:
    size_t detect(const TObjectDetectorSimOptions& o, const mrpt::math::TPose2D& pose,
                  mrpt::Clock::time_point stamp, mrpt::random::CRandomGenerator& rng,
                  mrpt::obs::CSensoryFrame& frame) const;

    TAuvSensorOptions m_o;
    struct TObject
    {
        double x, y, z;
        std::string label;
    };
    std::vector<TObject> m_objects;
    std::vector<std::string> m_labels;
};
}  // namespace semloc::detail
