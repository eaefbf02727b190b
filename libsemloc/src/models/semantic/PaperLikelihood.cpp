/* semloc — the fast kernel of the paper's likelihood (§III; see SemanticLikelihoodKernels.h). */
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "models/semantic/SemanticAssociation.h"
#include "models/semantic/SemanticLikelihoodKernels.h"
#include "models/semantic/VisibleObjects.h"
#include "world/Geometry2D.h"

using mrpt::math::TPose2D;

namespace semloc::semantic
{
namespace
{
/** z^k of one particle into sc.hits / sc.hitD2; returns q, its size. */
[[gnu::always_inline]] inline size_t predictVisible(const CSemanticMap::Index& ix, const Geom& g,
                                                    Scratch& sc)
{
    if (sc.hits.size() < ix.x.size())
    {
        sc.hits.resize(ix.x.size());
        sc.hitD2.resize(ix.x.size());
    }
    const size_t cnt =
        scanVisible<false>(ix, g, {sc.hits.data(), sc.hitD2.data(), nullptr, nullptr}, sc.vis,
                           detail::listOf(sc.vis, g));
    sc.nVis = cnt;
    if (sc.used.size() < sc.dets.size() + cnt)
    {
        sc.used.resize(sc.dets.size() + ix.x.size(), 0);
    }
    return cnt;
}

/** Stage 1: z^k of every particle (q = blockVis[i], kNoPose if its pose is not finite) and,
 *  into sc.gated, its visible objects that may pair (inside their label's range hull).
 *  Returns how many may pair. */
size_t visibleBlock(const CSemanticMap::Index& ix, Scratch& sc, const Geom* geoms,
                    const TPose2D* poses, size_t m)
{
    const size_t nd = sc.dets.size();
    const int32_t* L = ix.label.data();
    const double* lo2 = sc.gateLo2.data();
    const double* hi2 = sc.gateHi2.data();
    uint32_t* blockVis = sc.blockVis.data();
    uint32_t* pairCount = sc.pairCount.data();
    size_t ne = 0;
    for (uint32_t i = 0; i < m; i++)
    {
        blockVis[i] = kNoPose;
        pairCount[i] = 0;
        if (!detail::finitePose(poses[i]))
        {
            continue;
        }
        const auto nv = static_cast<uint32_t>(predictVisible(ix, geoms[i], sc));
        blockVis[i] = nv;
        if (nd == 0)
        {
            continue;
        }
        if (sc.gated.size() < ne + nv)
        {
            sc.gated.resize(2 * (ne + nv));
        }
        const uint32_t* hit = sc.hits.data();
        const double* hitD2 = sc.hitD2.data();
        Gated* gated = sc.gated.data();
        for (uint32_t v = 0; v < nv; v++)
        {
            const uint32_t kk = hit[v];
            const auto l = static_cast<size_t>(L[kk]);
            const double d2 = hitD2[v];
            // Written always, kept only if it may pair.
            gated[ne].o.sorted = static_cast<int32_t>(kk);
            gated[ne].p = i;
            gated[ne].v = v;
            ne += static_cast<size_t>((d2 >= lo2[l]) & (d2 <= hi2[l]));
        }
    }
    return ne;
}

/** Stage 2: the ne objects that may pair in the sensor frame, and every (object, detection
 *  slot of its label) against the exact range and bearing gates, branch-free, into
 *  sc.cands: each object tests slotCount detections, the same number for every particle of
 *  the call. idTest: NamedObjectTest, or AnyObjectTest without detections naming an object. Returns
 *  how many pass. */
template <typename IdTest>
size_t gateBlock(const CSemanticMap::Index& ix, const ModelConsts& k, Scratch& sc,
                 const Geom* geoms, size_t ne, IdTest idTest)
{
    const size_t ns = sc.slotCount;
    const double ir = k.gateIr, maxBudget = k.rangeBudget, cosGate = k.cosGate;
    const double* X = ix.x.data();
    const double* Y = ix.y.data();
    const int32_t* L = ix.label.data();
    Gated* gated = sc.gated.data();
    Cand* cands = sc.cands.data();
    const Slot* slots = sc.slots.data();
    size_t nc = 0;
    for (uint32_t e = 0; e < ne; e++)
    {
        Vis& o = gated[e].o;
        const Geom& g = geoms[gated[e].p];
        const auto kk = static_cast<size_t>(o.sorted);
        const double dx = X[kk] - g.sx, dy = Y[kk] - g.sy;
        o.lx = g.c * dx + g.s * dy;
        o.ly = -g.s * dx + g.c * dy;
        o.d2 = dx * dx + dy * dy;
        o.label = L[kk];
        o.r = std::sqrt(o.d2);
        const Slot* sl = slots + static_cast<size_t>(o.label) * ns;
        for (size_t t = 0; t < ns; t++)
        {
            const Det& d = sl[t].d;
            cands[nc] = {sl[t].j, e};  // written always, kept if it passes
            // Both tests evaluated, without a branch.
            nc += static_cast<size_t>(
                static_cast<int>(passesGates(d, o.r, o.lx, o.ly, ir, maxBudget, cosGate)) &
                static_cast<int>(idTest(d.fixed, o.sorted)));
        }
    }
    return nc;
}

/** Stage 3: atan2 and gain of the nc candidates; those that gain are the pairs, in particle
 *  order (sc.pairs, sc.pairCount[i] of particle i). */
void gainBlock(const ModelConsts& k, Scratch& sc, size_t nc)
{
    if (sc.pairs.size() < nc + 1)
    {
        sc.pairs.resize(2 * nc + 1);  // at least one: read (not used) when a particle has none
    }
    const double ir = k.ir, ib = k.ib, unmatchedPair = k.logPu + k.logPo;
    const bool outliers = k.rangeOutliers;
    const Cand* cands = sc.cands.data();
    const Gated* gated = sc.gated.data();
    Pair* pairs = sc.pairs.data();
    uint32_t* pairCount = sc.pairCount.data();
    const Det* dets = sc.dets.data();
    size_t np = 0;
    for (size_t t = 0; t < nc; t++)
    {
        const Det& d = dets[cands[t].j];
        const Gated& q = gated[cands[t].e];
        const double dr = d.r - q.o.r;
        const double db = absBearingDiff(d, q.o.lx, q.o.ly);
        const double h = -0.5 * (dr * ir) * (dr * ir);
        const double gain =
            (outliers ? rangeTerm(k, h) : h) - 0.5 * (db * ib) * (db * ib) - unmatchedPair;
        pairs[np] = {gain, cands[t].j, q.v};  // written always, kept if it gains
        pairCount[q.p] += static_cast<uint32_t>(gain > 0);
        np += static_cast<size_t>(gain > 0);
    }
}

/** Stage 4: per particle, the assignment and
 *  sum(s_i) + (l - m) log p_u + (q - m) log p_o  ==  l log p_u + q log p_o + sum(gain_i)
 *  (§III: p_o = p_u, d = q + l - 2m unmatched). */
void totalsBlock(const ModelConsts& k, Scratch& sc, size_t m, double* out)
{
    const size_t nd = sc.dets.size();
    const uint32_t* blockVis = sc.blockVis.data();
    const uint32_t* pairCount = sc.pairCount.data();
    Pair* pairs = sc.pairs.data();
    uint8_t* used = sc.used.data();  // sized by predictVisible()
    size_t t = 0;
    for (uint32_t i = 0; i < m; i++)
    {
        const uint32_t c = pairCount[i];
        const double gains =
            c <= 1 ? (c == 0 ? 0.0 : pairs[t].gain) : assignGreedy(pairs + t, c, nd, used);
        t += c;
        out[i] = blockVis[i] == kNoPose
                     ? kMinLogLik
                     : finite(static_cast<double>(nd) * k.logPu +
                              static_cast<double>(blockVis[i]) * k.logPo + gains);
    }
}
}  // namespace

/** The stages each run over the whole block: z^k of every particle and its objects that
 *  may pair (label's range hull); those objects in the sensor frame and against the exact
 *  gates (passesGates) for every detection of their label; atan2 and gain of the pairs that
 *  pass; the assignments. Most of the time of a particle was spent waiting on short
 *  dependent chains (sqrt, then the gates, atan2, the gain) and on the branches that test
 *  them; one stage at a time, the chains of successive particles overlap. The order in
 *  which pairs are collected does not matter: assignGreedy() sorts them by (gain, j, v). */
void scorePaperBlock(const CSemanticMap::Index& ix, const ModelConsts& k, Scratch& sc,
                     const Geom* geoms, const TPose2D* poses, size_t m, double* out)
{
    for (auto* v : {&sc.blockVis, &sc.pairCount})  // each: the probabilistic block sizes one
    {
        if (v->size() < m)
        {
            v->resize(m);
        }
    }
    const size_t ne = visibleBlock(ix, sc, geoms, poses, m);
    if (sc.cands.size() < ne * sc.slotCount)
    {
        sc.cands.resize(2 * ne * sc.slotCount);
    }
    // Without detections naming an object (the usual case), no id test.
    const size_t nc = anyNamed(sc) ? gateBlock(ix, k, sc, geoms, ne, NamedObjectTest())
                                   : gateBlock(ix, k, sc, geoms, ne, AnyObjectTest());
    gainBlock(k, sc, nc);
    totalsBlock(k, sc, m, out);
}
}  // namespace semloc::semantic
