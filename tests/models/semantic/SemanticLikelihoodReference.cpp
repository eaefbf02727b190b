/* semloc tests — the semantic likelihoods written to be read (SemanticLikelihoodReference.h). */
#include "models/semantic/SemanticLikelihoodReference.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <set>
#include <string>
#include <vector>

namespace semloc::reference
{
namespace
{
using mrpt::math::TPose2D;
using Options = CSemanticMap::TLikelihoodOptions;

/** What a pose that is not finite scores, and a sum that is not finite: the fast path's
 *  floor, which keeps MRPT's finite-likelihood assertion true. */
constexpr double kFloor = -1e300;

/** One detection of z^r as the likelihoods use it. */
struct Detection
{
    double rho, theta;  // range [m], bearing in the sensor frame [rad]
    /** Its label if the map knows it, else empty (an MRPT landmark, or a label the map
     *  lacks on a detection that names an object). */
    std::string label;
    /** Index into the map's objects of the object it names (a known id), else -1. */
    int named;
};

/** One object of z^k: a map object inside the sensor's range and field of view. */
struct Predicted
{
    double rho, theta;  // range [m], bearing in the sensor frame [rad]
    size_t object;      // index into the map's objects
};

/** The observation as the likelihoods see it. */
struct Scan
{
    double R = 0, fov = 0;            // effective max range [m] and field of view [rad]
    double sx = 0, sy = 0, syaw = 0;  // the sensor's pose on the vehicle (2D part)
    std::vector<Detection> z_r;
    /** A sensor without a positive finite range and field of view scores 0 everywhere. */
    bool usable() const { return R > 0 && std::isfinite(R) && fov > 0 && std::isfinite(fov); }
};

int objectWithId(const CSemanticMap& map, int32_t id)
{
    const auto& objs = map.objects();
    for (size_t i = 0; i < objs.size(); i++)
    {
        if (objs[i].id == id)
        {
            return static_cast<int>(i);
        }
    }
    return -1;
}

std::set<std::string> labelsOf(const CSemanticMap& map)
{
    std::set<std::string> labels;
    for (const auto& o : map.objects())
    {
        labels.insert(o.label);
        for (const auto& c : o.classes)
        {
            labels.insert(c.first);  // a class an object may be is a label of the map
        }
    }
    return labels;
}

/** |bearing| <= 4 pi and, wrapped into [-pi, pi], inside the field of view (+1e-9). */
bool bearingInFov(double b, double fov)
{
    return std::abs(b) <= 4 * M_PI && std::abs(std::remainder(b, 2 * M_PI)) <= 0.5 * fov + 1e-9;
}

/** A detection's range `rho` at bearing `theta` less the detector's range bias, the sum of
 *  c_k u^k with u the bearing over half the view (over pi for a full circle), within [0, R]. */
double unbiasedRange(const Options& opt, double rho, double theta, double R, double fov)
{
    const double u = std::remainder(theta, 2 * M_PI) / (fov < 2 * M_PI ? fov / 2 : M_PI);
    double bias = 0, power = 1;
    for (const double c : opt.detector.range_bias_m)
    {
        bias += c * power;
        power *= u;
    }
    return std::min(R, std::max(0.0, rho - bias));
}

Scan scanOf(const CSemanticMap& map, const CObservationSemantic& obs)
{
    const Options& opt = map.likelihoodOptions;
    Scan s;
    s.R = opt.detector.max_range_m > 0 ? opt.detector.max_range_m : obs.maxRange_m;
    s.fov = opt.detector.fov_deg > 0 ? opt.detector.fov_deg * M_PI / 180 : obs.fov_rad;
    s.sx = obs.sensorPose.x();
    s.sy = obs.sensorPose.y();
    s.syaw = obs.sensorPose.yaw();
    if (!s.usable())
    {
        return s;
    }
    const std::set<std::string> labels = labelsOf(map);
    for (const auto& d : obs.detections)
    {
        const bool valid = !d.label.empty() && d.range_m >= 0 && d.range_m <= s.R &&
                           d.confidence >= 0 && d.confidence <= 1 &&
                           d.confidence >= opt.detector.min_confidence &&
                           bearingInFov(d.bearing_rad, s.fov);
        if (!valid)
        {
            continue;
        }
        const int named = d.object_id >= 0 ? objectWithId(map, d.object_id) : -1;
        const bool known = labels.count(d.label) > 0;
        if (named < 0 && !known)
        {
            continue;  // unknown to the map: unmatched at every pose, a constant factor
        }
        s.z_r.push_back({unbiasedRange(opt, d.range_m, d.bearing_rad, s.R, s.fov), d.bearing_rad,
                         known ? d.label : std::string(), named});
    }
    return s;
}

Scan scanOf(const CSemanticMap& map, const mrpt::obs::CObservationBearingRange& obs)
{
    const Options& opt = map.likelihoodOptions;
    Scan s;
    s.R = opt.detector.max_range_m > 0 ? opt.detector.max_range_m : obs.maxSensorDistance;
    s.fov = opt.detector.fov_deg > 0 ? opt.detector.fov_deg * M_PI / 180 : obs.fieldOfView_yaw;
    if (s.fov == 0)
    {
        s.fov = 2 * M_PI;  // MRPT leaves it 0 when the sensor has no FOV limit
    }
    s.sx = obs.sensorLocationOnRobot.x();
    s.sy = obs.sensorLocationOnRobot.y();
    s.syaw = obs.sensorLocationOnRobot.yaw();
    if (!s.usable())
    {
        return s;
    }
    for (const auto& m : obs.sensedData)
    {
        const double rho = m.range, theta = m.yaw;
        if (!(rho >= 0 && rho <= s.R) || !bearingInFov(theta, s.fov))
        {
            continue;
        }
        const int named = m.landmarkID >= 0 ? objectWithId(map, m.landmarkID) : -1;
        if (m.landmarkID >= 0 && named < 0)
        {
            continue;  // an id the map does not have
        }
        // No label: any object.
        s.z_r.push_back({unbiasedRange(opt, rho, theta, s.R, s.fov), theta, std::string(), named});
    }
    return s;
}

/** z^k: the map objects within range R and field of view fov of the sensor, for the vehicle
 *  at `pose` (the sensor's pose on the vehicle composed with it). */
std::vector<Predicted> predict(const CSemanticMap& map, const Scan& s, const TPose2D& pose,
                               size_t& onEdge)
{
    const double cp = std::cos(pose.phi), sp = std::sin(pose.phi);
    const double x = pose.x + cp * s.sx - sp * s.sy;
    const double y = pose.y + sp * s.sx + cp * s.sy;
    // The sensor's axis in the world: the vehicle's heading turned by the sensor's yaw.
    const double c = cp * std::cos(s.syaw) - sp * std::sin(s.syaw);
    const double sn = sp * std::cos(s.syaw) + cp * std::sin(s.syaw);
    std::vector<Predicted> z_k;
    const auto& objs = map.objects();
    for (size_t i = 0; i < objs.size(); i++)
    {
        const double dx = objs[i].x - x, dy = objs[i].y - y;
        const double rho = std::hypot(dx, dy);
        const double theta = std::atan2(-sn * dx + c * dy, c * dx + sn * dy);
        const bool fullCircle = s.fov >= 2 * M_PI;
        onEdge += rho == 0 || std::abs(rho - s.R) <= 1e-9 * s.R ||
                  (!fullCircle && std::abs(std::abs(theta) - 0.5 * s.fov) <= 1e-9);
        if (rho <= s.R && (fullCircle || std::abs(theta) <= 0.5 * s.fov))
        {
            z_k.push_back({rho, theta, i});
        }
    }
    return z_k;
}

/** May detection d be object `i` (of label `label`)? The object it names only; else one of
 *  its label, or any object if it has no label or `anyLabel` (class confusion). */
bool mayPair(const Detection& d, size_t i, const std::string& label, bool anyLabel)
{
    if (d.named >= 0)
    {
        return static_cast<size_t>(d.named) == i;
    }
    return d.label.empty() || anyLabel || d.label == label;
}

/** Bearing difference theta^r - theta^k wrapped into [-pi, pi]. */
double bearingDiff(const Detection& d, const Predicted& v)
{
    return std::remainder(d.theta - v.theta, 2 * M_PI);
}

struct Pair
{
    double gain;  // what matching j with v adds to the log-likelihood (> 0)
    size_t j, v;  // indices into z^r and z^k
};

/** The greedy one-to-one association: pairs by decreasing gain (ties by j, then v), each
 *  taken unless its detection or its object is taken already. (z^k is in map order here, in
 *  index order in the fast path: the two may differ only between pairs of equal gain.) */
std::vector<Pair> associate(std::vector<Pair> pairs)
{
    std::sort(pairs.begin(), pairs.end(),
              [](const Pair& a, const Pair& b) {
                  return a.gain != b.gain ? a.gain > b.gain : a.j != b.j ? a.j < b.j : a.v < b.v;
              });
    std::set<size_t> usedJ, usedV;
    std::vector<Pair> chosen;
    for (const Pair& p : pairs)
    {
        if (usedJ.count(p.j) == 0 && usedV.count(p.v) == 0)
        {
            usedJ.insert(p.j);
            usedV.insert(p.v);
            chosen.push_back(p);
        }
    }
    return chosen;
}

/** The paper's likelihood (§III): z^r has l detections (rho^r, theta^r), z^k the q objects
 *  predicted visible (rho^k, theta^k), m pairs are matched:
 *
 *      log w = sum_{i=1..m} [ -1/2 ((rho^r_i - rho^k_i) / sigma_rho)^2
 *                             -1/2 ((theta^r_i - theta^k_i) / sigma_theta)^2 ]
 *              + d log(p_u),          d = q + l - 2m
 *
 *  (with missed_object_penalty p_o > 0: (l - m) log(p_u) + (q - m) log(p_o) instead).
 *  Matching a pair gains its Gaussian terms s_i less the log(p_u) + log(p_o) it saves: pairs
 *  that may pair (mayPair, by label) with a positive gain, associated greedily. */
double paper(const CSemanticMap& map, const Scan& s, const TPose2D& pose, SemanticTerms& t)
{
    const Options& opt = map.likelihoodOptions;
    const double sigmaRho = opt.detector.sigma_range_m,
                 sigmaTheta = opt.detector.sigma_bearing_deg * M_PI / 180;
    const double logPu = std::log(opt.paper.unmatched_penalty);
    const double logPo =
        opt.paper.missed_object_penalty > 0 ? std::log(opt.paper.missed_object_penalty) : logPu;
    const std::vector<Predicted> z_k = predict(map, s, pose, t.onEdge);
    const auto& objs = map.objects();
    // With misread ranges (eps > 0) the range factor is (1 - eps) N0 + eps sqrt(2 pi) sigma / R.
    const double eps = opt.detector.p_range_outlier;
    const double outlierFactor = eps * std::sqrt(2 * M_PI) * sigmaRho / s.R;
    auto gaussians = [&](const Detection& d, const Predicted& v)
    {
        const double dRho = (d.rho - v.rho) / sigmaRho;
        const double dTheta = bearingDiff(d, v) / sigmaTheta;
        const double rangeTerm =
            eps > 0 ? std::log((1 - eps) * std::exp(-0.5 * dRho * dRho) + outlierFactor)
                    : -0.5 * dRho * dRho;
        return rangeTerm - 0.5 * dTheta * dTheta;
    };
    std::vector<Pair> pairs;
    for (size_t j = 0; j < s.z_r.size(); j++)
    {
        for (size_t v = 0; v < z_k.size(); v++)
        {
            if (!mayPair(s.z_r[j], z_k[v].object, objs[z_k[v].object].label, false))
            {
                continue;
            }
            const double gain = gaussians(s.z_r[j], z_k[v]) - logPu - logPo;
            if (gain > 0)
            {
                pairs.push_back({gain, j, v});
            }
        }
    }
    const std::vector<Pair> matched = associate(pairs);
    double sum = 0;
    for (const Pair& p : matched)
    {
        sum += gaussians(s.z_r[p.j], z_k[p.v]);
    }
    t.l = s.z_r.size();
    t.q = z_k.size();
    t.m = matched.size();
    return static_cast<double>(t.l - t.m) * logPu + static_cast<double>(t.q - t.m) * logPo + sum;
}

/** Pairs whose weight w = e^gain is below e^-50 change a sum over associations (>= 1: the
 *  empty association) by less than a double's rounding: the reference leaves them out. */
constexpr double kNegligibleLogWeight = -50;

/** log of the sum over every one-to-one association of the `pairs` (detection j, object v,
 *  log w_jv = gain) of the product of its pairs' w, the empty association counting 1: each
 *  detection in turn is clutter or one of its objects not yet taken. Plain enumeration. */
double sumOverAssociations(const std::vector<Pair>& pairs, size_t detections)
{
    // In logarithms: a product of a few w can exceed a double's range.
    auto logAdd = [](double a, double b)
    { return std::max(a, b) + std::log1p(std::exp(-std::abs(a - b))); };
    std::set<size_t> taken;
    std::function<double(size_t)> logFrom = [&](size_t j) -> double
    {
        if (j == detections)
        {
            return 0.0;
        }
        double logSum = logFrom(j + 1);  // detection j is clutter
        for (const Pair& p : pairs)
        {
            if (p.j == j && taken.count(p.v) == 0)
            {
                taken.insert(p.v);
                logSum = logAdd(logSum, p.gain + logFrom(j + 1));
                taken.erase(p.v);
            }
        }
        return logSum;
    };
    return logFrom(0);
}

/** The terms of the probabilistic model for one scan (see probabilistic()). */
class ProbabilisticTerms
{
public:
    ProbabilisticTerms(const CSemanticMap& map, const Scan& s)
        : m_opt(map.likelihoodOptions),
          m_s(s),
          m_objs(map.objects()),
          m_sigmaRho(m_opt.detector.sigma_range_m),
          m_sigmaTheta(m_opt.detector.sigma_bearing_deg * M_PI / 180),
          m_K(std::max<double>(1, static_cast<double>(labelsOf(map).size()))),
          m_confusion(m_opt.probabilistic.p_confusion > 0 && m_K > 1)
    {
        logKappa = std::log(m_opt.probabilistic.clutter_per_scan /
                            (s.R * std::min(s.fov, 2 * M_PI) * m_K));
    }
    /** log kappa, the clutter density. */
    double logKappa = 0;

