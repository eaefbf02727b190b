/* semloc — ActivePolicy: the greedy expected-entropy choice of the next motion. */
#include <mrpt/core/exceptions.h>
#include <mrpt/math/wrap2pi.h>
#include <semloc/active/ActivePolicy.h>
#include <semloc/filter/ParallelExecutor.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/models/semantic/DetectionProbability.h>
#include <semloc/observation/CObservationSemantic.h>
#include <semloc/world/World.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <tuple>

#include "io/ExactConfigWrite.h"

namespace semloc
{
namespace
{
constexpr const char* kSection = "ActiveLocalization";

/** A uniform number in [0, 1) from 53 bits of `g` (the same on every platform). */
double uniform01(std::mt19937_64& g)
{
    return static_cast<double>(g() >> 11) * 0x1.0p-53;
}

/** A Poisson draw of mean `mean` by inversion (small means: the clutter per scan). */
int poisson(double mean, std::mt19937_64& g)
{
    const double u = uniform01(g);
    double p = std::exp(-mean), cdf = p;
    int k = 0;
    while (u > cdf && k < 1000)
    {
        k++;
        p *= mean / k;
        cdf += p;
    }
    return k;
}

/** Shannon entropy [nats] of the weights exp(logw) (normalized here). */
double entropyOfLogWeights(const std::vector<double>& logw)
{
    const double top = *std::max_element(logw.begin(), logw.end());
    if (!std::isfinite(top))
    {
        return 0;  // every hypothesis impossible: nothing left to tell apart
    }
    double sum = 0, sumWLogW = 0;
    for (double l : logw)
    {
        const double w = std::exp(l - top);
        sum += w;
        sumWLogW += w > 0 ? w * (l - top) : 0;
    }
    return std::log(sum) - sumWLogW / sum;
}

/** The distinct labels of the map's objects, sorted. */
std::vector<std::string> mapLabels(const CSemanticMap& map)
{
    std::vector<std::string> labels;
    for (const auto& o : map.objects())
    {
        labels.push_back(o.label);
    }
    std::sort(labels.begin(), labels.end());
    labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
    return labels;
}

/** What the map's detector model would report from `pose`: each object in view detected
 *  with P_D times p_exist at its exact range (plus the range bias) and bearing, its label
 *  confused with p_confusion, and Poisson clutter. Two uniforms per map object are drawn
 *  whether it is in view or not, so the streams of two poses stay aligned. */
CObservationSemantic drawScan(const CSemanticMap& map, const std::vector<std::string>& labels,
                              const CObservationSemantic& sensor, const mrpt::math::TPose2D& pose,
                              std::mt19937_64& g)
{
    const auto& lo = map.likelihoodOptions;
    CObservationSemantic z;
    z.sensorPose = sensor.sensorPose;
    z.maxRange_m = sensor.maxRange_m;
    z.fov_rad = sensor.fov_rad;
    const double R = lo.maxRange(sensor), fov = lo.fieldOfView(sensor);
    std::vector<double> u(2 * map.objects().size());
    for (double& v : u)
    {
        v = uniform01(g);
    }
    const auto pick = [&](double v)
    {
        const auto n = static_cast<double>(labels.size());
        return labels[std::min(labels.size() - 1, static_cast<size_t>(v * n))];
    };
    for (const auto& seen :
         map.objectsInView(sensor, mrpt::poses::CPose3D(mrpt::poses::CPose2D(pose))))
    {
        const auto& o = map.objects()[seen.index];
        const double pd =
            lo.detectionProbability(seen.range_m, R, seen.bearing_rad, fov) * o.p_exist;
        if (u[2 * seen.index] >= pd)
        {
            continue;
        }
        TSemanticDetection d;
        const double v = u[2 * seen.index + 1];
        d.label = (v < lo.probabilistic.p_confusion && labels.size() > 1)
                      ? pick(v / lo.probabilistic.p_confusion)
                      : o.label;
        d.range_m = std::clamp(
            seen.range_m + rangeBias(lo.detector.range_bias_m, seen.bearing_rad, fov), 0.0, R);
        d.bearing_rad = seen.bearing_rad;
        z.detections.push_back(d);
    }
    const int clutter = poisson(lo.probabilistic.clutter_per_scan, g);
    for (int k = 0; k < clutter && !labels.empty(); k++)
    {
        TSemanticDetection d;
        d.range_m = R * uniform01(g);
        d.bearing_rad = (fov >= 2 * M_PI ? 2 * M_PI : fov) * (uniform01(g) - 0.5);
        d.label = pick(uniform01(g));
        z.detections.push_back(d);
    }
    return z;
}

}  // namespace

bool pathIsFree(const World& world, const mrpt::math::TPose2D& from, const TActiveMotion& m)
{
    if (m.distance_m <= 0)
    {
        return true;
    }
    const double h = from.phi + m.turn_rad;
    const mrpt::math::TPoint2D a(from.x, from.y),
        b(from.x + m.distance_m * std::cos(h), from.y + m.distance_m * std::sin(h));
    return world.isFree(b.x, b.y) && world.firstObjectOnSegment(a, b) < 0;
}

mrpt::poses::CPose2D TActiveMotion::increment() const
{
    return {distance_m * std::cos(turn_rad), distance_m * std::sin(turn_rad), turn_rad};
}

// ------------------------------------------------------------------ options

std::string ActivePolicy::objectiveName(TObjective o)
{
    return o == TObjective::GainPerMetre ? "gain_per_metre" : "entropy_plus_cost";
}

config::TValueRange ActivePolicy::TOptions::range(const std::string& key)
{
    if (key == "bin_xy_m")
    {
        return {1e-3, 1e3};
    }
    if (key == "bin_heading_deg")
    {
        return {1e-3, 360};
    }
    if (key == "travel_cost_per_m")
    {
        return {0, 1e3};
    }
    if (key == "overhead_m")
    {
        return {1e-3, 1e3};
    }
    if (key == "min_free_share")
    {
        return {0, 1};
    }
    if (key == "converged_var_xy_m2")
    {
        return {0, 1e6};
    }
    if (key == "distances_m" || key == "scan_every_m")
    {
        return {1e-3, 1e3};
    }
    THROW_EXCEPTION("[" + std::string(kSection) + "] '" + key + "' is not a numeric key");
}

void ActivePolicy::TOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                                const std::string& s)
{
    using namespace semloc::config;
    rejectUnknownKeys(
        c, s,
        {"headings", "distances_m", "look_around", "representatives", "bin_xy_m", "bin_heading_deg",
         "outcomes", "scan_every_m", "objective", "travel_cost_per_m", "overhead_m",
         "min_free_share", "converged_var_xy_m2", "seed", "threads"});
    readInt(c, s, "headings", headings, 1, kMaxHeadings);
    const auto d = range("distances_m");
    readDoubles(c, s, "distances_m", distances_m, kMaxDistances, d.lo, d.hi);
    readBool(c, s, "look_around", look_around);
    readInt(c, s, "representatives", representatives, 1, kMaxRepresentatives);
    readDouble(c, s, "bin_xy_m", bin_xy_m, range("bin_xy_m"));
    readDouble(c, s, "bin_heading_deg", bin_heading_deg, range("bin_heading_deg"));
    readInt(c, s, "outcomes", outcomes, 1, kMaxOutcomes);
    readDouble(c, s, "scan_every_m", scan_every_m, range("scan_every_m"));
    std::string name = objectiveName(objective);
    readChoice(
        c, s, "objective", name,
        {objectiveName(TObjective::EntropyPlusCost), objectiveName(TObjective::GainPerMetre)});
    objective = name == objectiveName(TObjective::GainPerMetre) ? TObjective::GainPerMetre
                                                                : TObjective::EntropyPlusCost;
    readDouble(c, s, "travel_cost_per_m", travel_cost_per_m, range("travel_cost_per_m"));
    readDouble(c, s, "overhead_m", overhead_m, range("overhead_m"));
    readDouble(c, s, "min_free_share", min_free_share, range("min_free_share"));
    readDouble(c, s, "converged_var_xy_m2", converged_var_xy_m2, range("converged_var_xy_m2"));
    int seedValue = static_cast<int>(seed);
    readInt(c, s, "seed", seedValue, 0, 2147483647);
    seed = static_cast<uint32_t>(seedValue);
    readInt(c, s, "threads", threads, 0, kMaxThreads);
}

