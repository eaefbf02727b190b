/* semloc — a camera's object detections: a bearing within a field of view, no range
 * (docs/design.md, "The detector models"). */
#pragma once

#include <semloc/models/detector/CObjectDetectorMap.h>
#include <semloc/models/detector/FanOptions.h>

namespace semloc
{
/** The bearing-only camera model (`[MetricMap] bearingCameraMap_count = 1`): an object is
 *  seen within the field of view (bearing within half `fov_deg`, depression within half
 *  `vertical_fov_deg` about `tilt_deg`) and the visibility window (`min_range_m` to
 *  `max_range_m`, slant or horizontal); a detection reports its bearing alone (its range is
 *  not read: NaN or anything), with the bearing's Gaussian density. Clutter is uniform over
 *  the field of view (V = fov). */
class CBearingCameraMap : public CObjectDetectorMap
{
    DEFINE_SERIALIZABLE(CBearingCameraMap, semloc)

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
    bool measuresRange() const override { return false; }
    bool measuresBearing() const override { return true; }

    MAP_DEFINITION_START(CBearingCameraMap)
    std::string world_file;
    TLikelihoodOptions likelihoodOpts;
    MAP_DEFINITION_END(CBearingCameraMap)

protected:
    bool validDetection(const TSemanticDetection& d) const override;
    double measurementVolume() const override;
};

}  // namespace semloc
