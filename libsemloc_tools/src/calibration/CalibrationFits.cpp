/* semloc — the fits of semloc-calibrate (docs/tools.md, "semloc-calibrate"). */
#include "calibration/CalibrationFits.h"

#include <mrpt/core/bits_math.h>
#include <semloc/filter/MotionModelConfig.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace semloc::detail
{
namespace
{
constexpr double kZ95 = 1.96;

/** A number in 4 significant digits. */
std::string text(double v)
{
    std::ostringstream s;
    s << std::setprecision(4) << v;
    return s.str();
}

double median(std::vector<double> x)
{
    if (x.empty())
    {
        return 0;
    }
    const size_t h = x.size() / 2;
    std::nth_element(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(h), x.end());
    const double hi = x[h];
    if (x.size() % 2 == 1)
    {
        return hi;
    }
    return 0.5 * (hi + *std::max_element(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(h)));
}

TCalibrationFit fit(double value, size_t n, double ci95, const std::string& method)
{
    TCalibrationFit f;
    f.value = value;
    f.n = n;
    f.ci95 = ci95;
    f.method = method;
    return f;
}

/** The standard deviation of `x` (0 for fewer than 2 values). */
double standardDeviation(const std::vector<double>& x)
{
    if (x.size() < 2)
    {
        return 0;
    }
    double m = 0, ss = 0;
    for (const double v : x)
    {
        m += v;
    }
    m /= static_cast<double>(x.size());
    for (const double v : x)
    {
        ss += (v - m) * (v - m);
    }
    return std::sqrt(ss / static_cast<double>(x.size() - 1));
}

/** A robust sigma with its interval: the MAD's asymptotic efficiency is 37 %. When more than
 *  half the residuals are one value (readings quantized coarser than their noise) the MAD is
 *  0: the standard deviation is taken instead. */
TCalibrationFit robustSigma(const std::vector<double>& x)
{
    const double mad = madSigma(x);
    const double s = mad > 0 ? mad : standardDeviation(x);
    const double n = static_cast<double>(x.size());
    return fit(s, x.size(), kZ95 * 1.166 * s / std::sqrt(std::max(n, 1.0)),
               mad > 0 || s == 0 ? "1.4826 MAD of the matched residuals"
                                 : "standard deviation of the matched residuals (their MAD is 0: "
                                   "more than half are one value)");
}

constexpr double kInvPhi = 0.6180339887498949;
constexpr int kGoldenIterations = 60;
constexpr double kGoldenWidth = 1e-10;

/** The maximum of a concave function on [lo, hi] by golden-section search. */
template <typename F>
double goldenMax(F f, double lo, double hi)
{
    double a = lo, b = hi, c = b - kInvPhi * (b - a), d = a + kInvPhi * (b - a);
    double fc = f(c), fd = f(d);
    for (int it = 0; it < kGoldenIterations && b - a > kGoldenWidth; it++)
    {
        if (fc >= fd)
        {
            b = d, d = c, fd = fc, c = b - kInvPhi * (b - a), fc = f(c);
        }
        else
        {
            a = c, c = d, fc = fd, d = a + kInvPhi * (b - a), fd = f(d);
        }
    }
    return fc >= fd ? c : d;
}

/** About how many times goldenMax() evaluates its function on [lo, hi] (the interval shrinks
 *  by kInvPhi at each step whichever way it goes). */
size_t goldenEvaluations(double lo, double hi)
{
    size_t n = 2;
    for (double w = hi - lo; n < static_cast<size_t>(kGoldenIterations) + 2 && w > kGoldenWidth;
         w *= kInvPhi)
    {
        n++;
    }
    return n;
}

/** The detection model q(x, b) = (qn + (qf - qn) x) (1 - (1 - e) b), x = range / max range
 *  and b = |bearing| / half the field of view, both in [0, 1], fitted by maximum likelihood
 *  to the in-view objects' detected (0/1, less the clutter expected in the object's gate):
 *  sum y log q + (1 - y) log(1 - q). It is concave in the line (qn, qf) for a given ratio e
 *  and in e for a given line; the two are maximized in turn (the line over [0, seen]^2, a
 *  share of the detections being misread out of the gates; e over [0, 1]) until the
 *  log-likelihood gains less than 1e-9. A detection far out keeps q above 0 there, which a
 *  least-squares line does not. Half-widths from the inverse of the observed information at
 *  the maximum. */
class DetectionModelFit
{
public:
    DetectionModelFit(const TCalibrationResult& r, double lambda)
        : m_n(r.samples.visibleRanges_m.size())
    {
        const auto& sm = r.samples;
        m_x.resize(m_n);
        m_y.resize(m_n);
        m_b.assign(m_n, 0.0);
        for (size_t i = 0; i < m_n; i++)
        {
            m_x[i] =
                r.maxRange_m > 0 ? std::clamp(sm.visibleRanges_m[i] / r.maxRange_m, 0.0, 1.0) : 0.0;
            // less the expected clutter
            m_y[i] = std::clamp(sm.visibleDetected[i] - lambda * sm.visibleSpurious[i], 0.0, 1.0);
            if (i < sm.visibleOffAxis.size())
            {
                m_b[i] = std::clamp(sm.visibleOffAxis[i], 0.0, 1.0);
                m_edge = m_edge || m_b[i] > 0;
            }
        }
    }
    /** False when every object was on the axis (a 360-degree view): e is not fitted. */
    bool hasEdge() const { return m_edge; }

    double logLik(double qn, double qf, double e) const
    {
        double l = 0;
        for (size_t i = 0; i < m_n; i++)
        {
            const double q = (qn + (qf - qn) * m_x[i]) * (1 - (1 - e) * m_b[i]);
            l += (m_y[i] > 0 ? m_y[i] * std::log(q) : 0.0) +
                 (m_y[i] < 1 ? (1 - m_y[i]) * std::log1p(-q) : 0.0);
        }
        return std::isnan(l) ? -std::numeric_limits<double>::infinity() : l;
    }

    /** The maximum over [0, seen]^2 x [0, 1] (e = 1 without an edge): qn, qf, e. `progress`
     *  is told each step of each round's search of the line. */
    std::array<double, 3> maximize(double seen, const FitProgress& progress) const
    {
        std::array<double, 3> q{0, 0, 1};
        double best = -std::numeric_limits<double>::infinity();
        const size_t steps = goldenEvaluations(0, seen);
        for (int round = 0; round < 50; round++)
        {
            const double e = q[2];
            const auto bestFar = [&](double qn)
            { return goldenMax([&](double qf) { return logLik(qn, qf, e); }, 0, seen); };
            size_t step = 0;
            q[0] = goldenMax(
                [&](double v)
                {
                    const double l = logLik(v, bestFar(v), e);
                    if (progress)
                    {
                        progress(round + 1, std::min(++step, steps), steps);
                    }
                    return l;
                },
                0, seen);
            q[1] = bestFar(q[0]);
            if (m_edge)
            {
                q[2] = goldenMax([&](double v) { return logLik(q[0], q[1], v); }, 0, 1);
            }
            snapToBounds(q, seen);
            const double l = logLik(q[0], q[1], q[2]);
            if (!m_edge || l - best < 1e-9)
            {
                break;
            }
            best = l;
        }
        return q;
    }

    /** Half-widths (95 %) of qn, qf and e from the observed information at q (0 where it is
     *  singular; e's row left out without an edge). */
    std::array<double, 3> halfWidths(const std::array<double, 3>& q) const
    {
        const int k = m_edge ? 3 : 2;
        Eigen::Matrix3d info = Eigen::Matrix3d::Zero();
        for (size_t i = 0; i < m_n; i++)
        {
            const double line = q[0] + (q[1] - q[0]) * m_x[i], taper = 1 - (1 - q[2]) * m_b[i];
            const double p = std::clamp(line * taper, 1e-9, 1 - 1e-9);
            const Eigen::Vector3d g((1 - m_x[i]) * taper, m_x[i] * taper, line * m_b[i]);
            info += (m_y[i] / (p * p) + (1 - m_y[i]) / ((1 - p) * (1 - p))) * g * g.transpose();
        }
        const Eigen::MatrixXd sub = info.topLeftCorner(k, k);
        std::array<double, 3> out{0, 0, 0};
        if (std::abs(sub.determinant()) > 1e-12)
        {
            const Eigen::MatrixXd cov = sub.inverse();
            for (int j = 0; j < k; j++)
            {
                out[static_cast<size_t>(j)] = kZ95 * std::sqrt(std::max(cov(j, j), 0.0));
            }
        }
        return out;
    }

private:
    /** A search that ends within 1e-7 of a bound it should sit on (no detection at all far
     *  out, none at the edge) is put on it. */
    void snapToBounds(std::array<double, 3>& q, double seen) const
    {
        for (size_t j = 0; j < 3; j++)
        {
            for (const double bound : {0.0, j < 2 ? seen : 1.0})
            {
                if (std::abs(q[j] - bound) < 1e-7)
                {
                    const double keep = q[j], before = logLik(q[0], q[1], q[2]);
                    q[j] = bound;
                    if (logLik(q[0], q[1], q[2]) < before)
                    {
                        q[j] = keep;
                    }
                }
            }
        }
    }

    size_t m_n;
    std::vector<double> m_x, m_y, m_b;
    bool m_edge = false;
};

void detectionModel(TCalibrationResult& r, double lambda, double seen, const FitProgress& progress)
{
    const DetectionModelFit f(r, lambda);
    const auto q = f.maximize(seen, progress);
    const auto hw = f.halfWidths(q);
    const size_t n = r.samples.visibleRanges_m.size();
    const std::string how = "maximum-likelihood detection model, (line against range / " +
                            text(r.maxRange_m) +
                            " m) x (1 - (1 - ratio) |bearing| / half the field of view), of "
                            "detected (0/1) over the in-view objects";
    const std::string misread =
        seen < 1 ? ", over the " + text(seen) + " of the detections not misread out of the gate"
                 : "";
    r.p_detect_near = fit(std::clamp(q[0] / seen, 0.0, 1.0), n, hw[0] / seen,
                          how + ", at 0 m on the axis" + misread);
    r.p_detect_far = fit(std::clamp(q[1] / seen, 0.0, 1.0), n, hw[1] / seen,
                         how + ", at max range on the axis" + misread);
    r.p_detect_edge_ratio =
        f.hasEdge()
            ? fit(q[2], n, hw[2], how + ", at the edge of the field of view over on its axis")
            : fit(1.0, n, 0.0, "a 360-degree field of view has no edge: 1");
}
}  // namespace

double madSigma(std::vector<double> x)
{
    const double m = median(x);
    for (double& v : x)
    {
        v = std::abs(v - m);
    }
    return 1.482602218505602 * median(std::move(x));
}

std::vector<double> nonNegativeLeastSquares(const std::vector<std::vector<double>>& cols,
                                            const std::vector<double>& y, std::vector<double>& ci95)
{
    const size_t k = cols.size(), n = y.size();
    std::vector<double> best(k, 0.0);
    ci95.assign(k, 0.0);
    double bestSse = std::numeric_limits<double>::infinity();
    for (unsigned mask = 1; mask < (1U << k); mask++)
    {
        std::vector<size_t> use;
        for (size_t c = 0; c < k; c++)
        {
            if ((mask >> c) & 1U)
            {
                use.push_back(c);
            }
        }
        Eigen::MatrixXd X(n, use.size());
        Eigen::VectorXd Y(n);
        for (size_t i = 0; i < n; i++)
        {
            Y(static_cast<Eigen::Index>(i)) = y[i];
            for (size_t c = 0; c < use.size(); c++)
            {
                X(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(c)) = cols[use[c]][i];
            }
        }
        const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(X);
        if (n <= use.size() || qr.rank() < static_cast<Eigen::Index>(use.size()))
        {
            continue;
        }
        const Eigen::VectorXd b = qr.solve(Y);
        if ((b.array() < 0).any())
        {
            continue;
        }
        const double sse = (X * b - Y).squaredNorm();
        if (sse < bestSse * (1 - 1e-12))
        {
            bestSse = sse;
            const Eigen::MatrixXd cov =
                (X.transpose() * X).inverse() * sse / static_cast<double>(n - use.size());
            std::fill(best.begin(), best.end(), 0.0);
            std::fill(ci95.begin(), ci95.end(), 0.0);
            for (size_t c = 0; c < use.size(); c++)
            {
                const auto e = static_cast<Eigen::Index>(c);
                best[use[c]] = b(e);
                ci95[use[c]] = kZ95 * std::sqrt(std::max(cov(e, e), 0.0));
            }
        }
    }
    return best;
}

namespace
{
/** The heading drift of the odometry from the kept increments `kept` of `sm`: the signed
 *  heading errors' sum over the seconds they span (the least-squares rate of errors
 *  e_k = b dt_k + noise), its 95 % half-width from the residuals; in deg/min. */
TCalibrationFit fitHeadingDrift(const TCalibrationSamples& sm, const std::vector<size_t>& kept)
{
    double sumE = 0, sumDt = 0, sumDt2 = 0;
    for (const size_t i : kept)
    {
        sumE += sm.odomErrPhiSigned_rad[i] * sm.odomDt_s[i];
        sumDt2 += sm.odomDt_s[i] * sm.odomDt_s[i];
        sumDt += sm.odomDt_s[i];
    }
    if (kept.size() < 4 || !(sumDt2 > 0))
    {
        return fit(0, kept.size(), 0, "too few timed odometry increments");
    }
    const double b = sumE / sumDt2;  // rad/s
    double ss = 0;
    for (const size_t i : kept)
    {
        const double res = sm.odomErrPhiSigned_rad[i] - b * sm.odomDt_s[i];
        ss += res * res;
    }
    const double se = std::sqrt(ss / static_cast<double>(kept.size() - 1) / sumDt2);
    constexpr double k = kRadPerSecondPerDegPerMinute;
    return fit(b / k, kept.size(), kZ95 * se / k,
               "least squares of the signed heading errors against the seconds of their "
               "increments (" +
                   text(sumDt) + " s)");
}
}  // namespace

/** The smallest k >= 1 such that `z2` / k^2 <= `bound` for a share of at least `share` of
 *  the weights: k = sqrt(max(1, weighted `share` quantile of z2 / bound)). */
double quantileFactor(const std::vector<double>& z2, const std::vector<double>& w, double bound,
                      double share)
{
    std::vector<size_t> order(z2.size());
    for (size_t i = 0; i < order.size(); i++)
    {
        order[i] = i;
    }
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return z2[a] < z2[b]; });
    double total = 0;
    for (const double v : w)
    {
        total += v;
    }
    double sum = 0;
    for (const size_t i : order)
    {
        sum += w[i];
        if (sum >= share * total)
        {
            return std::sqrt(std::max(1.0, z2[i] / bound));
        }
    }
    return 1;
}