void ActivePolicy::TOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                              const std::string& s) const
{
    detail::writeText(c, s, "headings", std::to_string(headings),
                      "candidate turns, evenly over the circle");
    detail::writeExactList(c, s, "distances_m", distances_m,
                           "candidate distances straight ahead after the turn [m]");
    detail::writeText(c, s, "look_around", look_around ? "true" : "false",
                      "also each turn on the spot (distance 0)");
    detail::writeText(c, s, "representatives", std::to_string(representatives),
                      "most weighted poses standing for the particles (one per bin)");
    detail::writeExact(c, s, "bin_xy_m", bin_xy_m, "bin size of the representatives in x, y [m]");
    detail::writeExact(c, s, "bin_heading_deg", bin_heading_deg,
                       "bin size of the representatives in heading [deg]");
    detail::writeText(c, s, "outcomes", std::to_string(outcomes),
                      "scans drawn per representative and motion");
    detail::writeExact(c, s, "scan_every_m", scan_every_m,
                       "the predicted scans along a path: one every this many metres [m]");
    detail::writeText(c, s, "objective", objectiveName(objective),
                      "entropy_plus_cost: E[H] + cost x d; gain_per_metre: (H - E[H]) / (d + "
                      "overhead_m)");
    detail::writeExact(c, s, "travel_cost_per_m", travel_cost_per_m,
                       "entropy_plus_cost: added to the expected entropy per metre [nats/m]");
    detail::writeExact(c, s, "overhead_m", overhead_m,
                       "gain_per_metre: metres added to every motion's distance [m]");
    detail::writeExact(c, s, "min_free_share", min_free_share,
                       "share of the weight whose path must stay in the free space");
    detail::writeExact(c, s, "converged_var_xy_m2", converged_var_xy_m2,
                       "stop rule: hand back to the route at this x-y variance [m^2]");
    detail::writeText(c, s, "seed", std::to_string(seed), "seed of the drawn scans");
    detail::writeText(c, s, "threads", std::to_string(threads),
                      "threads over the candidates; 0: every hardware thread");
}

