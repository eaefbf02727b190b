/* semloc — what a semantic likelihood model needs that is the same for every particle of a
 * call (private). */
#pragma once

#include <semloc/maps/CSemanticMap.h>

#include <array>
#include <cstddef>

namespace semloc::semantic
{
/** What a model needs that is the same for every particle of a call (options, sensor
 *  range and FOV): computed once per call, not per particle. */
struct ModelConsts
{
    double ir = 0, ib = 0;  // 1 / sigma_rho, 1 / sigma_theta [1/m, 1/rad]
    /** Largest (dr/sigma_r)^2 + (db/sigma_b)^2 a pair may cost and still gain. */
    double budget = 0;
    /** cos of the largest |dtheta| the budget allows (-2: no bearing gate). */
    double cosGate = -2;
    double logPu = 0;  // paper: log p_u, per unmatched detection
    double logPo = 0;  // paper: log of the factor per unmatched (missed) object
    // probabilistic
    double sb = 0, logNorm = 0, logKappa = 0, logSame = 0, logOther = 0, lambda = 0;
    /** log(P_D / (1 - P_D)) at P_D's smallest and largest, widened by 1e-9 (gainBlock). */
    double logQLo = 0, logQHi = 0;
    bool confusable = false;
    /** association = marginal (probabilistic model): the sum over every association. */
    bool marginal = false;
    /** The smallest gain log w of a pair that is kept: 0 for the greedy association (a pair
     *  is taken only if it gains), log kMarginalMinWeight for the marginal one. */
    double gainFloor = 0;
};

/** The constants of the last call, kept while their inputs stay the same (MRPT's
 *  per-particle path makes one call per particle). */
struct ModelConstsCache
{
    std::array<double, 13> key{};
    ModelConsts consts;
    bool valid = false;
};

/** The constants of options `opt` for a map of nLabels labels and a sensor of range R and
 *  field of view fov. */
ModelConsts modelConsts(const CSemanticMap::TLikelihoodOptions& opt, size_t nLabels, double R,
                        double fov);

/** modelConsts(), recomputed only when an input differs from the cached call's. */
const ModelConsts& cachedModelConsts(const CSemanticMap::TLikelihoodOptions& opt, size_t nLabels,
                                     double R, double fov, ModelConstsCache& cache);
}  // namespace semloc::semantic
