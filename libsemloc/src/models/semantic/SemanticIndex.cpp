/* semloc — CSemanticMap's grid index: the objects sorted by cell (see SemanticIndex.h). */
#include "models/semantic/SemanticIndex.h"

#include <algorithm>
#include <atomic>

#include "models/semantic/LabelIndex.h"
#include "models/semantic/VisibilityTable.h"

namespace semloc
{
namespace
{
/** The grid of `objects`: origin at their lowest corner, cells of `cell` metres doubled
 *  until at most ~1M cells cover their extent. */
void placeGrid(CSemanticMap::Index& ix, const std::vector<CSemanticMap::TObject>& objects,
               double cell)
{
    double xmin = objects[0].x, xmax = xmin, ymin = objects[0].y, ymax = ymin;
    for (const auto& o : objects)
    {
        xmin = std::min(xmin, o.x);
        xmax = std::max(xmax, o.x);
        ymin = std::min(ymin, o.y);
        ymax = std::max(ymax, o.y);
    }
    ix.cell = cell;
    // Keep the grid at most ~1M cells whatever the extent.
    while (((xmax - xmin) / ix.cell + 1) * ((ymax - ymin) / ix.cell + 1) > 1e6)
    {
        ix.cell *= 2;
    }
    ix.inv_cell = 1.0 / ix.cell;
    ix.x0 = xmin;
    ix.y0 = ymin;
    ix.nx = static_cast<int>((xmax - xmin) * ix.inv_cell) + 1;
    ix.ny = static_cast<int>((ymax - ymin) * ix.inv_cell) + 1;
}

/** Each object's cell, and ix.cellStart: where each cell's objects start in sorted order. */
std::vector<uint32_t> countCells(CSemanticMap::Index& ix,
                                 const std::vector<CSemanticMap::TObject>& objects)
{
    const size_t n = objects.size();
    const size_t ncell = static_cast<size_t>(ix.nx) * static_cast<size_t>(ix.ny);
    std::vector<uint32_t> cellOf(n);
    ix.cellStart.assign(ncell + 1, 0);
    for (size_t i = 0; i < n; i++)
    {
        const int cx = std::min(ix.nx - 1, static_cast<int>((objects[i].x - ix.x0) * ix.inv_cell));
        const int cy = std::min(ix.ny - 1, static_cast<int>((objects[i].y - ix.y0) * ix.inv_cell));
        cellOf[i] = static_cast<uint32_t>(cy * ix.nx + cx);
        ix.cellStart[cellOf[i] + 1]++;
    }
    for (size_t c = 0; c < ncell; c++)
    {
        ix.cellStart[c + 1] += ix.cellStart[c];
    }
    return cellOf;
}
}  // namespace

namespace
{
/** The per-object sigma_m^2, p_exist and class rows of `ix` (sorted order), each left empty
 *  when no object needs it. */
void indexUncertainty(CSemanticMap::Index& ix, const std::vector<CSemanticMap::TObject>& objects,
                      const LabelIndex& labels)
{
    const size_t n = objects.size(), nl = labels.size();
    for (const auto& o : objects)
    {
        ix.maxSigma = std::max(ix.maxSigma, o.sigma_m);
        ix.minExist = std::min(ix.minExist, o.p_exist);
    }
    const bool anyClasses =
        std::any_of(objects.begin(), objects.end(),
                    [](const CSemanticMap::TObject& o) { return !o.classes.empty(); });
    if (ix.maxSigma > 0)
    {
        ix.sigma2.resize(n);
    }
    if (ix.minExist < 1)
    {
        ix.pExist.resize(n);
    }
    if (anyClasses)
    {
        ix.classRow.assign(n, -1);
    }
    for (size_t k = 0; k < n; k++)
    {
        const auto& o = objects[static_cast<size_t>(ix.objIdx[k])];
        if (!ix.sigma2.empty())
        {
            ix.sigma2[k] = o.sigma_m * o.sigma_m;
        }
        if (!ix.pExist.empty())
        {
            ix.pExist[k] = o.p_exist;
        }
        if (anyClasses && !o.classes.empty())
        {
            ix.classRow[k] = static_cast<int32_t>(ix.classProb.size());
            ix.classProb.resize(ix.classProb.size() + nl, 0.0);
            for (const auto& [label, p] : o.classes)
            {
                ix.classProb[static_cast<size_t>(ix.classRow[k]) +
                             static_cast<size_t>(labels.find(label))] = p;
            }
        }
    }
}
}  // namespace

void CSemanticMap::rebuildIndex()
{
    m_labels->clear();
    Index& ix = *m_index;
    static std::atomic<uint64_t> stamps{0};
    ix = Index();
    ix.stamp = ++stamps;
    const size_t n = m_objects.size();
    if (n == 0)
    {
        return;
    }
    ix.vis = std::make_shared<detail::VisCache>();
    for (const auto& o : m_objects)
    {
        m_labels->intern(o.label);
    }
    for (const auto& o : m_objects)
    {
        for (const auto& c : o.classes)
        {
            m_labels->intern(c.first);
        }
    }
    placeGrid(ix, m_objects, likelihoodOptions.index_cell_m);
    const std::vector<uint32_t> cellOf = countCells(ix, m_objects);
    // One padding element: the scan reads candidates in pairs (scanVisible).
    ix.x.assign(n + 1, 0.0);
    ix.y.assign(n + 1, 0.0);
    ix.label.resize(n);
    ix.objIdx.resize(n);
    std::vector<uint32_t> fill(ix.cellStart.begin(), ix.cellStart.end() - 1);
    for (size_t i = 0; i < n; i++)
    {
        const uint32_t k = fill[cellOf[i]]++;
        ix.x[k] = m_objects[i].x;
        ix.y[k] = m_objects[i].y;
        ix.label[k] = m_labels->find(m_objects[i].label);
        ix.objIdx[k] = static_cast<int32_t>(i);
        ix.idToSorted[m_objects[i].id] = static_cast<int32_t>(k);
    }
    indexUncertainty(ix, m_objects, *m_labels);
}
}  // namespace semloc