/** r.spanFactorXY/Phi: the odometry over the spans between detections against the variance
 *  the per-step model with coefficients `cxy`, `cphi` (native units) adds up to there. Errors
 *  that do not cancel from step to step (a heading that wanders, a wheel that slips for
 *  seconds) grow faster than the per-step noise does: the factor is the smallest that puts
 *  the spans' normalized squared errors (2 degrees of freedom for the position, 1 for the
 *  heading less the drift) inside their 95 % chi-square bound for 95 % of the steps (each
 *  span weighted by its steps: what the filter lives through). */
void spanFactors(TCalibrationResult& r, const std::vector<double>& cxy,
                 const std::vector<double>& cphi, double driftRate)
{
    const auto& sm = r.samples;
    r.spanFactorXY = r.spanFactorPhi = 1;
    std::vector<double> zxy, zphi, w;
    for (size_t j = 0; j < sm.spanErrXY_m.size(); j++)
    {
        double vxy = 0, vphi = 0;
        for (size_t i = sm.spanBegin[j]; i < sm.spanEnd[j]; i++)
        {
            const double d = sm.odomDist_m[i], t = sm.odomTurn_rad[i];
            vxy += std::pow(cxy[0] + cxy[1] * d + cxy[2] * t, 2);
            vphi += std::pow(cphi[0] + cphi[1] * d + cphi[2] * t, 2);
        }
        if (!(vxy > 0) || !(vphi > 0))
        {
            return;  // a model without noise (a still vehicle): nothing to scale
        }
        const double ephi = sm.spanErrPhi_rad[j] - driftRate * sm.spanDt_s[j];
        zxy.push_back(sm.spanErrXY_m[j] * sm.spanErrXY_m[j] / vxy);
        zphi.push_back(ephi * ephi / vphi);
        w.push_back(static_cast<double>(sm.spanEnd[j] - sm.spanBegin[j]));
    }
    if (zxy.size() < TCalibrationResult::kMinMovingIncrements)
    {
        return;
    }
    constexpr double kChi2Dof2 = 5.991464547, kChi2Dof1 = 3.841458821, kShare = 0.95;
    r.spanFactorXY = quantileFactor(zxy, w, kChi2Dof2, kShare);
    r.spanFactorPhi = quantileFactor(zphi, w, kChi2Dof1, kShare);
}

