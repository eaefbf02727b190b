/* semloc — the pieces of SensorModelCalibration's fits (private). */
#pragma once

#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <semloc/calibration/SensorCalibration.h>
#include <semloc/calibration/SensorModelCalibration.h>
#include <semloc/dataset/GroundTruthFile.h>
#include <semloc/models/compass/CCompassMap.h>
#include <semloc/models/fix/CPoseFixMap.h>

#include <cstddef>
#include <string>
#include <vector>

#include "calibration/IniText.h"

namespace semloc::detail
{
/** A fit of `value` from `n` samples: TooLittleData below `minSamples`, else clamped into
 *  [lo, hi] (Clamped when it was moved). */
TCalibrationFit fitValue(double value, size_t n, double ci95, const std::string& method,
                         size_t minSamples, double lo, double hi);

/** The integrated autocorrelation time of the series `x` in samples: 1 + 2 sum of its
 *  autocorrelations (about its mean) from lag 1 to the first that is not positive, at most
 *  `maxLag`; 1 for a series of fewer than 3 samples or without spread. */
double autocorrelationTime(const std::vector<double>& x, size_t maxLag);

/** The compass's heading residuals, in time order. */
struct CompassFit
{
    const CCompassMap* map = nullptr;
    TModelFits out;
    std::vector<double> e;

    void add(const mrpt::obs::CObservationIMU& imu, const GroundTruthRow& truth);

    void fit();
};

/** The fixes' residuals. */
struct FixFit
{
    const CPoseFixMap* map = nullptr;
    TModelFits out;
    std::vector<double> ex, ey;

    void add(const mrpt::obs::CObservationRobotPose& fix, const GroundTruthRow& truth);

    void fit();
};

/** The DVL motion model's per-metre noise. */
struct DvlFit
{
    TModelFits out;
    double sumXY = 0, sumPhi = 0;
    size_t n = 0;
    bool havePrevious = false;
    GroundTruthRow previous;

    void add(const mrpt::obs::CActionRobotMovement2D& move, const GroundTruthRow* truth);

    void fit();
};
}  // namespace semloc::detail
