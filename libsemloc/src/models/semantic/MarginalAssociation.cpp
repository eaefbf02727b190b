/* semloc — the marginal association of the probabilistic model: the sum over every one-to-one
 * association of a particle's pairs (see SemanticAssociation.h and CSemanticMap.h). */
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "models/semantic/SemanticAssociation.h"

namespace semloc::semantic
{
namespace
{
using Edge = MarginalScratch::Edge;
constexpr double kNegInf = -std::numeric_limits<double>::infinity();

/** log(exp(a) + exp(b)). */
double logAdd(double a, double b)
{
    if (a < b)
    {
        std::swap(a, b);
    }
    return b == kNegInf ? a : a + std::log1p(std::exp(b - a));
}

uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t a)
{
    while (parent[a] != a)
    {
        parent[a] = parent[parent[a]];
        a = parent[a];
    }
    return a;
}

/** The groups of edges[0, n): detections and objects linked by edges (union-find over
 *  detections d and objects nd + o). Orders the edges by group, then detection, then object,
 *  and writes each edge's group root to ms.root (in the new order). */
void groupEdges(Edge* edges, size_t n, size_t nd, size_t no, MarginalScratch& ms)
{
    ms.parent.resize(nd + no);
    for (size_t u = 0; u < n; u++)
    {
        ms.parent[edges[u].det] = edges[u].det;
        ms.parent[nd + edges[u].obj] = static_cast<uint32_t>(nd + edges[u].obj);
    }
    for (size_t u = 0; u < n; u++)
    {
        const uint32_t a = findRoot(ms.parent, edges[u].det);
        const uint32_t b = findRoot(ms.parent, static_cast<uint32_t>(nd + edges[u].obj));
        ms.parent[std::max(a, b)] = std::min(a, b);
    }
    ms.order.resize(n);
    ms.root.resize(n);
    for (size_t u = 0; u < n; u++)
    {
        ms.root[u] = findRoot(ms.parent, edges[u].det);
        ms.order[u] = u;
    }
    std::sort(ms.order.begin(), ms.order.begin() + static_cast<std::ptrdiff_t>(n),
              [&](size_t a, size_t b)
              {
                  const Edge &ea = edges[a], &eb = edges[b];
                  return ms.root[a] != ms.root[b] ? ms.root[a] < ms.root[b]
                         : ea.det != eb.det       ? ea.det < eb.det
                                                  : ea.obj < eb.obj;
              });
    ms.local.resize(n);
    ms.start.resize(n);
    for (size_t u = 0; u < n; u++)
    {
        ms.local[u] = edges[ms.order[u]];
        ms.start[u] = ms.root[ms.order[u]];
    }
    std::copy(ms.local.begin(), ms.local.begin() + static_cast<std::ptrdiff_t>(n), edges);
    std::copy(ms.start.begin(), ms.start.begin() + static_cast<std::ptrdiff_t>(n), ms.root.begin());
}

/** log of the sum over the associations of one group (edges g[0, n), sorted by
 *  detection): the partial associations of the first detections, summed by the set of
 *  objects they take (a bit mask over the group's objects, at most 64), each detection in
 *  turn clutter or one of its objects not taken yet. Exact while at most
 *  kMarginalMaxStates sets are reached; beyond, the heaviest of them are kept
 *  (`approximated`). */
double groupLogSum(const Edge* g, size_t n, MarginalScratch& ms, bool& approximated)
{
    // Local object numbers (first appearance); -1 again after.
    uint32_t objs = 0;
    ms.kept.assign(g, g + n);
    for (auto& e : ms.kept)
    {
        int32_t& o = ms.objLocal[e.obj];
        o = o < 0 ? static_cast<int32_t>(objs++) : o;
        e.obj = static_cast<uint32_t>(o);
    }
    for (size_t u = 0; u < n; u++)
    {
        ms.objLocal[g[u].obj] = -1;
    }
    auto& cur = ms.states;
    auto& next = ms.nextStates;
    cur.assign(1, {0, 0.0});
    for (size_t a = 0; a < n;)
    {
        size_t b = a;
        while (b < n && ms.kept[b].det == ms.kept[a].det)
        {
            b++;
        }
        next.clear();
        for (const auto& st : cur)
        {
            next.push_back(st);  // the detection is clutter
            for (size_t e = a; e < b; e++)
            {
                const uint64_t bit = uint64_t{1} << ms.kept[e].obj;
                if ((st.taken & bit) == 0)
                {
                    next.push_back({st.taken | bit, st.logSum + ms.kept[e].logW});
                }
            }
        }
        std::stable_sort(next.begin(), next.end(),
                         [](const MarginalScratch::State& x, const MarginalScratch::State& y)
                         { return x.taken < y.taken; });
        cur.clear();
        for (const auto& st : next)
        {
            if (!cur.empty() && cur.back().taken == st.taken)
            {
                cur.back().logSum = logAdd(cur.back().logSum, st.logSum);
            }
            else
            {
                cur.push_back(st);
            }
        }
        if (cur.size() > CSemanticMap::kMarginalMaxStates)
        {
            approximated = true;
            std::nth_element(
                cur.begin(),
                cur.begin() + static_cast<std::ptrdiff_t>(CSemanticMap::kMarginalMaxStates),
                cur.end(),
                [](const MarginalScratch::State& x, const MarginalScratch::State& y)
                { return x.logSum != y.logSum ? x.logSum > y.logSum : x.taken < y.taken; });
            cur.resize(CSemanticMap::kMarginalMaxStates);
        }
        a = b;
    }
    double total = kNegInf;
    for (const auto& st : cur)
    {
        total = logAdd(total, st.logSum);
    }
    return total;
}

/** groupLogSum(), with the usual groups first: one detection (its edges sorted by
 *  detection are all of it) or one object: at most one of the edges is taken, the sum is
 *  1 + sum of w. */
double starOrGroupLogSum(const Edge* g, size_t n, MarginalScratch& ms, bool& approximated)
{
    bool oneDet = true, oneObj = true;
    for (size_t u = 1; u < n; u++)
    {
        oneDet = oneDet && g[u].det == g[0].det;
        oneObj = oneObj && g[u].obj == g[0].obj;
    }
    if (!oneDet && !oneObj)
    {
        return groupLogSum(g, n, ms, approximated);
    }
    double sum = 0;  // log 1: no edge taken
    for (size_t u = 0; u < n; u++)
    {
        sum = logAdd(sum, g[u].logW);
    }
    return sum;
}

/** The number of distinct objects of edges g[0, n). */
uint32_t objectCount(const Edge* g, size_t n, MarginalScratch& ms)
{
    uint32_t objs = 0;
    for (size_t u = 0; u < n; u++)
    {
        objs += ms.objLocal[g[u].obj] < 0 ? 1 : 0;
        ms.objLocal[g[u].obj] = 0;
    }
    for (size_t u = 0; u < n; u++)
    {
        ms.objLocal[g[u].obj] = -1;
    }
    return objs;
}

/** The groups of edges[0, n) (in the particle's numbering), each summed; false, with
 *  nothing summed, if a group links more than 64 objects. */
bool sumGroups(Edge* edges, size_t n, size_t nd, size_t no, MarginalScratch& ms, double& total,
               bool& approximated)
{
    groupEdges(edges, n, nd, no, ms);
    for (int pass = 0; pass < 2; pass++)  // pass 0: the object counts; pass 1: the sums
    {
        total = 0;
        for (size_t g0 = 0; g0 < n;)
        {
            size_t g1 = g0;
            while (g1 < n && ms.root[g1] == ms.root[g0])
            {
                g1++;
            }
            if (pass == 0 && objectCount(edges + g0, g1 - g0, ms) > 64)
            {
                return false;
            }
            if (pass == 1)
            {
                total += starOrGroupLogSum(edges + g0, g1 - g0, ms, approximated);
            }
            g0 = g1;
        }
    }
    return true;
}
}  // namespace