void fitOdometry(TCalibrationResult& r)
{
    const auto& sm = r.samples;
    // An increment whose error is 10 medians away is not noise (a kidnapping, a jump in the
    // ground truth): it is left out.
    const double limXY = 10 * median(sm.odomErrXY_m), limPhi = 10 * median(sm.odomErrPhi_rad);
    std::vector<size_t> kept;
    for (size_t i = 0; i < sm.odomDist_m.size(); i++)
    {
        if (sm.odomErrXY_m[i] <= limXY && sm.odomErrPhi_rad[i] <= limPhi)
        {
            kept.push_back(i);
        }
    }
    // The heading drift: when it is real, the heading noise is what remains without it.
    r.heading_drift_deg_per_min = fitHeadingDrift(sm, kept);
    const auto& drift = r.heading_drift_deg_per_min;
    r.headingDrifts = std::abs(drift.value) > drift.ci95 &&
                      std::abs(drift.value) >= TCalibrationResult::kMinHeadingDriftDegPerMin;
    const double driftRate = r.headingDrifts ? drift.value * kRadPerSecondPerDegPerMinute : 0;
    std::vector<std::vector<double>> cols(3);
    std::vector<double> exy, ephi;
    for (const size_t i : kept)
    {
        cols[0].push_back(1.0);
        cols[1].push_back(sm.odomDist_m[i]);
        cols[2].push_back(sm.odomTurn_rad[i]);
        // E|e| = std sqrt(pi/2) (2D isotropic), std sqrt(2/pi) (1D).
        exy.push_back(sm.odomErrXY_m[i] / std::sqrt(M_PI / 2));
        const double ePhi = sm.odomErrPhiSigned_rad[i] - driftRate * sm.odomDt_s[i];
        ephi.push_back(std::abs(ePhi) / std::sqrt(2 / M_PI));
    }
    const size_t n = exy.size();
    std::vector<double> cxy(3, 0.0), cphi(3, 0.0), ixy(3, 0.0), iphi(3, 0.0);
    if (n >= 4)
    {
        cxy = nonNegativeLeastSquares(cols, exy, ixy);
        cphi = nonNegativeLeastSquares(cols, ephi, iphi);
    }
    std::string xy = "least squares (>= 0) of |xy error| / sqrt(pi/2) against [1, d, |dphi|]";
    std::string ph = std::string("least squares (>= 0) of |phi error") +
                     (r.headingDrifts ? " - drift dt" : "") +
                     "| / sqrt(2/pi) against [1, d, |dphi|]";
    spanFactors(r, cxy, cphi, driftRate);
    const auto scaled = [&](std::vector<double>& c, std::vector<double>& ci, double f)
    {
        for (size_t k = 0; k < c.size(); k++)
        {
            c[k] *= f;
            ci[k] *= f;
        }
    };
    scaled(cxy, ixy, r.spanFactorXY);
    scaled(cphi, iphi, r.spanFactorPhi);
    const auto spanText = [&](double f)
    {
        return f == 1 ? std::string()
                      : ", x" + text(f) + " to hold the errors over the " +
                            std::to_string(sm.spanErrXY_m.size()) +
                            " spans between detections within their 95 % bound for 95 % of "
                            "the steps";
    };
    xy += spanText(r.spanFactorXY);
    ph += spanText(r.spanFactorPhi);
    const double d2r = M_PI / 180;
    r.minStdXY = fit(cxy[0], n, ixy[0], xy);
    r.a1 = fit(cxy[1], n, ixy[1], xy);
    r.a2 = fit(cxy[2] * d2r, n, ixy[2] * d2r, xy);
    r.minStdPHI = fit(mrpt::RAD2DEG(cphi[0]), n, mrpt::RAD2DEG(iphi[0]), ph);
    r.a3 = fit(mrpt::RAD2DEG(cphi[1]), n, mrpt::RAD2DEG(iphi[1]), ph);
    r.a4 = fit(cphi[2], n, iphi[2], ph);
}

