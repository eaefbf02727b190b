/* semloc — CSemanticMap's grid index of its objects (private). */
#pragma once

#include <semloc/models/semantic/CSemanticMap.h>

#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

namespace semloc
{
namespace detail
{
struct VisCache;
}

/** Objects sorted by grid cell (row-major), structure-of-arrays, so the cells of one
 *  grid row that overlap the detector's disc are one contiguous range. Built by
 *  CSemanticMap::rebuildIndex() after any change of the objects. */
struct CSemanticMap::Index
{
    double x0 = 0, y0 = 0, cell = 10, inv_cell = 0.1;
    int nx = 0, ny = 0;
    std::vector<uint32_t> cellStart;  // nx*ny + 1
    std::vector<double> x, y;         // n + 1: one padding element
    std::vector<int32_t> label;
    std::vector<int32_t> objIdx;  // index into m_objects
    std::unordered_map<int32_t, int32_t> idToSorted;
    /** @name How sure the map is of each object (probabilistic model), by sorted index
     *  @{ */
    /** sigma_m^2 [m^2] (empty when every object is exact). */
    std::vector<double> sigma2;
    /** p_exist (empty when every object surely exists). */
    std::vector<double> pExist;
    /** First of the object's nLabels class probabilities in classProb, by label id, or -1 for
     *  a certain label (empty when no object has a class distribution). */
    std::vector<int32_t> classRow;
    std::vector<double> classProb;
    /** The largest sigma_m [m] and the smallest p_exist. */
    double maxSigma = 0, minExist = 1;
    /** @} */
    /** Unique per build of an index (any map, any thread): keys what callers cache. */
    uint64_t stamp = 0;
    /** Visibility candidate tables of this build (null: no objects). */
    std::shared_ptr<detail::VisCache> vis;
};
}  // namespace semloc