// ------------------------------------------------------------------ the policy

ActivePolicy::ActivePolicy(const TOptions& options, const CSemanticMap& map, const World* world)
    : m_options(options), m_map(map), m_world(world)
{
    const auto& o = options;
    ASSERTMSG_(o.headings >= 1 && o.headings <= TOptions::kMaxHeadings,
               "ActivePolicy: headings out of range");
    ASSERTMSG_(
        !o.distances_m.empty() && std::all_of(o.distances_m.begin(), o.distances_m.end(),
                                              [](double d) { return d > 0 && std::isfinite(d); }),
        "ActivePolicy: distances_m must be positive numbers");
    ASSERTMSG_(o.representatives >= 1 && o.outcomes >= 1 && o.scan_every_m > 0 && o.bin_xy_m > 0 &&
                   o.bin_heading_deg > 0 && o.travel_cost_per_m >= 0 && o.overhead_m > 0 &&
                   o.min_free_share >= 0 && o.min_free_share <= 1 && o.converged_var_xy_m2 >= 0,
               "ActivePolicy: an option is out of range");
    ASSERTMSG_(o.threads >= 0, "ActivePolicy: threads < 0");
    m_executor = std::make_unique<ParallelExecutor>(static_cast<size_t>(o.threads));
}

ActivePolicy::~ActivePolicy() = default;

void ActivePolicy::setCostObserver(std::function<void(const TDecision&)> observer)
{
    m_costObserver = std::move(observer);
}

double ActivePolicy::filterSteps(double evaluations, size_t particles)
{
    return particles > 0 ? evaluations / static_cast<double>(particles)
                         : std::numeric_limits<double>::infinity();
}

std::vector<TActiveMotion> ActivePolicy::candidates() const
{
    std::vector<TActiveMotion> out;
    const int n = m_options.headings;
    for (int h = 0; h < n; h++)
    {
        const double turn = mrpt::math::wrapToPi(2 * M_PI * h / n);
        for (double d : m_options.distances_m)
        {
            out.push_back({turn, d});
        }
    }
    if (m_options.look_around)
    {
        for (int h = 1; h < n; h++)
        {
            out.push_back({mrpt::math::wrapToPi(2 * M_PI * h / n), 0.0});
        }
    }
    return out;
}

