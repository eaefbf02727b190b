/* semloc — the per-call constants of the semantic likelihood models (see
 * SemanticModelConstants.h). */
#include "maps/SemanticModelConstants.h"

#include <algorithm>
#include <cmath>

namespace semloc::semantic
{
namespace
{
/** The paper model's constants; returns sigma_theta [rad]. */
double paperConsts(const CSemanticMap::TLikelihoodOptions& opt, ModelConsts& k)
{
    k.ir = 1.0 / opt.sigma_range_m;
    k.ib = 1.0 / (opt.sigma_bearing_deg * M_PI / 180.0);
    k.logPu = std::log(opt.unmatched_penalty);
    k.logPo = opt.missed_object_penalty > 0 ? std::log(opt.missed_object_penalty) : k.logPu;
    // Matching a pair instead of leaving both unmatched gains s - log(p_u) - log(p_o) (> 0
    // to match; §III: s - 2 log(p_u)). Gain > 0 needs (dr/sr)^2 + (db/sb)^2 <
    // -2 (log(p_u) + log(p_o)).
    k.budget = -2 * (k.logPu + k.logPo);
    return 1.0 / k.ib;
}

/** The probabilistic model's constants; returns sigma_theta [rad]. */
double probabilisticConsts(const CSemanticMap::TLikelihoodOptions& opt, size_t nLabels, double R,
                           double fov, ModelConsts& k)
{
    const double sr = opt.sigma_range_m, sb = opt.sigma_bearing_deg * M_PI / 180.0;
    k.sb = sb;
    k.logNorm = -std::log(2 * M_PI * sr * sb);
    const double K = static_cast<double>(std::max<size_t>(1, nLabels));
    k.lambda = opt.clutter_per_scan;
    k.logKappa = std::log(k.lambda / (R * std::min(fov, 2 * M_PI) * K));
    k.logSame = std::log1p(-opt.p_confusion);
    k.confusable = opt.p_confusion > 0 && nLabels > 1;
    k.logOther = k.confusable ? std::log(opt.p_confusion / (K - 1)) : 0;
    k.ir = 1.0 / sr;
    k.ib = 1.0 / sb;
    // Gain > 0 needs the Gaussian terms to cost less than the best the rest can give:
    // P_D at its largest, a label term <= 0.
    const double pmax = std::clamp(std::max(opt.p_detect_near, opt.p_detect_far), 1e-6, 1 - 1e-6);
    // With the marginal association a pair is kept down to a gain of log kMarginalMinWeight.
    k.marginal = opt.association == CSemanticMap::Association::Marginal;
    k.gainFloor = k.marginal ? std::log(CSemanticMap::kMarginalMinWeight) : 0.0;
    k.budget = 2 * (std::log(pmax) - std::log1p(-pmax) + k.logNorm - k.logKappa - k.gainFloor);
    const double pmin = std::clamp(std::min(opt.p_detect_near, opt.p_detect_far), 1e-6, 1 - 1e-6);
    k.logQLo = std::log(pmin / (1 - pmin)) - 1e-9;
    k.logQHi = std::log(pmax / (1 - pmax)) + 1e-9;
    return sb;
}
}  // namespace

ModelConsts modelConsts(const CSemanticMap::TLikelihoodOptions& opt, size_t nLabels, double R,
                        double fov)
{
    ModelConsts k;
    const double sigmaB = opt.model == CSemanticMap::Model::Paper
                              ? paperConsts(opt, k)
                              : probabilisticConsts(opt, nLabels, R, fov, k);
    const double maxAbsDb = sigmaB * std::sqrt(std::max(0.0, k.budget));
    k.cosGate = maxAbsDb >= M_PI ? -2.0 : std::cos(maxAbsDb);
    return k;
}

const ModelConsts& cachedModelConsts(const CSemanticMap::TLikelihoodOptions& opt, size_t nLabels,
                                     double R, double fov, ModelConstsCache& cache)
{
    const std::array<double, 13> key = {static_cast<double>(opt.model),
                                        static_cast<double>(opt.association),
                                        opt.sigma_range_m,
                                        opt.sigma_bearing_deg,
                                        opt.unmatched_penalty,
                                        opt.missed_object_penalty,
                                        opt.p_detect_near,
                                        opt.p_detect_far,
                                        opt.clutter_per_scan,
                                        opt.p_confusion,
                                        static_cast<double>(nLabels),
                                        R,
                                        fov};
    if (!cache.valid || key != cache.key)
    {
        cache.consts = modelConsts(opt, nLabels, R, fov);
        cache.key = key;
        cache.valid = true;
    }
    return cache.consts;
}
}  // namespace semloc::semantic
