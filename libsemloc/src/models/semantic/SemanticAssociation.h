/* semloc — association of detections with the visible objects z^k: the detection plan, the
 * gates, the bearing differences and the greedy one-to-one assignment (private; the
 * per-pair helpers are inline: the kernels' inner loops). */
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "math/FastMath.h"
#include "models/semantic/SemanticIndex.h"
#include "models/semantic/SemanticLikelihoodState.h"
#include "models/semantic/SemanticModelConstants.h"

namespace semloc::semantic
{
/** Which detections may pair with an object of label l (once per call):
 *  detByLabel[detStart[l] .. detStart[l + 1]) holds those of label l, those of any label
 *  (`k.planAll`: class confusion or class distributions, or a detection without one), and those
 * naming an object of label l (they pair with that object only: Det::fixed); the same as slots
 * padded to one count per label, sorted by range into range bins (planRangeBins). Also the range
 * hull of each label: a pair passes the range gate (passesGates) only if |rho^r - rho^k| <=
 * sigma_rho sqrt(rangeBudget), so an object of label l whose squared range is outside [gateLo2[l],
 *  gateHi2[l]] pairs with none of them (bounds widened by a relative 1e-9 for rounding: a
 *  necessary condition). */
void planPairs(Scratch& sc, const CSemanticMap::Index& ix, size_t nLabels, const ModelConsts& k);

/** planPairs() of sc.dets, unless the last call's plan is for the same detections, index
 *  build and constants (MRPT's per-particle path makes one call per particle with the same
 *  observation). */
void planPairsOnce(Scratch& sc, const CSemanticMap::Index& ix, size_t nLabels,
                   const ModelConsts& k);

/** The exact gates of the pair (detection d, visible object at (lx, ly) in the sensor frame,
 *  range r): `k.rangeBudget` and `k.bearingBudget` bound what the range and bearing terms may
 *  cost for its gain to stay positive, so (dr/sigma_r)^2 <= rangeBudget (passed as `budget`)
 *  and u . v >= cosGate |v| (|dtheta| <= sigma_theta sqrt(bearingBudget)) are necessary
 *  conditions, checked before any atan2 (most candidates fail them); the bearing
 *  one as u . v >= cos(max dtheta) |v| with the detection's unit vector u. Branch-free. */
inline bool passesGates(const Det& d, double r, double lx, double ly, double ir, double budget,
                        double cosGate)
{
    const double dr = d.r - r;
    const double dot = d.uc * lx + d.us * ly;
    return ((dr * ir) * (dr * ir) <= budget) & (dot >= cosGate * r);
}

/** The id test of a pair: a detection naming an object (`fixed` >= 0) pairs with it only. */
struct NamedObjectTest
{
    bool operator()(int32_t fixed, int32_t sorted) const { return (fixed < 0) | (fixed == sorted); }
};

/** The id test when no detection names an object (the usual case): none. */
struct AnyObjectTest
{
    bool operator()(int32_t /*fixed*/, int32_t /*sorted*/) const { return true; }
};

/** True if a detection names an object (then the gates need the id test). */
inline bool anyNamed(const Scratch& sc)
{
    return std::any_of(sc.dets.begin(), sc.dets.end(), [](const Det& d) { return d.fixed >= 0; });
}

/** |bearing difference| of detection d and the object at (lx, ly): |atan2(u x v, u . v)| of
 *  the detection's unit vector u and the object's direction v, exact, no angle wrapping
 *  (the models use its square only; gated pairs are within 45 degrees: the short path). */
inline double absBearingDiff(const Det& d, double lx, double ly)
{
    return detail::fastAbsAtan2(d.uc * ly - d.us * lx, d.uc * lx + d.us * ly);
}

/** absBearingDiff of two pairs at once (d0 with the object at (lx0, ly0), d1 with
 *  (lx1, ly1)): the same operations lane by lane, so the same bits. */
inline detail::Vec2 absBearingDiff2(const Det& d0, double lx0, double ly0, const Det& d1,
                                    double lx1, double ly1)
{
    using detail::Vec2;
    const Vec2 uc{d0.uc, d1.uc}, us{d0.us, d1.us}, lx{lx0, lx1}, ly{ly0, ly1};
    return detail::fastAbsAtan2x2(uc * ly - us * lx, uc * lx + us * ly);
}

/** Pair a before pair b in the greedy order: larger gain first, ties broken by (j, v) so
 *  the result never depends on the sort implementation. */
inline bool greedyBefore(const Pair& a, const Pair& b)
{
    if (a.gain != b.gain)
    {
        return a.gain > b.gain;
    }
    return a.j != b.j ? a.j < b.j : a.v < b.v;
}

/** Greedy one-to-one assignment of the np pairs of one particle (nd detections), best pair
 *  first; `used` marks taken detections [0, nd) and objects [nd, ...), all zero before and
 *  after. Returns the summed gain. */
inline double assignGreedy(Pair* pairs, size_t np, size_t nd, uint8_t* used)
{
    if (np <= 1)
    {
        return np == 0 ? 0.0 : pairs[0].gain;  // the usual case: no conflict to resolve
    }
    if (np > 24)
    {
        std::sort(pairs, pairs + np,
                  [](const Pair& a, const Pair& b) { return greedyBefore(a, b); });
    }
    else
    {
        for (size_t i = 1; i < np; i++)  // a handful of pairs: insertion sort, inline
        {
            const Pair p = pairs[i];
            size_t k = i;
            for (; k > 0 && greedyBefore(p, pairs[k - 1]); k--)
            {
                pairs[k] = pairs[k - 1];
            }
            pairs[k] = p;
        }
    }
    double sum = 0;
    for (size_t i = 0; i < np; i++)
    {
        const Pair& p = pairs[i];
        if (used[p.j] | used[nd + p.v])
        {
            continue;
        }
        used[p.j] = used[nd + p.v] = 1;
        sum += p.gain;
    }
    for (size_t i = 0; i < np; i++)
    {
        used[pairs[i].j] = used[nd + pairs[i].v] = 0;
    }
    return sum;
}
/** log of the sum over every one-to-one association of the np pairs of one particle (nd
 *  detections; pair u's weight is exp(pairs[u].gain + log pairs[u].q)) of the product of its
 *  pairs' weights, the empty association counting 1: the marginal association of the
 *  probabilistic model (CSemanticMap). Exact per group of detections and objects linked by
 *  pairs while a group reaches at most CSemanticMap::kMarginalMaxStates sets of taken
 *  objects; beyond, the heaviest sets are kept and `approximated` is set. */
double marginalAssociation(const Pair* pairs, size_t np, size_t nd, MarginalScratch& ms,
                           bool& approximated);

}  // namespace semloc::semantic