std::vector<ActivePolicy::TRepresentative> ActivePolicy::representatives(
    const mrpt::poses::CPosePDFParticles& pdf) const
{
    const auto K = static_cast<size_t>(m_options.representatives);
    struct Bin
    {
        double w = 0, x = 0, y = 0, c = 0, s = 0;
    };
    const auto& ps = pdf.m_particles;
    ASSERTMSG_(!ps.empty(), "ActivePolicy: no particles");
    double top = -std::numeric_limits<double>::infinity();
    for (const auto& p : ps)
    {
        top = std::max(top, p.log_w);
    }
    const double cell = m_options.bin_xy_m, cellPhi = mrpt::DEG2RAD(m_options.bin_heading_deg);
    std::map<std::tuple<long, long, long>, Bin> bins;  // ordered: the same order every run
    for (const auto& p : ps)
    {
        const double w = std::exp(p.log_w - top);
        const auto& d = p.d;
        auto& b = bins[{static_cast<long>(std::floor(d.x / cell)),
                        static_cast<long>(std::floor(d.y / cell)),
                        static_cast<long>(std::floor((d.phi + M_PI) / cellPhi))}];
        b.w += w;
        b.x += w * d.x;
        b.y += w * d.y;
        b.c += w * std::cos(d.phi);
        b.s += w * std::sin(d.phi);
    }
    std::vector<TRepresentative> all;
    double total = 0;
    for (const auto& [key, b] : bins)
    {
        if (b.w > 0)
        {
            all.push_back({{b.x / b.w, b.y / b.w, std::atan2(b.s, b.c)}, b.w});
            total += b.w;
        }
    }
    // More bins than representatives: systematic sampling of the bins in their (spatial)
    // order by weight, K pointers at (k + 1/2) / K of the total; a bin keeps the pointers'
    // share. The set then spreads over every hypothesis in proportion, not over the heaviest.
    std::vector<TRepresentative> reps;
    if (all.size() <= K)
    {
        reps = std::move(all);
    }
    else
    {
        double cum = 0;
        size_t k = 0;
        for (const auto& b : all)
        {
            cum += b.weight;
            size_t hits = 0;
            while (k < K && (static_cast<double>(k) + 0.5) / static_cast<double>(K) * total < cum)
            {
                hits++;
                k++;
            }
            if (hits > 0)
            {
                reps.push_back({b.pose, static_cast<double>(hits)});
            }
        }
    }
    std::stable_sort(reps.begin(), reps.end(),
                     [](const auto& a, const auto& b) { return a.weight > b.weight; });
    double sum = 0;
    for (const auto& r : reps)
    {
        sum += r.weight;
    }
    for (auto& r : reps)
    {
        r.weight /= sum;
    }
    return reps;
}

