/* semloc — the ground-truth file of a rawlog: `t x y phi` per line. */
#pragma once

#include <mrpt/math/TPose2D.h>

#include <string>
#include <vector>

namespace semloc
{
/** The true vehicle pose when one step's observations were taken. */
struct GroundTruthRow
{
    /** Time [s] (the step's timestamp, mrpt::Clock::toDouble). */
    double t = 0;
    /** Pose x [m]. */
    double x = 0;
    /** Pose y [m]. */
    double y = 0;
    /** Pose heading [rad], in [-pi, pi]. */
    double phi = 0;
    /** The pose as an MRPT TPose2D. */
    mrpt::math::TPose2D pose() const { return {x, y, phi}; }
};

/** The poses of `rows`, in order. */
inline std::vector<mrpt::math::TPose2D> posesOf(const std::vector<GroundTruthRow>& rows)
{
    std::vector<mrpt::math::TPose2D> poses;
    poses.reserve(rows.size());
    for (const auto& r : rows)
    {
        poses.push_back(r.pose());
    }
    return poses;
}

/** The ground truth of a dataset as semloc-simulate, semloc-import and
 *  semloc-import-landmarks write it and semloc-localize and semloc-calibrate read it: one pose
 *  `t x y phi` per line, times increasing. */
class GroundTruthFile
{
public:
    /** `<dir>/<stem>_gt.txt` for `<dir>/<stem>.rawlog` (any extension). */
    static std::string PathFor(const std::string& rawlogPath);
    /** Reads a ground-truth file (lines `t x y phi`; `#` or `%` comments and blank lines
     *  skipped). Throws "file:line: ..." on a row without exactly 4 columns, a cell that is
     *  not a finite number, or a time not after the previous row's; and on a file without
     *  rows. */
    static std::vector<GroundTruthRow> Read(const std::string& path);
    /** Writes `rows` as the `t x y phi` file Read() reads (numbers exactly); throws "cannot
     *  write 'PATH': REASON" on an error. */
    static void Write(const std::vector<GroundTruthRow>& rows, const std::string& path);
    /** True when Read() reads `path` without an error. */
    static bool IsGroundTruthFile(const std::string& path);
};
}  // namespace semloc
