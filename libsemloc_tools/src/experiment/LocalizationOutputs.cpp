/* semloc — a localization run's steps.csv and summary.yaml. */
#include "experiment/LocalizationOutputs.h"

#include <mrpt/core/format.h>

#include <mrpt/core/exceptions.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

#include "io/Text.h"

namespace semloc::detail
{
namespace
{
/** Shortest round-trip text of a number; "" for NaN (steps.csv's empty cells). */
std::string num(double v)
{
    return std::isnan(v) ? std::string() : detail::shortestText(v);
}

/** A YAML value: `null` for NaN. */
std::string yamlNum(double v)
{
    return std::isnan(v) ? "null" : num(v);
}

std::string yamlString(const std::string& s)
{
    std::string q = "\"";
    for (const char ch : s)
    {
        if (ch == '"' || ch == '\\')
        {
            q += '\\';
        }
        q += ch;
    }
    return q + "\"";
}
}  // namespace

namespace
{
const char* const kStepsHeader =
    "step,t,gt_x,gt_y,gt_phi,est_x,est_y,est_phi,err_xy,err_phi,var_xy,ess,n_particles,"
    "update_us,nees,var_x,var_y,var_phi,cov_xy,cov_xphi,cov_yphi\n";

void stepsRow(std::ostream& o, const TStepRecord& r)
{
    o << r.step << ',' << (std::isnan(r.t) ? "" : mrpt::format("%.6f", r.t)) << ','
      << (r.gt ? num(r.gt->x) : "") << ',' << (r.gt ? num(r.gt->y) : "") << ','
      << (r.gt ? num(r.gt->phi) : "") << ',' << num(r.est.x) << ',' << num(r.est.y) << ','
      << num(r.est.phi) << ',' << num(r.errXY()) << ',' << num(r.errPhi()) << ',' << num(r.var_xy)
      << ',' << num(r.ess) << ',' << r.n_particles << ',' << mrpt::format("%.1f", r.update_us)
      << ',' << num(r.nees()) << ',' << num(r.var_x) << ',' << num(r.var_y) << ',' << num(r.var_phi)
      << ',' << num(r.cov_xy) << ',' << num(r.cov_xphi) << ',' << num(r.cov_yphi) << '\n';
}
}  // namespace

std::string stepsCsv(const std::vector<TStepRecord>& records)
{
    std::ostringstream o;
    o << kStepsHeader;
    for (const auto& r : records)
    {
        stepsRow(o, r);
    }
    return o.str();
}

StepsCsv::StepsCsv(const std::string& path) : m_path(path), m_out(path, std::ios::binary)
{
    m_out << kStepsHeader;
    if (!m_out)
    {
        THROW_EXCEPTION("cannot write '" + m_path + "': " + std::strerror(errno));
    }
}

void StepsCsv::add(const TStepRecord& r)
{
    stepsRow(m_out, r);
}

void StepsCsv::finish()
{
    m_out.close();
    if (!m_out)
    {
        THROW_EXCEPTION("cannot write '" + m_path + "' (disk full?)");
    }
}

namespace
{
static_assert(TStepRecord::kNeesMaxCondition == 1e9 && TStepRecord::kNeesMinEigenvalue == 1e-9,
              "summary.yaml's comment says 1e9 and 1e-9");

/** summary.yaml's consistency (NEES) and "lost again" keys, with their comments. */
std::string neesAndLostYaml(const RunMetrics& m, const RunMetrics::TConvergenceCriterion& c)
{
    const auto count = [&](size_t n) { return m.converged ? std::to_string(n) : "null"; };
    std::ostringstream y;
    y << "# NEES: e' P^-1 e, e the pose error (x, y, phi) to the ground truth, P the particles'\n"
      << "# covariance, over the steps with ground truth: its median (~"
      << mrpt::format("%.2f", RunMetrics::kNeesChi2Median) << " consistent), the share\n"
      << "# of them with NEES <= " << mrpt::format("%.4f", RunMetrics::kNeesChi2_95)
      << " (the chi-square 95 % quantile, 3 dof; a one-sided bound:\n"
      << "# ~0.95 consistent, less overconfident), and its mean over the steps whose P is well\n"
      << "# conditioned (>= " << mrpt::format("%.0f", TStepRecord::kNeesMinEffectiveParticles)
      << " effective particles, condition number <= 1e9, eigenvalues >= 1e-9;\n"
      << "# ~3 consistent) with the share of such steps\n"
      << "nees_median: " << yamlNum(m.nees_median) << "\n"
      << "nees_inside_share: " << yamlNum(m.nees_inside_share) << "\n"
      << "nees_mean_well_conditioned: " << yamlNum(m.nees_mean_well_conditioned) << "\n"
      << "nees_well_conditioned_share: " << yamlNum(m.nees_well_conditioned_share) << "\n"
      << "# lost again: from the convergence step on, steps with ground truth and err_xy > "
      << num(c.max_err_xy_m) << " m;\n"
      << "# an episode lasts to the next step not lost (or the last step); null: not converged\n"
      << "lost_after_convergence_steps: " << count(m.lost_after_convergence_steps) << "\n"
      << "lost_after_convergence_s: " << yamlNum(m.lost_after_convergence_s) << "\n"
      << "lost_episodes: " << count(m.lost_episodes) << "\n"
      << "first_lost_after_convergence_s: " << yamlNum(m.first_lost_after_convergence_s) << "\n"
      << "longest_lost_s: " << yamlNum(m.longest_lost_s) << "\n";
    return y.str();
}

/** summary.yaml's keys of the detector's bound (docs/design.md, "The detector's bound"). */
std::string detectorBoundYaml(const LocalizationExperiment::TResult& res)
{
    const double ratio = res.metrics.mean_err_after_conv_m / res.detector_bound_after_conv_m;
    return "# the detector's Cramer-Rao bound [m]: the mean position error no filter of these\n"
           "# detections can beat on average (one run may) under the configured detector\n"
           "# model, linearized at the true path; from the convergence step on, and over every\n"
           "# step with ground truth (null: no ground truth, no semantic map, not converged)\n"
           "detector_bound_after_conv_m: " +
           yamlNum(res.detector_bound_after_conv_m) + "\n" +
           "detector_bound_mean_m: " + yamlNum(res.detector_bound_mean_m) + "\n" +
           "# mean_err_after_conv_m / detector_bound_after_conv_m\n"
           "error_over_bound_after_conv: " +
           yamlNum(std::isfinite(ratio) ? ratio : std::nan("")) + "\n";
}
}  // namespace

std::string summaryYaml(const LocalizationExperiment::TResult& res,
                        const LocalizationExperiment::TOptions& o)
{
    const auto& m = res.metrics;
    const auto& c = o.convergence;
    std::ostringstream y;
    y << "# semloc-localize run summary (docs/design.md); null: not available\n"
      << "variant: " << yamlString(res.variant) << "\n"
      << "particles: " << o.filter.particles_count << "\n"
      << "seed: " << o.filter.seed << "\n"
      << "threads: " << res.threads << "\n"
      << "steps: " << m.steps << "\n"
      << "steps_with_ground_truth: " << m.steps_with_ground_truth << "\n"
      << "converged: " << (m.converged ? "true" : "false") << "\n"
      << "convergence_step: " << (m.converged ? std::to_string(m.convergence_step) : "null") << "\n"
      << "convergence_time_s: " << yamlNum(m.convergence_time_s) << "\n"
      << "mean_err_after_conv_m: " << yamlNum(m.mean_err_after_conv_m) << "\n"
      << "rmse_m: " << yamlNum(m.rmse_m) << "\n"
      << "final_err_m: " << yamlNum(m.final_err_m) << "\n"
      << "total_update_s: " << yamlNum(m.total_update_s) << "\n"
      << "mean_update_us_per_particle: " << yamlNum(m.mean_update_us_per_particle) << "\n"
      << "final_particles: " << res.final_particles << "\n"
      << "convergence_criterion: {max_err_xy_m: " << num(c.max_err_xy_m)
      << ", max_var_xy_m2: " << num(c.max_var_xy_m2) << ", min_steps: " << c.min_steps << "}\n"
      << neesAndLostYaml(m, c) << detectorBoundYaml(res)
      << "# observations and detections the maps could not use, non-finite likelihoods\n"
      << "observations_used: " << res.likelihood.observations_used << "\n"
      << "observations_skipped: " << res.likelihood.observations_skipped << "\n"
      << "detections_invalid: " << res.likelihood.detections_invalid << "\n"
      << "detections_unknown: " << res.likelihood.detections_unknown << "\n"
      << "nonfinite_likelihoods: " << res.likelihood.nonfinite_likelihoods << "\n"
      << "associations_approximated: " << res.likelihood.associations_approximated << "\n"
      << "# init_PDF_mode = 3: particles drawn from the first detections\n"
      << "initialized_from_detections: " << res.initialized_from_detections << "\n"
      << "# [MotionModel] heading_drift_*: the particles' mean heading drift rate at the end\n"
      << "# [deg/min] (what the odometry's heading gains beyond the truth; 0: no drift state)\n"
      << "heading_drift_deg_per_min: " << yamlNum(res.heading_drift_deg_per_min) << "\n"
      << "# every weight zero: particles re-initialized over the free space\n"
      << "reinitializations: " << res.recovery.reinitializations << "\n"
      << "reinitialized_from_detections: " << res.recovery.reinitialized_from_detections << "\n"
      << "# injected particles ([Recovery] trigger)\n"
      << "injection_steps: " << res.recovery.injection_steps << "\n"
      << "injected_particles: " << res.recovery.injected_particles << "\n"
      << "injected_from_detections: " << res.recovery.injected_from_detections << "\n"
      << "# challenger sets ([Recovery] challenger_frames) that joined the cloud\n"
      << "challenger_merges: " << res.recovery.challenger_merges << "\n"
      << "# of injection_steps, the sensor resetting while lost ([Recovery] lost_var_xy_m2)\n"
      << "lost_injection_steps: " << res.recovery.lost_injection_steps << "\n"
      << "# free_space_prior: particle updates found outside the free space (weight 0)\n"
      << "outside_free_space: " << res.recovery.outside_free_space << "\n"
      << "# range-scan beams with a NaN, infinite, negative or beyond-max range (skipped)\n"
      << "beams_invalid: " << res.likelihood.beams_invalid << "\n"
      << "# observations that cannot be scored (a non-finite sensor pose, aperture or range\n"
      << "# limit, a scan without beams...), left out whole\n"
      << "observations_invalid: " << res.likelihood.observations_invalid << "\n"
      << "rawlog_format: " << yamlString(res.rawlogFormat) << "\n"
      << "# --allow-truncated: index of the first unreadable entry (null: rawlog complete)\n"
      << "rawlog_truncated_at_entry: "
      << (res.rawlogTruncatedAtEntry ? std::to_string(*res.rawlogTruncatedAtEntry) : "null") << "\n"
      << "rawlog_file: " << yamlString(o.rawlog_file) << "\n"
      << "map_file: " << yamlString(o.map_file) << "\n"
      << "ground_truth_path_file: " << yamlString(o.ground_truth_path_file) << "\n"
      << "wall_time_s: " << yamlNum(res.wallTime_s) << "\n";
    return y.str();
}

ParticlesCsv::ParticlesCsv(const std::string& path, size_t every)
    : m_path(path), m_out(path, std::ios::binary), m_every(std::max<size_t>(every, 1))
{
    m_out << "step,t,x,y,phi,weight\n";
    if (!m_out)
    {
        THROW_EXCEPTION("cannot write '" + m_path + "': " + std::strerror(errno));
    }
}

void ParticlesCsv::step(const TStepRecord& r, const CParallelMonteCarloLocalization2D& pdf)
{
    if (r.step % m_every == 0)
    {
        write(r, pdf);
    }
}

void ParticlesCsv::finish(const TStepRecord& last, const CParallelMonteCarloLocalization2D& pdf)
{
    if (m_lastWritten != last.step)
    {
        write(last, pdf);
    }
    m_out.close();
    if (!m_out)
    {
        THROW_EXCEPTION("cannot write '" + m_path + "' (disk full?)");
    }
}

void ParticlesCsv::write(const TStepRecord& r, const CParallelMonteCarloLocalization2D& pdf)
{
    const auto& ps = pdf.m_particles;
    double maxLogW = -std::numeric_limits<double>::infinity();
    for (const auto& p : ps)
    {
        maxLogW = std::max(maxLogW, p.log_w);
    }
    double sum = 0;
    for (const auto& p : ps)
    {
        sum += std::exp(p.log_w - maxLogW);
    }
    const std::string prefix = std::to_string(r.step) + "," + num(r.t) + ",";
    std::string rows;
    for (const auto& p : ps)
    {
        rows += prefix;
        rows += num(p.d.x) + "," + num(p.d.y) + "," + num(p.d.phi) + ",";
        rows += num(std::exp(p.log_w - maxLogW) / sum) + "\n";
    }
    m_out << rows;
    m_lastWritten = r.step;
}

}  // namespace semloc::detail
