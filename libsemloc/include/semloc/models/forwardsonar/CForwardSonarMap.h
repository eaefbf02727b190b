/* semloc — the forward-looking sonar's object detections: slant range and bearing in a fan, no
 * elevation (docs/design.md, "The detector models"). */
#pragma once

#include <semloc/models/detector/CObjectDetectorMap.h>
#include <semloc/models/detector/FanOptions.h>

namespace semloc
{
/** The forward-looking sonar model (`[MetricMap] forwardSonarMap_count = 1`): an object is
 *  seen within the fan (bearing within half `fov_deg`, depression within half
 *  `vertical_fov_deg` about `tilt_deg`) and the range window; a detection reports its slant
 *  range and bearing, no elevation, and its density is the range's Gaussian (with the
 *  misread-range mixture) times the bearing's. Clutter is uniform over the fan
 *  (V = (max_range_m - min_range_m) fov). With `range_kind = slant` (the default) this is
 *  also the range-bearing detector in the water column. */
class CForwardSonarMap : public CObjectDetectorMap
{
    DEFINE_SERIALIZABLE(CForwardSonarMap, semloc)

public:
    /** The shared keys and the fan's, with this kind's defaults. */
    struct TLikelihoodOptions : public TFanDetectorOptions
    {
        TLikelihoodOptions();
    };
    TLikelihoodOptions likelihoodOptions;

    const TDetectorParam& detectorParam() const override { return likelihoodOptions.detector; }
    void scoreScan(const TScan& scan, const mrpt::math::TPose2D* poses, size_t n,
                   double* out) const override;
    std::vector<TInView> inView(const TScan& scan, const mrpt::math::TPose2D& pose) const override;
    bool measuresRange() const override { return true; }
    bool measuresBearing() const override { return true; }

    MAP_DEFINITION_START(CForwardSonarMap)
    std::string world_file;
    TLikelihoodOptions likelihoodOpts;
    MAP_DEFINITION_END(CForwardSonarMap)

protected:
    bool validDetection(const TSemanticDetection& d) const override;
    double measurementVolume() const override;
};

}  // namespace semloc
