/* semloc — semloc-calibrate's fit of the detector's range bias by bearing: robust least
 * squares of the range residuals against a cubic in the bearing over half the view. */
#include <semloc/models/semantic/DetectionProbability.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <vector>

#include "calibration/CalibrationFits.h"

namespace semloc::detail
{
std::vector<double> fitRangeBias(const TCalibrationSamples& s, std::vector<double>& ci95)
{
    ci95.clear();
    const std::vector<double>& y = s.rangeResiduals_m;
    const std::vector<double>& u = s.rangeResidualBearing;
    const size_t n = std::min(y.size(), u.size());
    if (n < kMinRangeBiasResiduals)
    {
        return {};
    }
    constexpr auto kTerms = static_cast<Eigen::Index>(kRangeBiasTerms);
    Eigen::VectorXd c = Eigen::VectorXd::Zero(kTerms);
    // Residuals over 4 robust sigmas of the fit so far are left out (clutter the gate let
    // in, misreads), three times.
    std::vector<bool> kept(n, true);
    double sse = 0, sse0 = 0;
    size_t m = 0;
    Eigen::MatrixXd normal;
    for (int round = 0; round < 3; round++)
    {
        std::vector<double> res(n);
        for (size_t i = 0; i < n; i++)
        {
            res[i] = y[i] - (c[0] + u[i] * (c[1] + u[i] * (c[2] + u[i] * c[3])));
        }
        const double sigma = madSigma(res);
        m = 0;
        for (size_t i = 0; i < n; i++)
        {
            kept[i] = std::abs(res[i]) <= 4 * sigma;
            m += kept[i] ? 1 : 0;
        }
        if (m < kMinRangeBiasResiduals)
        {
            return {};
        }
        Eigen::MatrixXd a(static_cast<Eigen::Index>(m), kTerms);
        Eigen::VectorXd b(static_cast<Eigen::Index>(m));
        const auto fill = [&]
        {
            Eigen::Index row = 0;
            for (size_t i = 0; i < n; i++)
            {
                if (kept[i])
                {
                    a.row(row) << 1, u[i], u[i] * u[i], u[i] * u[i] * u[i];
                    b[row++] = y[i];
                }
            }
        };
        fill();
        {
            // Decomposed in a's own storage (a long log's matrix is not copied), then a is
            // filled again for the residuals.
            const Eigen::ColPivHouseholderQR<Eigen::Ref<Eigen::MatrixXd>> qr(a);
            if (qr.rank() < kTerms)
            {
                return {};  // the bearings do not vary enough for a cubic
            }
            c = qr.solve(b);
        }
        fill();
        sse = (a * c - b).squaredNorm();
        sse0 = b.squaredNorm();
        normal = a.transpose() * a;
    }
    const auto dm = static_cast<double>(m);
    if (!(sse > 0) || dm * std::log(sse0 / sse) <= TCalibrationResult::kRangeBiasChi2)
    {
        return {};
    }
    const Eigen::MatrixXd cov = normal.inverse() * (sse / (dm - static_cast<double>(kTerms)));
    std::vector<double> out(kRangeBiasTerms);
    ci95.resize(kRangeBiasTerms);
    for (Eigen::Index k = 0; k < kTerms; k++)
    {
        out[static_cast<size_t>(k)] = c[k];
        ci95[static_cast<size_t>(k)] = 1.96 * std::sqrt(cov(k, k));
    }
    return out;
}

void addRangeBias(const TCalibrationSamples& s, std::vector<double>& bias,
                  std::vector<double>& ci95)
{
    std::vector<double> moreCi95;
    const auto more = fitRangeBias(s, moreCi95);
    if (more.empty())
    {
        return;
    }
    bias.resize(kRangeBiasTerms, 0.0);
    for (size_t k = 0; k < kRangeBiasTerms; k++)
    {
        bias[k] += more[k];
    }
    ci95 = moreCi95;
}

const CObservationSemantic& lessRangeBias(const CObservationSemantic& obs,
                                          const std::vector<double>& bias,
                                          CObservationSemantic& copy)
{
    if (bias.empty())
    {
        return obs;
    }
    copy = obs;
    for (auto& d : copy.detections)
    {
        d.range_m = rangeLessBias(bias, d.range_m, d.bearing_rad, obs.maxRange_m, obs.fov_rad);
    }
    return copy;
}
}  // namespace semloc::detail
