/* semloc — what a semantic likelihood model needs that is the same for every particle of a
 * call (private). */
#pragma once

#include <semloc/models/semantic/CSemanticMap.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

namespace semloc::semantic
{
/** What a model needs that is the same for every particle of a call (options, sensor
 *  range and FOV): computed once per call, not per particle. */
struct ModelConsts
{
    double ir = 0, ib = 0;  // 1 / sigma_rho, 1 / sigma_theta [1/m, 1/rad]
    /** Largest (dr/sigma_r)^2 a pair may cost and still gain (infinite when a misread range
     *  alone gains: p_range_outlier). */
    double rangeBudget = 0;
    /** Largest (db/sigma_b)^2 a pair may cost and still gain. */
    double bearingBudget = 0;
    /** cos of the largest |dtheta| bearingBudget allows (-2: no bearing gate). */
    double cosGate = -2;
    /** p_range_outlier > 0: a pair's range term is rangeTerm(), the mixture of the Gaussian
     *  (log weight and normalisation mixA) and the uniform misread range (log density mixB);
     *  else the Gaussian's -(dr/sigma_r)^2 / 2 alone (normalisation in logNorm). */
    bool rangeOutliers = false;
    double mixA = 0, mixB = 0;
    /** log(1 - eps). */
    double logKeep = 0;
    /** probabilistic, with rangeOutliers: the bearing Gaussian's normalisation alone. */
    double logNormBearing = 0;
    double logPu = 0;  // paper: log p_u, per unmatched detection
    double logPo = 0;  // paper: log of the factor per unmatched (missed) object
    // probabilistic
    double sb = 0, logNorm = 0, logKappa = 0, logSame = 0, logOther = 0, lambda = 0;
    /** log(P_D / (1 - P_D)) at P_D's smallest and largest, widened by 1e-9 (gainBlock). */
    double logQLo = 0, logQHi = 0;
    bool confusable = false;
    /** Every detection may pair with every object's label (confusable, or an object with a
     *  class distribution): the plan lists them all. */
    bool planAll = false;
    /** 1 / the largest range sigma of a pair [1/m]: the range gate's scale (ir unless objects
     *  have a position sigma). */
    double gateIr = 0;
    /** probabilistic, objects with a position sigma (`uncertain`): a pair's variances are
     *  sigma_rho^2 + sigma_m^2 and sigma_theta^2 + sigma_m^2 / max(rho^2, 4 sigma_m^2). */
    bool uncertain = false;
    double sr2 = 0, sb2 = 0;
    /** probabilistic, objects with a class distribution pi: C(L_j | v) = pi(L_j) sameW +
     *  (1 - pi(L_j)) otherW. */
    bool classes = false;
    double sameW = 1, otherW = 0;
    /** association = marginal (probabilistic model): the sum over every association. */
    bool marginal = false;
    /** The smallest gain log w of a pair that is kept: 0 for the greedy association (a pair
     *  is taken only if it gains), log kMarginalMinWeight for the marginal one. */
    double gainFloor = 0;
};

/** What the probabilistic model needs of a map's uncertain objects (CSemanticMap::Index). */
struct MapSurety
{
    double maxSigma = 0;   //!< the largest sigma_m [m]
    double minExist = 1;   //!< the smallest p_exist
    bool classes = false;  //!< an object has a class distribution
};

/** The constants of the last call, kept while their inputs stay the same (MRPT's
 *  per-particle path makes one call per particle). */
struct ModelConstsCache
{
    std::array<double, 18> key{};
    ModelConsts consts;
    bool valid = false;
};

/** log(e^a + e^b), evaluated without overflow. */
inline double logAddExp(double a, double b)
{
    return std::max(a, b) + std::log1p(std::exp(-std::abs(a - b)));
}

/** The range term of a pair with h = -(dr/sigma_r)^2 / 2 when k.rangeOutliers:
 *  log(e^(mixA + h) + e^mixB). */
inline double rangeTerm(const ModelConsts& k, double h)
{
    return logAddExp(k.mixA + h, k.mixB);
}

/** The constants of options `opt` for a map of nLabels labels (and uncertain objects `map`)
 *  and a sensor of range R and field of view fov. */
ModelConsts modelConsts(const CSemanticMap::TLikelihoodOptions& opt, size_t nLabels, double R,
                        double fov, const MapSurety& map = MapSurety());

/** modelConsts(), recomputed only when an input differs from the cached call's. */
const ModelConsts& cachedModelConsts(const CSemanticMap::TLikelihoodOptions& opt, size_t nLabels,
                                     double R, double fov, const MapSurety& map,
                                     ModelConstsCache& cache);
}  // namespace semloc::semantic
