/* semloc — the fast kernel of the probabilistic likelihood (see SemanticLikelihoodKernels.h
 * and the model in CSemanticMap.h). */
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "models/semantic/SemanticAssociation.h"
#include "models/semantic/SemanticLikelihoodKernels.h"
#include "models/semantic/VisibleObjects.h"
#include "world/Geometry2D.h"

using mrpt::math::TPose2D;

namespace semloc::semantic
{
namespace
{
constexpr double kInfinity = std::numeric_limits<double>::infinity();

/** Most pairs of a particle whose q totalsBlock folds into the product: q^8 >= 1e-48. */
constexpr uint32_t kFoldPairs = 8;

/** Stage 1: z^k of particles [0, m) one after the other (entries e of the block: sorted
 *  index, particle, squared range, sensor-frame position) and per particle its q (kNoPose
 *  if its pose is not finite) and first entry. Returns the number of entries. */
size_t scanBlock(const CSemanticMap::Index& ix, Scratch& sc, const Geom* geoms,
                 const TPose2D* poses, size_t m)
{
    const size_t nObj = ix.x.size();
    uint32_t* blockVis = sc.blockVis.data();
    uint32_t* visStart = sc.visStart.data();
    size_t ne = 0;
    // The table lists of kSub particles first (independent chains of conversions, a
    // division and loads the CPU overlaps across particles), then their scans.
    constexpr uint32_t kSub = 64;
    detail::ListRange lists[kSub];
    for (uint32_t i = 0; i < m; i++)
    {
        if (i % kSub == 0)
        {
            for (uint32_t u = i; u < std::min<uint32_t>(m, i + kSub); u++)
            {
                lists[u - i] = detail::listOf(sc.vis, geoms[u]);
            }
        }
        blockVis[i] = kNoPose;
        visStart[i] = static_cast<uint32_t>(ne);
        if (!detail::finitePose(poses[i]))
        {
            continue;
        }
        if (sc.bHit.size() < ne + nObj + 2)
        {
            const size_t cap = 2 * (ne + nObj + 2);
            sc.bHit.resize(cap);
            sc.bPart.resize(cap);
            for (auto* v : {&sc.bD2, &sc.bLx, &sc.bLy, &sc.bR, &sc.bPd})
            {
                v->resize(cap);
            }
        }
        const auto nv = static_cast<uint32_t>(
            scanVisible<true>(ix, geoms[i],
                              {sc.bHit.data() + ne, sc.bD2.data() + ne, sc.bLx.data() + ne,
                               sc.bLy.data() + ne, sc.bPart.data() + ne, i},
                              sc.vis, lists[i % kSub]));
        blockVis[i] = nv;
        ne += nv;
    }
    return ne;
}

/** Stage 2: the ranges of the ne entries and their P_D(rho, theta), clamped inside (0, 1),
 *  two at a time (the arrays have room for the pair's second lane). The bearing's taper
 *  (p_detect_edge_ratio < 1) takes |theta| from the sensor-frame position (fastAbsAtan2x2). */
void rangesBlock(const CSemanticMap::Index& ix, Scratch& sc, size_t ne,
                 const CSemanticMap::TLikelihoodOptions& opt, double R, double fov)
{
    using namespace detail;
    const double* D2 = sc.bD2.data();
    const double* LX = sc.bLx.data();
    const double* LY = sc.bLy.data();
    double* RR = sc.bR.data();
    double* PD = sc.bPd.data();
    const double pNear = opt.probabilistic.p_detect_near,
                 slope = opt.probabilistic.p_detect_far - opt.probabilistic.p_detect_near;
    const Vec2 vnear{pNear, pNear}, vslope{slope, slope}, vR{R, R};
    const Vec2 lo{1e-6, 1e-6}, hi{1 - 1e-6, 1 - 1e-6};
    const bool taper = opt.probabilistic.p_detect_edge_ratio < 1 && fov < 2 * M_PI;
    // P_D times 1 - drop min(|theta| / half, 1)
    const double drop = 1 - opt.probabilistic.p_detect_edge_ratio, perRad = taper ? 2 / fov : 0.0;
    const Vec2 vdrop{drop, drop}, vperRad{perRad, perRad}, one{1.0, 1.0};
    for (size_t e = 0; e < ne; e += 2)
    {
        const Vec2 r = sqrtLanes(loadLanes(D2 + e));
        Vec2 p = vnear + vslope * (r / vR);
        if (taper)
        {
            const Vec2 off = fastAbsAtan2x2(loadLanes(LY + e), loadLanes(LX + e)) * vperRad;
            p = p * (one - vdrop * minLanes(off, one));
        }
        storeLanes(RR + e, r);
        storeLanes(PD + e, maxLanes(minLanes(p, hi), lo));  // = std::clamp: p is finite
    }
    if (!ix.pExist.empty())
    {
        // An object that may be gone: P_D = p_exist P_D(rho), clamped the same way (P_D(rho)
        // lies inside the clamp: the options and rho <= R keep it there).
        const uint32_t* hit = sc.bHit.data();
        for (size_t e = 0; e < ne; e++)
        {
            PD[e] = std::clamp(ix.pExist[hit[e]] * PD[e], 1e-6, 1 - 1e-6);
        }
    }
}

/** Stage 2b: per particle, the product of 1 - P_D over its visible objects in sc.bMiss and
 *  -lambda + l log kappa in sc.bBase, one flat loop over the entries (no loop per particle
 *  whose length changes at random). Each factor is >= 1e-6: a product below 1e-250 is
 *  folded into bBase as its log before it could underflow. */
void missBlock(Scratch& sc, const ModelConsts& k, size_t m, size_t ne)
{
    for (auto* v : {&sc.bMiss, &sc.bBase})
    {
        if (v->size() < m)
        {
            v->resize(m);
        }
    }
    double* miss = sc.bMiss.data();
    double* base = sc.bBase.data();
    std::fill(miss, miss + m, 1.0);
    double logKappas = static_cast<double>(sc.dets.size()) * k.logKappa;
    for (const auto& d : sc.dets)
    {
        logKappas += d.clutterShift;  // look-alikes' clutter densities (0 without)
    }
    std::fill(base, base + m, -k.lambda + logKappas);
    const uint32_t* part = sc.bPart.data();
    const double* PD = sc.bPd.data();
    for (size_t e = 0; e < ne; e++)
    {
        const uint32_t i = part[e];
        double v = miss[i] * (1 - PD[e]);
        if (v < 1e-250)
        {
            base[i] += std::log(v);
            v = 1;
        }
        miss[i] = v;
    }
}

/** Stage 3 when no bin holds more than S slots: the pairs to test are listed first (each
 *  entry writes S, keeps those inside its bin: spanOf(e)) and tested (test(idTest, slot,
 *  entry)) in one flat loop: no inner loop whose length (0, 1, 2... slots) changes at random
 *  from one object to the next. The same pairs in the same order as a loop per entry. */
template <uint32_t S, typename IdTest, typename SpanOf, typename Test>
inline void gateListed(Scratch& sc, size_t ne, IdTest idTest, const SpanOf& spanOf, Test& test)
{
    if (sc.tasks.size() < ne * S + S)
    {
        sc.tasks.resize(2 * (ne * S + S));
    }
    Cand* tasks = sc.tasks.data();
    size_t nt = 0;
    for (uint32_t e = 0; e < ne; e++)
    {
        const uint32_t* sp = spanOf(e);
        const uint32_t a = sp[0], cnt = sp[1] - sp[0];
        for (uint32_t u = 0; u < S; u++)
        {
            tasks[nt] = {a + u, e};  // written always, kept if inside the bin
            nt += static_cast<size_t>(u < cnt);
        }
    }
    for (size_t t = 0; t < nt; t++)
    {
        test(idTest, tasks[t].j, tasks[t].e);
    }
}

/** The most slots per bin that gateListed() serves. */
constexpr size_t kMaxTaskSpan = 4;

/** Stage 3: every (entry, detection slot of its label in its range bin) against the exact
 *  gates, branch-free, into sc.cands; returns how many pass. Listed (gateListed) when no
 *  bin holds more than kMaxTaskSpan slots, else a loop per entry over its bin's slots. */
size_t gateBlock(const CSemanticMap::Index& ix, Scratch& sc, const ModelConsts& k, size_t ne)
{
    const size_t span = std::max<size_t>(1, sc.maxSpan);
    if (sc.cands.size() < ne * span + 1)
    {
        sc.cands.resize(2 * ne * span + 1);
    }
    const uint32_t* hit = sc.bHit.data();
    const double* RR = sc.bR.data();
    const double* LX = sc.bLx.data();
    const double* LY = sc.bLy.data();
    const int32_t* L = ix.label.data();
    Cand* cands = sc.cands.data();
    const Slot* slots = sc.slots.data();
    const uint32_t* binSpan = sc.binSpan.data();
    const size_t nb = sc.binCount;
    const double binInv = sc.binInv, lastBin = static_cast<double>(nb - 1);
    const double ir = k.gateIr, budget = k.rangeBudget, cosGate = k.cosGate;
    auto spanOf = [&](uint32_t e)
    {
        const auto b = static_cast<size_t>(std::min(RR[e] * binInv, lastBin));
        return binSpan + 2 * (static_cast<size_t>(L[hit[e]]) * nb + b);
    };
    size_t nc = 0;
    // The pair (slot t, entry e) into cands, kept if it passes.
    auto test = [&](auto idTest, uint32_t t, uint32_t e)
    {
        const Det& d = slots[t].d;
        cands[nc] = {slots[t].j, e};  // written always, kept if it passes
        nc += static_cast<size_t>(
            static_cast<int>(passesGates(d, RR[e], LX[e], LY[e], ir, budget, cosGate)) &
            static_cast<int>(idTest(d.fixed, static_cast<int32_t>(hit[e]))));
    };
    auto gate = [&](auto idTest)
    {
        switch (sc.maxSpan)
        {
            case 0:
                return;  // no slot in any bin: no pair
            case 1:
                return gateListed<1>(sc, ne, idTest, spanOf, test);
            case 2:
                return gateListed<2>(sc, ne, idTest, spanOf, test);
            case 3:
                return gateListed<3>(sc, ne, idTest, spanOf, test);
            case kMaxTaskSpan:
                return gateListed<kMaxTaskSpan>(sc, ne, idTest, spanOf, test);
            default:
                break;
        }
        for (uint32_t e = 0; e < ne; e++)
        {
            const uint32_t* sp = spanOf(e);
            for (uint32_t t = sp[0]; t < sp[1]; t++)
            {
                test(idTest, t, e);
            }
        }
    };
    if (anyNamed(sc))
    {
        gate(NamedObjectTest());
    }
    else
    {
        gate(AnyObjectTest());
    }
    return nc;
}

/** The gain of matching detection j with entry e, less log(P_D / (1 - P_D)): the label term,
 *  the Gaussians' normalisation and costs, and the clutter density the detection no longer
 *  needs. */
struct GainParts
{
    const Det* dets;
    const uint32_t* hit;
    const double *RR, *LX, *LY;
    const int32_t* L;
    const CSemanticMap::Index* ix;
    /** The label term log C(L_j | v) of detection d and entry e. */
    double logC(const ModelConsts& k, const Det& d, uint32_t e) const
    {
        if (d.label < 0)
        {
            return 0;  // landmarks without a label: no label term
        }
        const int32_t row = k.classes ? ix->classRow[hit[e]] : -1;
        if (row >= 0)
        {
            const double pi =
                ix->classProb[static_cast<size_t>(row) + static_cast<size_t>(d.label)];
            const double w = pi * k.sameW + (1 - pi) * k.otherW;
            // A class it cannot be: only a detection naming it pairs (the id wins).
            return w > 0 ? std::log(w) : (d.fixed >= 0 ? 0.0 : -kInfinity);
        }
        if (d.label == L[hit[e]])
        {
            return k.logSame;
        }
        // Another label: only with class confusion, or naming it (the plan lists every
        // detection for every object when some object has a class distribution).
        return k.confusable || d.fixed >= 0 ? k.logOther : -kInfinity;
    }
    /** The rest of an uncertain object's pair (sigma_m > 0 widens its Gaussians). */
    double uncertainRest(const ModelConsts& k, double logC, double dr, double db, uint32_t e) const
    {
        const double s2 = ix->sigma2[hit[e]], r = RR[e];
        const double vr = k.sr2 + s2, vb = k.sb2 + (s2 > 0 ? s2 / std::max(r * r, 4 * s2) : 0.0);
        const double hr = -0.5 * dr * dr / vr;
        double range = hr - 0.5 * std::log(2 * M_PI * vr);
        if (k.rangeOutliers)
        {
            range = logAddExp(range + k.logKeep, k.mixB);  // (1 - eps) N(dr; vr) + eps / R
        }
        return logC + range - 0.5 * std::log(2 * M_PI * vb) - 0.5 * db * db / vb - k.logKappa;
    }
    /** With db = absBearingDiff(dets[j], LX[e], LY[e]). */
    double rest(const ModelConsts& k, uint32_t j, uint32_t e, double db) const
    {
        const Det& d = dets[j];
        const double dr = d.r - RR[e];
        const double logC = this->logC(k, d, e);
        if (k.uncertain)
        {
            return uncertainRest(k, logC, dr, db, e) - d.clutterShift;
        }
        if (k.rangeOutliers)
        {
            return logC + k.logNormBearing + rangeTerm(k, -0.5 * (dr * k.ir) * (dr * k.ir)) -
                   0.5 * (db * k.ib) * (db * k.ib) - k.logKappa - d.clutterShift;
        }
        return logC + k.logNorm - 0.5 * (dr * k.ir) * (dr * k.ir) -
               0.5 * (db * k.ib) * (db * k.ib) - k.logKappa - d.clutterShift;
    }
};

GainParts gainParts(const CSemanticMap::Index& ix, const Scratch& sc)
{
    return {sc.dets.data(), sc.bHit.data(),  sc.bR.data(), sc.bLx.data(),
            sc.bLy.data(),  ix.label.data(), &ix};
}

/** A candidate pair's gain less log q, q = P_D / (1 - P_D), and whether its gain is
 *  above k.gainFloor (0 for the greedy association: positive): decided without log q when
 *  log q's range over the FOV decides it by more than 1e-9 (rounding: ~1e-14), else with
 *  log q: the same pairs as gain = log q + rest > gainFloor. */
struct PairGain
{
    double rest, q;
    bool gains;
};

PairGain pairGain(const ModelConsts& k, double rest, double q)
{
    PairGain g;
    g.rest = rest;
    g.q = q;
    g.gains = g.rest + k.logQLo > k.gainFloor;
    if (!g.gains && g.rest + k.logQHi >= k.gainFloor)
    {
        g.gains = std::log(g.q) + g.rest > k.gainFloor;
    }
    return g;
}

/** q = P_D / (1 - P_D) of a P_D (or two) clamped inside (0, 1). */
template <typename T>
inline T detectionOdds(T pd)
{
    return pd / (1.0 - pd);
}

/** Stage 4: the gains of the nc candidates; those with a positive gain are the pairs, in
 *  particle order (sc.pairs, sc.pairCount[i] of particle i), each with its gain less log q
 *  and its q. Branch-free but for pairGain's rare log. The bearing differences and the q of
 *  two candidates at a time (one division and one atan polynomial chain for both, the same
 *  bits as one at a time): their latency was much of this loop's time at steps with several
 *  pairs per particle. */
void gainBlock(const CSemanticMap::Index& ix, Scratch& sc, const ModelConsts& k, size_t m,
               size_t nc)
{
    using detail::Vec2;
    if (sc.pairs.size() < nc + 1)
    {
        sc.pairs.resize(2 * nc + 1);  // at least one: read (not used) when a particle has none
    }
    const Cand* cands = sc.cands.data();
    const uint32_t* part = sc.bPart.data();
    const uint32_t* visStart = sc.visStart.data();
    const double* PD = sc.bPd.data();
    const GainParts gp = gainParts(ix, sc);
    Pair* pairs = sc.pairs.data();
    uint32_t* pairCount = sc.pairCount.data();
    std::fill(pairCount, pairCount + m, 0u);
    size_t np = 0;
    auto emit = [&](const Cand& c, double db, double q)
    {
        const uint32_t i = part[c.e];
        const PairGain g = pairGain(k, gp.rest(k, c.j, c.e, db), q);
        pairs[np] = {g.rest, c.j, c.e - visStart[i], g.q};  // written always, kept if it gains
        pairCount[i] += static_cast<uint32_t>(g.gains);
        np += static_cast<size_t>(g.gains);
    };
    const double* LX = gp.LX;
    const double* LY = gp.LY;
    size_t t = 0;
    for (; t + 1 < nc; t += 2)
    {
        const Cand c0 = cands[t], c1 = cands[t + 1];
        const Det& d0 = gp.dets[c0.j];
        const Det& d1 = gp.dets[c1.j];
        const Vec2 db = absBearingDiff2(d0, LX[c0.e], LY[c0.e], d1, LX[c1.e], LY[c1.e]);
        const Vec2 pd{PD[c0.e], PD[c1.e]};
        const Vec2 q = detectionOdds(pd);
        emit(c0, db[0], q[0]);
        emit(c1, db[1], q[1]);
    }
    if (t < nc)
    {
        const Cand c = cands[t];
        emit(c, absBearingDiff(gp.dets[c.j], LX[c.e], LY[c.e]), detectionOdds(PD[c.e]));
    }
}

/** True if the c pairs (of one particle, in candidate order: an object's pairs are
 *  consecutive) share no detection and no object, so the greedy assignment takes them all;
 *  false also for more than kFoldPairs pairs or detections beyond 64. */
bool disjointPairs(const Pair* pairs, size_t c)
{
    if (c > kFoldPairs)
    {
        return false;
    }
    uint64_t dets = 0;
    bool ok = true;
    for (size_t u = 0; u < c; u++)
    {
        const uint64_t bit = uint64_t{1} << (pairs[u].j & 63u);
        ok &= pairs[u].j < 64 && (dets & bit) == 0 && (u == 0 || pairs[u].v != pairs[u - 1].v);
        dets |= bit;
    }
    return ok;
}

/** assignGreedy() out of line: only particles whose pairs compete take it, and inlined it
 *  made the totals loop around it costlier (measured with callgrind). */
[[gnu::noinline]] double assignCompeting(Pair* pairs, size_t np, size_t nd, uint8_t* used)
{
    return assignGreedy(pairs, np, nd, used);
}

/** Stage 5's loop: per particle, missBlock's terms and `association(pairs, c, miss)`, the log
 *  of the association's part of its c pairs (it may fold factors into `miss`, the product of
 *  the 1 - P_D: one log for the particle). */
template <typename Association>
void totalsLoop(Scratch& sc, size_t m, double* out, Association association)
{
    const uint32_t* blockVis = sc.blockVis.data();
    const uint32_t* pairCount = sc.pairCount.data();
    const double* bMiss = sc.bMiss.data();
    const double* bBase = sc.bBase.data();
    Pair* pairs = sc.pairs.data();
    size_t t = 0;
    for (uint32_t i = 0; i < m; i++)
    {
        if (blockVis[i] == kNoPose)
        {
            out[i] = kMinLogLik;
            continue;
        }
        const uint32_t c = pairCount[i];
        double miss = bMiss[i];
        const double gains = association(pairs + t, c, miss);
        t += c;
        out[i] = finite(bBase[i] + std::log(miss) + gains);
    }
}

/** Stage 5, greedy association. Pairs that share no detection and no object are all taken by
 *  the greedy assignment: up to kFoldPairs of them, their q join the product (one log for the
 *  particle) and their gains less log q are summed in pair order; otherwise each pair's gain
 *  log q + rest goes to the assignment. */
void totalsBlock(Scratch& sc, size_t m, double* out)
{
    const size_t nd = sc.dets.size();
    uint8_t* used = sc.used.data();
    totalsLoop(sc, m, out,
               [&](Pair* pairs, uint32_t c, double& miss)
               {
                   double gains = 0;
                   if (disjointPairs(pairs, c))
                   {
                       // q in [1e-6, 1e6]: a product >= 1e-250 times q^c (c <= 8) stays a
                       // normal number.
                       double qProd = 1;
                       for (size_t u = 0; u < c; u++)
                       {
                           gains += pairs[u].gain;
                           qProd *= pairs[u].q;
                       }
                       miss *= qProd;
                       return gains;
                   }
                   for (size_t u = 0; u < c; u++)
                   {
                       pairs[u].gain += std::log(pairs[u].q);
                   }
                   return assignCompeting(pairs, c, nd, used);
               });
}

/** Stage 5, marginal association: the log of the sum over the particle's associations
 *  (marginalAssociation; pairs that share no detection and no object: the product of their
 *  1 + w, w = q e^rest). */
void marginalTotalsBlock(Scratch& sc, size_t m, double* out)
{
    const size_t nd = sc.dets.size();
    totalsLoop(sc, m, out,
               [&](const Pair* pairs, uint32_t c, double& /*miss*/)
               {
                   if (!disjointPairs(pairs, c))
                   {
                       bool approximated = false;
                       const double sum =
                           marginalAssociation(pairs, c, nd, sc.marginal, approximated);
                       sc.approximated += approximated ? 1 : 0;
                       return sum;
                   }
                   // The product of the 1 + w (c <= 8), one log; with extreme options (tiny
                   // sigmas and clutter) a w can approach 1e300: then log(1 + w) pair by pair.
                   double prod = 1;
                   for (size_t u = 0; u < c; u++)
                   {
                       prod *= 1 + pairs[u].q * std::exp(pairs[u].gain);
                   }
                   if (prod < 1e300)
                   {
                       return std::log(prod);
                   }
                   double sum = 0;
                   for (size_t u = 0; u < c; u++)
                   {
                       const double x = pairs[u].gain + std::log(pairs[u].q);
                       sum += x > 0 ? x + std::log1p(std::exp(-x)) : std::log1p(std::exp(x));
                   }
                   return sum;
               });
}
}  // namespace

/** The stages over the whole block as in scorePaperBlock (PaperLikelihood.cpp). With class
 *  confusion every detection is a slot of every label (planPairs). */
void scoreProbabilisticBlock(const CSemanticMap::Index& ix,
                             const CSemanticMap::TLikelihoodOptions& opt, const ModelConsts& k,
                             Scratch& sc, const Geom* geoms, const TPose2D* poses, size_t m,
                             double* out)
{
    for (auto* v : {&sc.blockVis, &sc.pairCount, &sc.visStart})  // shared with the paper block
    {
        if (v->size() < m)
        {
            v->resize(m);
        }
    }
    if (sc.used.size() < sc.dets.size() + ix.x.size())
    {
        sc.used.resize(sc.dets.size() + ix.x.size(), 0);
    }
    const size_t ne = scanBlock(ix, sc, geoms, poses, m);
    if (m > 0)
    {
        rangesBlock(ix, sc, ne, opt, geoms[0].R, geoms[0].fov);
    }
    missBlock(sc, k, m, ne);
    const size_t nc = gateBlock(ix, sc, k, ne);
    gainBlock(ix, sc, k, m, nc);
    if (k.marginal)
    {
        marginalTotalsBlock(sc, m, out);
        return;
    }
    totalsBlock(sc, m, out);
}
}  // namespace semloc::semantic
