/* semloc — a ground-truth path, matched to filter steps by timestamp. */
#pragma once

#include <semloc/dataset/GroundTruthFile.h>

#include <string>
#include <vector>

namespace semloc
{
/** The true poses of a dataset (`t x y phi` rows, docs/design.md), looked up by time. */
class GroundTruth
{
public:
    GroundTruth() = default;
    /** The rows, by strictly increasing time; throws on a non-finite value or a time not
     *  after the previous row's (never re-ordered: a jumbled file is an error). */
    explicit GroundTruth(std::vector<GroundTruthRow> rows);
    /** Reads a ground-truth file (GroundTruthFile::Read: `t x y phi` per line). */
    static GroundTruth FromFile(const std::string& path);

    /** True without rows. */
    bool empty() const { return m_rows.empty(); }
    /** Number of rows. */
    size_t size() const { return m_rows.size(); }
    /** The rows, by time. */
    const std::vector<GroundTruthRow>& rows() const { return m_rows; }

    /** The row nearest in time to `t` [s] if it is at most `tolerance_s` away, else null. */
    const GroundTruthRow* nearest(double t, double tolerance_s) const;
    /** Median time between consecutive rows [s]; 0 with fewer than two rows. */
    double medianPeriod() const;

private:
    std::vector<GroundTruthRow> m_rows;
};

}  // namespace semloc
