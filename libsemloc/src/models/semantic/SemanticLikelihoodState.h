/* semloc — the semantic likelihood's per-call state: prepared detections, the elements of
 * z^k and of the association, and the per-thread scratch of the fast kernels (private). */
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "models/semantic/SemanticModelConstants.h"
#include "models/semantic/SemanticSensorGeometry.h"
#include "models/semantic/VisibilityTable.h"

namespace semloc::semantic
{
/** A detection prepared for matching. */
struct Det
{
    double r;             // range [m]
    double uc, us;        // unit vector of the bearing (cos, sin), computed once per observation
    int32_t label;        // label id, or -1 = any label (MRPT landmarks without id)
    int32_t fixed;        // sorted index of the object it names, or -1
    double clutterShift;  // log of its clutter density over kappa (look-alikes), >= 0
};

inline Det makeDet(double r, double bearing, int32_t label, int32_t fixed)
{
    return {r, std::cos(bearing), std::sin(bearing), label, fixed, 0.0};
}

/** A map object predicted visible from the particle: one element of z^k. */
struct Vis
{
    double lx, ly, d2;  // position in the sensor frame, squared range
    double r;           // range
    int32_t label, sorted;
};

/** A (detection j, visible object v) pair that gains, and its gain. */
struct Pair
{
    double gain;
    uint32_t j, v;
    double q = 0;  // probabilistic: P_D / (1 - P_D) of the pair's object (totalsBlock)
};

/** The workspace of marginalAssociation() (SemanticAssociation.h): grown, never shrunk. */
struct MarginalScratch
{
    /** A pair in a group's local numbering: detection, object, gain log w. */
    struct Edge
    {
        uint32_t det, obj;
        double logW;
    };
    std::vector<int32_t> objLocal;  // -1 between calls
    std::vector<uint32_t> parent;   // union-find over the local nodes
    /** The partial associations that take the objects of `taken`: log of their sum. */
    struct State
    {
        uint64_t taken;
        double logSum;
    };
    std::vector<Edge> edges, group, kept, local;
    std::vector<uint32_t> root, start;
    std::vector<size_t> order;
    std::vector<State> states, nextStates;
};

/** A detection as one of a label's slots (planPairs). */
struct Slot
{
    Det d;
    uint32_t j;  // index into Scratch::dets
};

/** A visible object, of particle p of a block, that may pair (scorePaperBlock). */
struct Gated
{
    Vis o;
    uint32_t p, v;
};

/** A (detection j, gated object e) pair that passed the range and bearing gates. */
struct Cand
{
    uint32_t j, e;
};

constexpr double kInf = std::numeric_limits<double>::infinity();

/** Lowest value returned: keeps MRPT's finite-likelihood assertion true even if an
 *  extreme option set ever made the sum overflow. */
constexpr double kMinLogLik = -1e300;

inline double finite(double v)
{
    return std::isfinite(v) ? v : kMinLogLik;
}

/** A block's q of a particle whose pose is not finite (Scratch::blockVis). */
constexpr uint32_t kNoPose = std::numeric_limits<uint32_t>::max();

/** Per-thread scratch (one TLS access per call): no allocation per particle once
 *  warmed up, and safe for concurrent const calls from many threads. */
struct Scratch
{
    std::vector<Det> dets;
    size_t nVis = 0;
    std::vector<uint32_t> hits;  // sorted indices of the visible objects (first nVis)
    std::vector<double> hitD2;   // and their squared ranges
    /** Per call: the detections that may pair with a visible object of label l are
     *  detByLabel[detStart[l] .. detStart[l + 1]) (planPairs). */
    std::vector<uint32_t> detByLabel, detStart, detFill;
    /** Per call: squared ranges [gateLo2[l], gateHi2[l]] outside which no detection may
     *  pair with a visible object of label l (planPairs; empty interval: none may). */
    std::vector<double> gateLo2, gateHi2;
    /** Per call: the detections that may pair with label l, padded to slotCount each with
     *  a detection no object can pair with (planPairs), so every object tests as many. */
    std::vector<Slot> slots;
    size_t slotCount = 0;
    /** Per call: the range bins of the slots (planRangeBins): count, 1 / width, spans. */
    size_t binCount = 1;
    double binInv = 0;
    std::vector<uint32_t> binSpan;
    /** The most slots of any bin (planRangeBins). */
    size_t maxSpan = 0;
    /** The block stages: per particle of the block, its q (paper) or number of visible
     *  objects (probabilistic), its number of pairs (paper) and where its objects start
     *  (probabilistic); the objects that may pair (paper) and the gated candidate pairs of
     *  the whole block. */
    std::vector<uint32_t> blockVis, pairCount, visStart;
    std::vector<Gated> gated;
    std::vector<Cand> cands;
    /** gateBlock's (slot, entry) pairs to test, when bins hold few slots. */
    std::vector<Cand> tasks;
    /** Per particle of the block: the product of 1 - P_D of its visible objects, and the
     *  terms of its log-likelihood that do not depend on the association (missBlock). */
    std::vector<double> bMiss, bBase;
    /** planPairs() of the last call is kept while these stay the same. */
    std::vector<Det> planDets;
    std::array<double, 4> planKey{};
    bool planConfusable = false, planValid = false;
    /** scoreProbabilisticBlock's visible objects of the whole block, structure of arrays:
     *  sorted index, particle, squared range, position in the sensor frame, range, P_D. */
    std::vector<uint32_t> bHit, bPart;
    std::vector<double> bD2, bLx, bLy, bR, bPd;
    /** modelConsts() of the last call. */
    ModelConstsCache consts;
    std::vector<Pair> pairs;
    /** The visibility table of this call (null: grid scan) and the last one looked up. */
    const detail::VisTable* vis = nullptr;
    detail::VisTableHandle visHandle;
    /** assignGreedy's marks: all zero between calls (it clears what it set). */
    std::vector<uint8_t> used;
    SensorTrig trig;
    /** marginalAssociation's workspace. */
    MarginalScratch marginal;
    /** Particle evaluations of this call whose marginal association was approximated. */
    size_t approximated = 0;
};
}  // namespace semloc::semantic
