/* A small landmark log as MRPT's simul-landmarks writes it, shared by the tests of the
 * landmark import. */
#pragma once

#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>

namespace semloc::test
{
/** 3 sensory frames, at t = 1, 2, 3 s, of a CObservationBearingRange (10 m) seeing landmarks
 *  1 and 2 (ranges 4 and 5 m, bearings 0.1 and 0.2 rad). */
inline mrpt::obs::CRawlog landmarkLog()
{
    mrpt::obs::CRawlog log;
    for (int k = 0; k < 3; k++)
    {
        auto o = mrpt::obs::CObservationBearingRange::Create();
        o->timestamp = mrpt::Clock::fromDouble(1.0 + k);
        o->maxSensorDistance = 10;
        for (int id = 1; id <= 2; id++)
        {
            mrpt::obs::CObservationBearingRange::TMeasurement m;
            m.range = 3.0f + static_cast<float>(id);
            m.yaw = 0.1f * static_cast<float>(id);
            m.pitch = 0;
            m.landmarkID = id;
            o->sensedData.push_back(m);
        }
        mrpt::obs::CSensoryFrame sf;
        sf.insert(o);
        log.insert(sf);
    }
    return log;
}
}  // namespace semloc::test