void fitDetector(TCalibrationResult& r, const FitProgress& progress)
{
    if (r.samples.rangeResiduals_m.empty())
    {
        throw std::runtime_error(
            "calibration: no detection matched an in-view object of its "
            "label (wrong world, ground truth or gate?)");
    }
    r.sigma_range_m = robustSigma(r.samples.rangeResiduals_m);
    r.sigma_bearing_deg = robustSigma(r.samples.bearingResiduals_deg);
    // Clutter within the gate of an object without a same-label match was taken for a
    // confusion, and within its misread strip for a misread range: their expected numbers
    // depend on the clutter rate (fixed point).
    double confPerRate = 0, misPerRate = 0;
    for (size_t i = 0; i < r.samples.visibleSpurious.size(); i++)
    {
        confPerRate += r.samples.visibleSpurious[i];
        misPerRate += r.samples.visibleMisreadSpurious[i];
    }
    const double scans = static_cast<double>(r.scans);
    double lambda = static_cast<double>(r.clutter) / scans, spurious = 0, spuriousMis = 0;
    for (int it = 0; it < 50; it++)
    {
        spurious = std::min(lambda * confPerRate, static_cast<double>(r.confused));
        spuriousMis = std::min(lambda * misPerRate, static_cast<double>(r.misread));
        lambda = (static_cast<double>(r.clutter) + spurious + spuriousMis) / scans;
    }
    const double clutter = static_cast<double>(r.clutter) + spurious + spuriousMis;
    r.clutter_per_scan =
        fit(lambda, r.scans, kZ95 * std::sqrt(std::max(clutter, 1.0)) / scans,
            std::to_string(r.clutter) + " detections matching no in-view object + " +
                text(spurious + spuriousMis) + " expected in the confusion and misread gates, " +
                "per scan");
    const double confused = static_cast<double>(r.confused) - spurious;
    const double n = static_cast<double>(r.matched) + confused;
    const double p = n > 0 ? confused / n : 0.0;
    r.p_confusion = fit(p, r.matched + r.confused, kZ95 * std::sqrt(p * (1 - p) / std::max(n, 1.0)),
                        std::to_string(r.confused) + " matched detections of another label, less " +
                            text(spurious) + " expected clutter");
    // A misread inside the gate was matched there: the ones seen are the share outside it.
    const double misread = static_cast<double>(r.misread) - spuriousMis;
    const double own = static_cast<double>(r.matched) + misread;
    const double outside = 1 - r.misreadInGate;
    const bool fitted = own > 0 && outside > 0;
    const double eps = fitted ? std::clamp(misread / (own * outside), 0.0, 0.99) : 0.0;
    r.p_range_outlier =
        fit(eps, r.matched + r.misread,
            fitted ? kZ95 * std::sqrt(eps * (1 - eps) / std::max(own, 1.0)) / outside : 0.0,
            std::to_string(r.misread) + " detections at an object's bearing outside its range " +
                "gate, less " + text(spuriousMis) + " expected clutter, over the " +
                text(100 * outside) + " % of the range outside the gate");
    // The detection model counted the detections the gates matched: all but the misreads
    // outside them.
    detectionModel(r, lambda, 1 - eps * outside, progress);
}
}  // namespace semloc::detail
