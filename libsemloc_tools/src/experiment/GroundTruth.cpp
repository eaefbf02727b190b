/* semloc — GroundTruth: nearest row in time. */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <semloc/dataset/GroundTruthFile.h>
#include <semloc/experiment/GroundTruth.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "experiment/Statistics.h"

namespace semloc
{
GroundTruth::GroundTruth(std::vector<GroundTruthRow> rows) : m_rows(std::move(rows))
{
    for (size_t i = 0; i < m_rows.size(); i++)
    {
        const auto& r = m_rows[i];
        if (!std::isfinite(r.t) || !std::isfinite(r.x) || !std::isfinite(r.y) ||
            !std::isfinite(r.phi))
        {
            THROW_EXCEPTION(mrpt::format("ground truth row %zu is not finite", i));
        }
        if (i > 0 && !(r.t > m_rows[i - 1].t))
        {
            THROW_EXCEPTION(
                mrpt::format("ground truth row %zu: time %.17g is not after the previous row's "
                             "%.17g (times must increase)",
                             i, r.t, m_rows[i - 1].t));
        }
    }
}

GroundTruth GroundTruth::FromFile(const std::string& path)
{
    return GroundTruth(GroundTruthFile::Read(path));
}

const GroundTruthRow* GroundTruth::nearest(double t, double tolerance_s) const
{
    if (m_rows.empty() || !std::isfinite(t))
    {
        return nullptr;
    }
    const auto it = std::lower_bound(m_rows.begin(), m_rows.end(), t,
                                     [](const GroundTruthRow& r, double v) { return r.t < v; });
    const GroundTruthRow* best = nullptr;
    if (it != m_rows.end())
    {
        best = &*it;
    }
    if (it != m_rows.begin() && (!best || t - std::prev(it)->t <= best->t - t))
    {
        best = &*std::prev(it);
    }
    return (best && std::abs(best->t - t) <= tolerance_s) ? best : nullptr;
}

double GroundTruth::medianPeriod() const
{
    std::vector<double> d;
    for (size_t i = 1; i < m_rows.size(); i++)
    {
        d.push_back(m_rows[i].t - m_rows[i - 1].t);
    }
    return detail::median(std::move(d));
}

}  // namespace semloc