namespace
{
/** What every candidate of one decision is evaluated against. */
struct DecisionContext
{
    const CSemanticMap& map;
    const World* world;
    const ActivePolicy::TOptions& options;
    const std::vector<ActivePolicy::TRepresentative>& reps;
    const std::vector<double>& logw0;
    double entropy;
    const std::vector<std::string>& labels;
    const CObservationSemantic& sensor;
    uint64_t streamSeed;
};

/** The scans along the path of `m`: one every scan_every_m and at its end (one after a turn
 *  alone). */
size_t pathPoints(const TActiveMotion& m, double scanEvery)
{
    return m.distance_m > 0 ? static_cast<size_t>(std::ceil(m.distance_m / scanEvery - 1e-9)) : 1;
}

/** The candidate's free share, whether it is admissible and the likelihood evaluations its
 *  evaluation will take (no scan drawn). */
void admit(const DecisionContext& x, ActivePolicy::TCandidate& c)
{
    const auto& reps = x.reps;
    c.free_share = 0;
    for (const auto& r : reps)
    {
        c.free_share += (!x.world || pathIsFree(*x.world, r.pose, c.motion)) ? r.weight : 0;
    }
    c.admissible = c.motion.distance_m <= 0 || c.free_share >= x.options.min_free_share;
    c.expected_entropy = std::numeric_limits<double>::quiet_NaN();
    c.score = std::numeric_limits<double>::infinity();
    const auto K = static_cast<double>(reps.size());
    c.evaluations = c.admissible
                        ? K * K * x.options.outcomes *
                              static_cast<double>(pathPoints(c.motion, x.options.scan_every_m))
                        : 0.0;
}

/** E[H] after the admissible candidate's motion (see ActivePolicy) and its score. */
void evaluate(const DecisionContext& x, ActivePolicy::TCandidate& c)
{
    const auto& reps = x.reps;
    if (!c.admissible)
    {
        return;
    }
    const double d = c.motion.distance_m;
    const size_t points = pathPoints(c.motion, x.options.scan_every_m);
    const size_t K = reps.size();
    std::vector<std::vector<mrpt::math::TPose2D>> moved(points,
                                                        std::vector<mrpt::math::TPose2D>(K));
    for (size_t p = 0; p < points; p++)
    {
        const TActiveMotion part{c.motion.turn_rad,
                                 std::min(d, static_cast<double>(p + 1) * x.options.scan_every_m)};
        const mrpt::poses::CPose2D u = part.increment();
        for (size_t i = 0; i < K; i++)
        {
            moved[p][i] = (mrpt::poses::CPose2D(reps[i].pose) + u).asTPose();
        }
    }
    std::mt19937_64 g(x.streamSeed);  // common random numbers: every candidate the same draws
    std::vector<double> logl(K), logw(K);
    double expected = 0;
    const int outcomes = x.options.outcomes;
    for (size_t j = 0; j < reps.size(); j++)
    {
        for (int m = 0; m < outcomes; m++)
        {
            logw = x.logw0;
            for (size_t p = 0; p < points; p++)
            {
                const auto z = drawScan(x.map, x.labels, x.sensor, moved[p][j], g);
                x.map.logLikelihoods(z, moved[p].data(), K, logl.data());
                for (size_t i = 0; i < K; i++)
                {
                    // NaN and +inf count as impossible, as the filter counts them.
                    const bool usable = std::isfinite(logl[i]) || logl[i] < 0;
                    const double l = usable ? logl[i] : -std::numeric_limits<double>::infinity();
                    logw[i] += l;
                }
            }
            expected += reps[j].weight * entropyOfLogWeights(logw) / outcomes;
        }
    }
    c.expected_entropy = expected;
    c.score = x.options.objective == ActivePolicy::TObjective::GainPerMetre
                  ? -(x.entropy - expected) / (c.motion.distance_m + x.options.overhead_m)
                  : expected + x.options.travel_cost_per_m * c.motion.distance_m;
}

/** The first candidate of the lowest score; when none is admissible, the first turn on the
 *  spot, else the first candidate (straight ahead, the shortest distance). */
int chooseCandidate(const std::vector<ActivePolicy::TCandidate>& cs)
{
    int best = -1;
    for (size_t k = 0; k < cs.size(); k++)
    {
        if (cs[k].admissible && (best < 0 || cs[k].score < cs[static_cast<size_t>(best)].score))
        {
            best = static_cast<int>(k);
        }
    }
    if (best >= 0)
    {
        return best;
    }
    for (size_t k = 0; k < cs.size(); k++)
    {
        if (cs[k].motion.distance_m <= 0)
        {
            return static_cast<int>(k);
        }
    }
    return 0;
}
}  // namespace

ActivePolicy::TDecision ActivePolicy::decide(const mrpt::poses::CPosePDFParticles& pdf,
                                             const CObservationSemantic& sensor)
{
    TDecision out;
    const auto [cov, mean] = pdf.getCovarianceAndMean();
    (void)mean;
    out.var_xy_m2 = cov(0, 0) + cov(1, 1);
    const uint64_t decision = m_decisions++;
    if (out.var_xy_m2 <= m_options.converged_var_xy_m2)
    {
        out.converged = true;
        return out;
    }
    const auto reps = representatives(pdf);
    out.representatives = reps.size();
    std::vector<double> logw0(reps.size());
    for (size_t i = 0; i < reps.size(); i++)
    {
        logw0[i] = std::log(reps[i].weight);
    }
    out.entropy = entropyOfLogWeights(logw0);
    const auto motions = candidates();
    out.candidates.resize(motions.size());
    for (size_t k = 0; k < motions.size(); k++)
    {
        out.candidates[k].motion = motions[k];
    }
    const auto labels = mapLabels(m_map);
    const DecisionContext x{
        m_map,  m_world, m_options,
        reps,   logw0,   out.entropy,
        labels, sensor,  (static_cast<uint64_t>(m_options.seed) << 32) ^ decision};
    const auto forEachCandidate = [&](void (*f)(const DecisionContext&, TCandidate&))
    {
        m_executor->forEachRange(
            motions.size(),
            [&](size_t begin, size_t end, size_t /*thread*/)
            {
                for (size_t k = begin; k < end; k++)
                {
                    f(x, out.candidates[k]);
                }
            },
            1);
    };
    forEachCandidate(admit);
    for (const auto& c : out.candidates)
    {
        out.evaluations += c.evaluations;
    }
    if (m_costObserver)
    {
        m_costObserver(out);  // before the scans are drawn: a costly decision is told first
    }
    forEachCandidate(evaluate);
    out.chosen = chooseCandidate(out.candidates);
    out.motion = out.candidates[static_cast<size_t>(out.chosen)].motion;
    return out;
}

}  // namespace semloc