double marginalAssociation(const Pair* pairs, size_t np, size_t nd, MarginalScratch& ms,
                           bool& approximated)
{
    if (np == 0)
    {
        return 0;
    }
    uint32_t no = 0;
    for (size_t u = 0; u < np; u++)
    {
        no = std::max(no, pairs[u].v + 1);
    }
    if (ms.objLocal.size() < no)
    {
        ms.objLocal.resize(no, -1);
    }
    ms.edges.resize(np);
    for (size_t u = 0; u < np; u++)
    {
        ms.edges[u] = {pairs[u].j, pairs[u].v, pairs[u].gain + std::log(pairs[u].q)};
    }
    // A group of more than 64 objects (a bit mask each) leaves out its lightest pairs, an
    // eighth at a time, until none is left (approximated).
    size_t keep = np;
    double total = 0;
    bool sorted = false;
    while (true)
    {
        ms.group.assign(ms.edges.begin(), ms.edges.begin() + static_cast<std::ptrdiff_t>(keep));
        if (sumGroups(ms.group.data(), keep, nd, no, ms, total, approximated))
        {
            return total;
        }
        if (!sorted)
        {
            sorted = true;
            // The edges heaviest first (ties by detection and object: a fixed order).
            std::sort(ms.edges.begin(), ms.edges.end(),
                      [](const Edge& a, const Edge& b) {
                          return a.logW != b.logW ? a.logW > b.logW
                                 : a.det != b.det ? a.det < b.det
                                                  : a.obj < b.obj;
                      });
        }
        approximated = true;
        keep -= std::max<size_t>(1, keep / 8);
    }
}
}  // namespace semloc::semantic
