/* semloc — import MRPT landmark datasets (simul-landmarks) as semantic datasets. */
#pragma once

#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CRawlog.h>
#include <semloc/dataset/LandmarkSet.h>
#include <semloc/observation/CObservationSemantic.h>
#include <semloc/world/World.h>

#include <string>
#include <vector>

namespace semloc
{
/** Conversions from MRPT's landmark datasets (as written by MRPT's `simul-landmarks`:
 *  `CObservationBearingRange` rawlogs, a landmark file and a robot-path file) to semloc's
 *  formats, so semloc-localize runs on them directly. */
class LandmarkImport
{
public:
    /** Checks semloc-import-landmarks' options before any work: throws "--label: ..." if
     *  `label` is not a label a world file takes (labelProblem(): one word of 1 to
     *  kMaxLabelLength bytes without blanks), "--margin M: ..." if `margin_m` is not a
     *  finite number in [0, kMaxWorldCoordinate_m]. */
    static void checkOptions(const std::string& label, double margin_m);

    /** One `CObservationBearingRange` as a semantic observation: every measurement becomes
     *  a detection with `label`, its range and yaw, confidence 1 and `object_id` = the
     *  landmark ID (-1 when the sensor does not identify landmarks). A zero
     *  fieldOfView_yaw (MRPT's "no limit") becomes 2*pi. */
    static CObservationSemantic toSemantic(const mrpt::obs::CObservationBearingRange& obs,
                                           const std::string& label);

    /** Replaces, in place, every CObservationBearingRange of the rawlog's sensory frames by
     *  its semantic twin (sensor label SEMANTIC). Returns how many were converted. Throws
     *  "--label: ..." for a label checkOptions() refuses. */
    static size_t convertRawlog(mrpt::obs::CRawlog& log, const std::string& label);

    /** Reads simul-landmarks' landmark file (rows `x y z ... id`, the id in the last
     *  column: decimal digits, as simul-landmarks writes it; `0x10` or `1e3`, which read as
     *  numbers, are refused) into point objects, one row in memory at a time. Throws naming
     *  the file and line on a malformed row, and "--label: ..." for a label checkOptions()
     *  refuses. */
    static std::vector<WorldObject> readLandmarks(const std::string& path,
                                                  const std::string& label);
    /** readLandmarks() into a LandmarkSet (40 bytes a landmark; the file is read twice, its
     *  rows counted first). */
    static LandmarkSet readLandmarkSet(const std::string& path, const std::string& label);

    /** Reads a robot-path file (rows `x y z yaw pitch roll`, lines starting with % or #
     *  ignored), returning (x, y, yaw) per row. Throws naming the file and line. */
    static std::vector<mrpt::math::TPose2D> readPath(const std::string& path);

    /** A world of the landmarks; bounds = box of landmarks and path, grown by `margin_m`.
     *  Throws "--margin M: ..." if the bounds would reach beyond kMaxWorldCoordinate_m, and
     *  "the world ... would not load: <the world loader's message>" for anything else the
     *  world loader refuses: what makeWorld returns, World::saveToFile writes and semloc
     *  reads back. The landmarks become the world's objects (moved in: pass an rvalue to
     *  keep one copy of a large map); the check streams the world's text (memory beyond
     *  the world: its ids and centres). */
    static World makeWorld(std::vector<WorldObject> landmarks,
                           const std::vector<mrpt::math::TPose2D>& path, double margin_m,
                           const std::string& name);
    /** makeWorld() of the landmarks of a set without its objects (its name and bounds),
     *  checked with them: World::saveToFile(file, landmarks.objectList()) writes the world
     *  makeWorld() makes, without ever holding its objects. */
    static World makeWorldFrame(const LandmarkSet& landmarks,
                                const std::vector<mrpt::math::TPose2D>& path, double margin_m,
                                const std::string& name);

    /** Timestamps [s] of the rawlog's sensory frames, in order (from their first
     *  observation). */
    static std::vector<double> frameTimes(const mrpt::obs::CRawlog& log);

    /** Writes the `t x y phi` ground-truth file: row i pairs frame i's timestamp with path
     *  row i (simul-landmarks records the pose of each frame before moving). Throws if the
     *  path has fewer rows than there are frames, and "cannot write 'FILE': REASON" if the
     *  file cannot be written. */
    static void writeGroundTruth(const std::vector<double>& times,
                                 const std::vector<mrpt::math::TPose2D>& path,
                                 const std::string& outPath);
};

}  // namespace semloc