    /** P_D(rho, theta) of the detector times the object's p_exist. */
    double pD(const Predicted& v) const
    {
        double p =
            m_opt.probabilistic.p_detect_near +
            (m_opt.probabilistic.p_detect_far - m_opt.probabilistic.p_detect_near) * v.rho / m_s.R;
        if (m_opt.probabilistic.p_detect_edge_ratio < 1 && m_s.fov < 2 * M_PI)
        {
            const double off = std::min(std::abs(v.theta) / (0.5 * m_s.fov), 1.0);
            p *= 1 - (1 - m_opt.probabilistic.p_detect_edge_ratio) * off;
        }
        const double exist = m_objs[v.object].p_exist;
        return std::clamp(exist < 1 ? exist * p : p, 1e-6, 1 - 1e-6);
    }
    /** log P_D + log C + log(range density) + log N of a matched pair; the range density is
     *  N(d_rho; sigma_rho), or with misread ranges (eps > 0) (1 - eps) N + eps / R. */
    double matchedTerm(const Detection& d, const Predicted& v) const
    {
        // An object's position sigma widens both Gaussians: range by sigma_m, bearing by
        // sigma_m / max(rho, 2 sigma_m).
        const double sm = m_objs[v.object].sigma_m;
        const double sRho = std::sqrt(m_sigmaRho * m_sigmaRho + sm * sm);
        const double lateral = sm > 0 ? sm / std::max(v.rho, 2 * sm) : 0.0;
        const double sTheta = std::sqrt(m_sigmaTheta * m_sigmaTheta + lateral * lateral);
        const double eps = m_opt.detector.p_range_outlier;
        const double range =
            eps > 0 ? std::log((1 - eps) * std::exp(logN(d.rho - v.rho, sRho)) + eps / m_s.R)
                    : logN(d.rho - v.rho, sRho);
        return std::log(pD(v)) + logC(d, v) + range + logN(bearingDiff(d, v), sTheta);
    }
    /** The pairs that may pair (by id, label, confusion) whose gain exceeds `floor`. */
    std::vector<Pair> pairs(const std::vector<Predicted>& z_k, double floor) const
    {
        std::vector<Pair> out;
        for (size_t j = 0; j < m_s.z_r.size(); j++)
        {
            for (size_t v = 0; v < z_k.size(); v++)
            {
                const auto& ob = m_objs[z_k[v].object];
                if (!mayPair(m_s.z_r[j], z_k[v].object, ob.label,
                             m_confusion || !ob.classes.empty()))
                {
                    continue;
                }
                const double gain =
                    matchedTerm(m_s.z_r[j], z_k[v]) - std::log(1 - pD(z_k[v])) - logKappa;
                if (std::isinf(gain))
                {
                    continue;  // a class it cannot be
                }
                if (gain > floor)
                {
                    out.push_back({gain, j, v});
                }
            }
        }
        return out;
    }

private:
    static double logN(double d, double sigma)
    {
        return -0.5 * (d / sigma) * (d / sigma) - std::log(std::sqrt(2 * M_PI) * sigma);
    }
    double logC(const Detection& d, const Predicted& v) const
    {
        if (d.label.empty())
        {
            return 0.0;
        }
        const auto& classes = m_objs[v.object].classes;
        if (!classes.empty())
        {
            // C(L_j | v) = sum_c pi(c) C(L_j | c).
            double pi = 0;
            for (const auto& [label, p] : classes)
            {
                pi += label == d.label ? p : 0.0;
            }
            const double w =
                pi * (1 - m_opt.probabilistic.p_confusion) +
                (1 - pi) * (m_confusion ? m_opt.probabilistic.p_confusion / (m_K - 1) : 0.0);
            if (w > 0)
            {
                return std::log(w);
            }
            return d.named >= 0 ? 0.0 : -std::numeric_limits<double>::infinity();
        }
        if (d.label == m_objs[v.object].label)
        {
            return std::log(1 - m_opt.probabilistic.p_confusion);
        }
        return m_confusion ? std::log(m_opt.probabilistic.p_confusion / (m_K - 1)) : 0.0;
    }

