/* semloc — the per-call constants of the semantic likelihood models (see
 * SemanticModelConstants.h). */
#include "models/semantic/SemanticModelConstants.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace semloc::semantic
{
namespace
{
/** The paper model's constants; returns sigma_theta [rad]. */
double paperConsts(const CSemanticMap::TLikelihoodOptions& opt, ModelConsts& k)
{
    k.ir = 1.0 / opt.detector.sigma_range_m;
    k.ib = 1.0 / (opt.detector.sigma_bearing_deg * M_PI / 180.0);
    k.logPu = std::log(opt.paper.unmatched_penalty);
    k.logPo =
        opt.paper.missed_object_penalty > 0 ? std::log(opt.paper.missed_object_penalty) : k.logPu;
    // Matching a pair instead of leaving both unmatched gains s - log(p_u) - log(p_o) (> 0
    // to match; §III: s - 2 log(p_u)). Gain > 0 needs (dr/sr)^2 + (db/sb)^2 <
    // -2 (log(p_u) + log(p_o)).
    k.rangeBudget = k.bearingBudget = -2 * (k.logPu + k.logPo);
    return 1.0 / k.ib;
}

/** The probabilistic model's constants; returns the largest bearing sigma of a pair [rad]. */
double probabilisticConsts(const CSemanticMap::TLikelihoodOptions& opt, size_t nLabels, double R,
                           double fov, const MapSurety& map, ModelConsts& k)
{
    const double sr = opt.detector.sigma_range_m,
                 sb = opt.detector.sigma_bearing_deg * M_PI / 180.0;
    k.sb = sb;
    k.logNorm = -std::log(2 * M_PI * sr * sb);
    const double K = static_cast<double>(std::max<size_t>(1, nLabels));
    k.lambda = opt.probabilistic.clutter_per_scan;
    k.logKappa = std::log(k.lambda / (R * std::min(fov, 2 * M_PI) * K));
    k.logSame = std::log1p(-opt.probabilistic.p_confusion);
    k.confusable = opt.probabilistic.p_confusion > 0 && nLabels > 1;
    k.logOther = k.confusable ? std::log(opt.probabilistic.p_confusion / (K - 1)) : 0;
    k.ir = 1.0 / sr;
    k.ib = 1.0 / sb;
    // Gain > 0 needs the Gaussian terms to cost less than the best the rest can give:
    // P_D at its largest, a label term <= 0.
    const double pmax = std::clamp(
        std::max(opt.probabilistic.p_detect_near, opt.probabilistic.p_detect_far), 1e-6, 1 - 1e-6);
    // With the marginal association a pair is kept down to a gain of log kMarginalMinWeight.
    k.marginal = opt.probabilistic.association == CSemanticMap::Association::Marginal;
    k.gainFloor = k.marginal ? std::log(CSemanticMap::kMarginalMinWeight) : 0.0;
    k.rangeBudget = k.bearingBudget =
        2 * (std::log(pmax) - std::log1p(-pmax) + k.logNorm - k.logKappa - k.gainFloor);
    // An object's P_D is p_exist times the detector's, clamped the same way; the edge of the
    // field of view takes p_detect_edge_ratio of it.
    const double edge = fov < 2 * M_PI ? opt.probabilistic.p_detect_edge_ratio : 1.0;
    const double pmin =
        std::clamp(std::min(opt.probabilistic.p_detect_near, opt.probabilistic.p_detect_far) *
                       edge * map.minExist,
                   1e-6, 1 - 1e-6);
    k.logQLo = std::log(pmin / (1 - pmin)) - 1e-9;
    k.logQHi = std::log(pmax / (1 - pmax)) + 1e-9;
    // Objects with a class distribution may be any of the labels they list.
    k.classes = map.classes;
    k.planAll = k.confusable || k.classes;
    k.sameW = 1 - opt.probabilistic.p_confusion;
    k.otherW = k.confusable ? opt.probabilistic.p_confusion / (K - 1) : 0;
    // A position sigma widens a pair's Gaussians: the gates take the widest.
    k.sr2 = sr * sr;
    k.sb2 = sb * sb;
    k.uncertain = map.maxSigma > 0;
    if (k.uncertain)
    {
        k.gateIr = 1 / std::sqrt(k.sr2 + map.maxSigma * map.maxSigma);
        return std::sqrt(k.sb2 + 0.25);  // sigma_m / max(rho, 2 sigma_m) <= 1/2
    }
    return sb;
}

/** p_range_outlier > 0: the range term becomes the mixture (1 - eps) N(dr; sigma_rho) + eps / R
 *  (paper model: the same over the Gaussian's peak, so a perfect match still costs ~0), and
 *  the gates those of the gain C0 + rangeTerm - (db/sigma_b)^2 / 2 with the model's best
 *  other terms C0. */
void rangeOutlierConsts(const CSemanticMap::TLikelihoodOptions& opt, double R, ModelConsts& k)
{
    const double eps = opt.detector.p_range_outlier;
    const double logPeak = -std::log(std::sqrt(2 * M_PI) * opt.detector.sigma_range_m);  // log N(0)
    const bool paper = opt.model == CSemanticMap::Model::Paper;
    k.rangeOutliers = true;
    k.logKeep = std::log1p(-eps);
    k.mixA = std::log1p(-eps) + (paper ? 0.0 : logPeak);
    k.mixB = std::log(eps / R) - (paper ? logPeak : 0.0);
    double c0 = 0;
    if (paper)
    {
        c0 = -(k.logPu + k.logPo);
    }
    else
    {
        k.logNormBearing = -std::log(std::sqrt(2 * M_PI) * k.sb);
        c0 = k.logQHi + k.logNormBearing - k.logKappa - k.gainFloor;
    }
    const double rangeMax = rangeTerm(k, 0.0);
    // Widened by a relative 1e-9 (the gates are necessary conditions; rounding ~1e-14).
    k.bearingBudget = 2 * (c0 + rangeMax) * (1 + 1e-9) + 1e-9;
    // rangeTerm(h) > -c0 needs e^(mixA + h) > e^-c0 - e^mixB: any h when a misread range
    // alone gains.
    k.rangeBudget =
        k.mixB + c0 >= -1e-9
            ? std::numeric_limits<double>::infinity()
            : 2 * (k.mixA + c0 - std::log1p(-std::exp(k.mixB + c0))) * (1 + 1e-9) + 1e-9;
}
}  // namespace

ModelConsts modelConsts(const CSemanticMap::TLikelihoodOptions& opt, size_t nLabels, double R,
                        double fov, const MapSurety& map)
{
    ModelConsts k;
    const double sigmaB = opt.model == CSemanticMap::Model::Paper
                              ? paperConsts(opt, k)
                              : probabilisticConsts(opt, nLabels, R, fov, map, k);
    if (opt.detector.p_range_outlier > 0)
    {
        rangeOutlierConsts(opt, R, k);
    }
    if (!k.uncertain)
    {
        k.gateIr = k.ir;
    }
    const double maxAbsDb = sigmaB * std::sqrt(std::max(0.0, k.bearingBudget));
    k.cosGate = maxAbsDb >= M_PI ? -2.0 : std::cos(maxAbsDb);
    return k;
}

const ModelConsts& cachedModelConsts(const CSemanticMap::TLikelihoodOptions& opt, size_t nLabels,
                                     double R, double fov, const MapSurety& map,
                                     ModelConstsCache& cache)
{
    const std::array<double, 18> key = {static_cast<double>(opt.model),
                                        static_cast<double>(opt.probabilistic.association),
                                        opt.detector.sigma_range_m,
                                        opt.detector.sigma_bearing_deg,
                                        opt.paper.unmatched_penalty,
                                        opt.paper.missed_object_penalty,
                                        opt.probabilistic.p_detect_near,
                                        opt.probabilistic.p_detect_far,
                                        opt.probabilistic.p_detect_edge_ratio,
                                        opt.probabilistic.clutter_per_scan,
                                        opt.probabilistic.p_confusion,
                                        opt.detector.p_range_outlier,
                                        static_cast<double>(nLabels),
                                        R,
                                        fov,
                                        map.maxSigma,
                                        map.minExist,
                                        static_cast<double>(map.classes)};
    if (!cache.valid || key != cache.key)
    {
        cache.consts = modelConsts(opt, nLabels, R, fov, map);
        cache.key = key;
        cache.valid = true;
    }
    return cache.consts;
}
}  // namespace semloc::semantic
