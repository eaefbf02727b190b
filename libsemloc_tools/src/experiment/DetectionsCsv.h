/* semloc — detections.csv: what each semantic detection of a run did to the weights, at the
 * estimate and at the true pose (private). */
#pragma once

#include <mrpt/obs/CSensoryFrame.h>
#include <semloc/filter/StepRecord.h>
#include <semloc/models/semantic/CSemanticMap.h>

#include <fstream>
#include <string>

namespace semloc::detail
{
/** detections.csv, written while the run goes: one row per detection of each frame's
 *  CObservationSemantic that the semantic map uses,
 *
 *      step,t,k,label,range_m,bearing_deg,est_object,est_d2,est_gain,gt_object,gt_d2,gt_gain
 *
 *  - `k`: the detection's index in its observation;
 *  - `*_gain` [nats]: log p(z | x) - log p(z without detection k | x) at x = the step's
 *    estimate (est_) or true pose (gt_): what this detection adds to the weight of a particle
 *    there. A detection whose est_gain is far above its gt_gain pulls the weight from the
 *    truth to the estimate;
 *  - `*_object`: the id of the map object it is most like there: among the objects in view
 *    that the likelihood may associate it with (CSemanticMap::candidatesOf), the one of
 *    smallest d2 = ((range - predicted) / sigma_range_m)² + ((bearing - predicted) /
 *    sigma_bearing_deg)² (the nearest in measurement space; the model's own association
 *    weighs clutter and the other detections too); empty with none in view;
 *  - gt_* empty for a step without ground truth.
 *  Frames without a semantic observation write nothing. */
class DetectionsCsv
{
public:
    /** Writes the header to `path`; `map` scores the detections (the run's semantic map). */
    DetectionsCsv(const std::string& path, const CSemanticMap& map);
    /** The detections of step `r`'s frame `sf`. */
    void add(const TStepRecord& r, const mrpt::obs::CSensoryFrame& sf);
    /** Closes the file; throws naming it if a write failed. */
    void finish();

private:
    /** The columns object,d2,gain of detection k of `obs` at `pose`. */
    std::string explain(const CObservationSemantic& obs, size_t k,
                        const mrpt::math::TPose2D& pose) const;

    std::string m_path;
    std::ofstream m_out;
    const CSemanticMap& m_map;
};
}  // namespace semloc::detail