    const Options& m_opt;
    const Scan& m_s;
    const std::vector<CSemanticMap::TObject>& m_objs;
    double m_sigmaRho, m_sigmaTheta, m_K;
    bool m_confusion;
};

/** The probabilistic model: each object of z^k is detected with
 *      P_D(rho, theta) = clamp((p_detect_near + (p_detect_far - p_detect_near) rho / R)
 *                              (1 - (1 - p_detect_edge_ratio) min(|theta| / (fov / 2), 1)),
 *                              1e-6, 1 - 1e-6)      (the second factor 1 when fov >= 2 pi),
 *  a detection is labelled right with C = 1 - p_c, as any other of the K map labels with
 *  C = p_c / (K - 1) (no label term for a detection without a label the map knows; the code
 *  also gives none to a detection that names an object of another label when p_c = 0 or
 *  K = 1: the id wins), its range and bearing have Gaussian noise N(.; sigma), and Poisson
 *  clutter of mean lambda is uniform over the field of view and the labels:
 *  kappa = lambda / (R min(fov, 2 pi) K). With the association A:
 *
 *      log p(z | x) = -lambda + sum_{(j,v) in A} [log P_D(rho_v) + log C(L_j | L_v)
 *                                 + log N(d_rho; sigma_rho) + log N(d_theta; sigma_theta)]
 *                   + sum_{v unmatched} log(1 - P_D(rho_v)) + sum_{j unmatched} log kappa
 *
 *  A pair's gain (what matching it adds over leaving both unmatched) is
 *  log P_D - log(1 - P_D) + log C + log N + log N - log kappa; A takes the pairs that gain,
 *  greedily. With class confusion (p_c > 0, K > 1) a detection may be an object of any label.
 *
 *  With association = marginal, the sum over every association A of p(z, A | x):
 *
 *      log p(z | x) = -lambda + l log kappa + sum_v log(1 - P_D(rho_v))
 *                   + log sum_A prod_{(j,v) in A} exp(gain_jv)                          */
double probabilistic(const CSemanticMap& map, const Scan& s, const TPose2D& pose, SemanticTerms& t)
{
    const ProbabilisticTerms terms(map, s);
    const double lambda = map.likelihoodOptions.probabilistic.clutter_per_scan;
    const std::vector<Predicted> z_k = predict(map, s, pose, t.onEdge);
    const bool marginal =
        map.likelihoodOptions.probabilistic.association == CSemanticMap::Association::Marginal;
    const std::vector<Pair> pairs = terms.pairs(z_k, marginal ? kNegligibleLogWeight : 0.0);
    t.l = s.z_r.size();
    t.q = z_k.size();
    if (marginal)
    {
        // Every association at once: the terms of a detection matched to object v differ from
        // those of both left unmatched by the pair's gain, log w_jv.
        double logP = -lambda + static_cast<double>(t.l) * terms.logKappa;
        for (const Predicted& v : z_k)
        {
            logP += std::log(1 - terms.pD(v));
        }
        t.m = pairs.size();
        return logP + sumOverAssociations(pairs, s.z_r.size());
    }
    const std::vector<Pair> matched = associate(pairs);
    std::vector<bool> detMatched(s.z_r.size(), false), objMatched(z_k.size(), false);
    double logP = -lambda;
    for (const Pair& p : matched)
    {
        logP += terms.matchedTerm(s.z_r[p.j], z_k[p.v]);
        detMatched[p.j] = objMatched[p.v] = true;
    }
    for (size_t v = 0; v < z_k.size(); v++)
    {
        logP += objMatched[v] ? 0.0 : std::log(1 - terms.pD(z_k[v]));
    }
    for (size_t j = 0; j < s.z_r.size(); j++)
    {
        logP += detMatched[j] ? 0.0 : terms.logKappa;
    }
    t.m = matched.size();
    return logP;
}

double evaluate(const CSemanticMap& map, const Scan& s, const TPose2D& pose, SemanticTerms* terms)
{
    SemanticTerms t;
    double logLik = 0;  // an unusable sensor: uninformative, the same at every pose
    if (s.usable() && !(std::isfinite(pose.x) && std::isfinite(pose.y) && std::isfinite(pose.phi)))
    {
        logLik = kFloor;
    }
    else if (s.usable())
    {
        logLik = map.likelihoodOptions.model == CSemanticMap::Model::Paper
                     ? paper(map, s, pose, t)
                     : probabilistic(map, s, pose, t);
        logLik = std::isfinite(logLik) ? logLik : kFloor;
    }
    if (terms != nullptr)
    {
        *terms = t;
    }
    return logLik;
}
}  // namespace

double semanticLogLikelihood(const CSemanticMap& map, const CObservationSemantic& obs,
                             const TPose2D& pose, SemanticTerms* terms)
{
    return evaluate(map, scanOf(map, obs), pose, terms);
}

double semanticLogLikelihood(const CSemanticMap& map,
                             const mrpt::obs::CObservationBearingRange& obs, const TPose2D& pose,
                             SemanticTerms* terms)
{
    return evaluate(map, scanOf(map, obs), pose, terms);
}
}  // namespace semloc::reference
