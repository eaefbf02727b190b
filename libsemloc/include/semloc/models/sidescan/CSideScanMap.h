/* semloc — the side-scan sonar's object detections: an object reported abeam, on the port or
 * starboard side, at a slant range within the swath (docs/design.md, "The detector models"). */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <semloc/models/detector/CObjectDetectorMap.h>

namespace semloc
{
/** The side-scan model (`[MetricMap] sideScanMap_count = 1`).
 *
 *  A side-scan sonar looks to both sides in a thin fan across the vehicle's track: an object
 *  is seen when it is abeam (its along-track angle, asin(along / slant range), within half
 *  `beam_width_deg`), outside the nadir gap (its across-track distance on the seabed at least
 *  `nadir_gap_m`) and within the range window. A detection reports its side (the sign of its
 *  bearing: > 0 port, < 0 starboard; the import writes +-90 deg) and its slant range; its
 *  density given an object on that side is the range's Gaussian (with the misread-range
 *  mixture), 0 on the other side. Clutter is uniform over both sides' range windows
 *  (V = 2 (max_range_m - min_range_m)). */
class CSideScanMap : public CObjectDetectorMap
{
    DEFINE_SERIALIZABLE(CSideScanMap, semloc)

public:
    struct TLikelihoodOptions : public mrpt::config::CLoadableOptions
    {
        TLikelihoodOptions();
        /** The keys every detector kind shares. */
        TDetectorParam detector;
        /** The fan's along-track width [deg] (an object within half of it either way is
         *  abeam). */
        double beam_width_deg = 4;
        /** The across-track distance on the seabed below which nothing is seen [m]. */
        double nadir_gap_m = 3;
        void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                                const std::string& section) override;
        void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                              const std::string& section) const override;
    };
    TLikelihoodOptions likelihoodOptions;

    const TDetectorParam& detectorParam() const override { return likelihoodOptions.detector; }
    void scoreScan(const TScan& scan, const mrpt::math::TPose2D* poses, size_t n,
                   double* out) const override;
    std::vector<TInView> inView(const TScan& scan, const mrpt::math::TPose2D& pose) const override;
    bool measuresRange() const override { return true; }
    bool measuresBearing() const override { return false; }

    MAP_DEFINITION_START(CSideScanMap)
    std::string world_file;
    TLikelihoodOptions likelihoodOpts;
    MAP_DEFINITION_END(CSideScanMap)

protected:
    bool validDetection(const TSemanticDetection& d) const override;
    double measurementVolume() const override;
};

}  // namespace semloc
