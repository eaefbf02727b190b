/* semloc tests and benchmarks — an ideal sonar: ranges cast by RayCaster from a pose. */
#pragma once

#include <mrpt/math/TPose2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <semloc/models/structure/RayCaster.h>

#include <cmath>
#include <cstddef>

namespace semloc::test
{
/** A noise-free planar scan from `pose` (sensor at the vehicle origin): `nBeams` beams over
 *  `aperture_rad` centred ahead, right to left like MRPT's getScanAngle(); beams that hit
 *  nothing read `maxRange_m` and are valid (max-range readings). */
inline mrpt::obs::CObservation2DRangeScan simulateScan(const RayCaster& caster,
                                                       const mrpt::math::TPose2D& pose,
                                                       size_t nBeams = 60, double maxRange_m = 20,
                                                       double aperture_rad = M_PI)
{
    mrpt::obs::CObservation2DRangeScan scan;
    scan.sensorLabel = "SONAR";
    scan.aperture = static_cast<float>(aperture_rad);
    scan.maxRange = static_cast<float>(maxRange_m);
    scan.rightToLeft = true;
    scan.resizeScan(nBeams);
    for (size_t i = 0; i < nBeams; i++)
    {
        const double a = nBeams > 1 ? -0.5 * aperture_rad + aperture_rad * static_cast<double>(i) /
                                                                static_cast<double>(nBeams - 1)
                                    : 0.0;
        const double r = caster.cast(pose.x, pose.y, pose.phi + a, maxRange_m);
        scan.setScanRange(i, static_cast<float>(r));
        scan.setScanRangeValidity(i, true);
    }
    return scan;
}

}  // namespace semloc::test
