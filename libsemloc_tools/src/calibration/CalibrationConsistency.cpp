/* semloc — semloc-calibrate's consistency stage: the filter run on the calibration run itself,
 * its noise widened until its pose error is consistent with its spread. */
#include <semloc/calibration/SensorCalibration.h>
#include <semloc/experiment/LocalizationExperiment.h>
#include <semloc/filter/MotionModelConfig.h>
#include <semloc/models/semantic/CSemanticMap.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "io/TemporaryDirectory.h"

namespace semloc
{
namespace
{
namespace fs = std::filesystem;

std::string number(double v)
{
    std::ostringstream s;
    s << std::setprecision(3) << v;
    return s.str();
}

/** `f` multiplied by `k`, kept to `range` (a fit the data could not make, or 0, is left
 *  alone). */
void widen(TCalibrationFit& f, double k, const config::TValueRange& range)
{
    if (f.status == TCalibrationFit::Status::TooLittleData || k == 1 || !(f.value > 0))
    {
        return;
    }
    const double v = std::clamp(f.value * k, range.lo, range.hi);
    f.widenedBy *= v / f.value;  // the factor applied, range kept
    f.value = v;
}

/** The filter run once per seed with the ini `ini`, its metrics averaged into a trial;
 *  `progress` told of each run's entries under `stage`. */
TConsistencyTrial runTrial(const std::string& ini, const detail::TemporaryDirectory& dir,
                           const std::string& rawlogPath, const std::string& groundTruthPath,
                           const SensorCalibration::TConsistencyOptions& o,
                           const std::string& stage, const CalibrationProgress& progress)
{
    TConsistencyTrial t;
    for (const uint32_t seed : o.seeds)
    {
        LocalizationExperiment::TOverrides ov;
        ov.rawlog_file = rawlogPath;
        ov.ground_truth_path_file = groundTruthPath;
        ov.logOutput_dir = dir.path("run");
        ov.seed = seed;
        ov.threads = o.threads;
        const std::string run =
            stage + ", run " + std::to_string(t.runs + 1) + " of " + std::to_string(o.seeds.size());
        const auto told = [&](size_t done, size_t total) {
            progress({run, done, total, "entries"});
        };
        const auto m = LocalizationExperiment::FromConfigFile(ini, ov)
                           .run(progress ? std::function<void(size_t, size_t)>(told) : nullptr,
                                LocalizationExperiment::Records::Stream)
                           .metrics;
        t.runs++;
        t.converged += m.converged ? 1 : 0;
        t.steps += m.steps_with_ground_truth;
        t.insideShare += m.nees_inside_share;
        t.neesMean += m.nees_mean;
        t.meanErr_m += m.converged ? m.mean_err_after_conv_m : m.rmse_m;
    }
    const double n = static_cast<double>(std::max<size_t>(t.runs, 1));
    t.insideShare /= n;
    t.neesMean /= n;
    t.meanErr_m /= n;
    return t;
}

/** Whether the trials from `row` on hold one whose runs all converged within `tolerance` of
 *  the lowest error of such trials (true while no trial's runs all converged: more noise may
 *  be what they need). */
bool competitive(const std::vector<TConsistencyTrial>& trials, size_t row, double tolerance)
{
    double lowest = std::numeric_limits<double>::infinity();
    for (const auto& t : trials)
    {
        if (t.converged == t.runs)
        {
            lowest = std::min(lowest, t.meanErr_m);
        }
    }
    if (std::isinf(lowest))
    {
        return true;
    }
    for (size_t i = row; i < trials.size(); i++)
    {
        if (trials[i].converged == trials[i].runs &&
            trials[i].meanErr_m <= (1 + tolerance) * lowest)
        {
            return true;
        }
    }
    return false;
}

/** The trial written: the consistent one of the lowest error; else, of those whose runs all
 *  converged within `tolerance` of the lowest error, the one with the most steps inside the
 *  bound; else (no setting converged in every run) the one of the lowest error. */
size_t choose(const std::vector<TConsistencyTrial>& trials, double minShare, double tolerance)
{
    const auto lowestError = [&](const auto& admit)
    {
        std::optional<size_t> best;
        for (size_t i = 0; i < trials.size(); i++)
        {
            if (admit(trials[i]) && (!best || trials[i].meanErr_m < trials[*best].meanErr_m))
            {
                best = i;
            }
        }
        return best;
    };
    if (const auto c =
            lowestError([&](const auto& t) { return SensorCalibration::Consistent(t, minShare); }))
    {
        return *c;
    }
    const auto converged = lowestError([](const auto& t) { return t.converged == t.runs; });
    if (!converged)
    {
        return *lowestError([](const auto&) { return true; });
    }
    const double limit = (1 + tolerance) * trials[*converged].meanErr_m;
    size_t best = *converged;
    for (size_t i = 0; i < trials.size(); i++)
    {
        const auto& t = trials[i];
        if (t.converged == t.runs && t.meanErr_m <= limit &&
            t.insideShare > trials[best].insideShare)
        {
            best = i;
        }
    }
    return best;
}

/** Runs one setting (sensor factor, motion factor, tempering); true when it is consistent. */
using Trial = std::function<bool(double, double, double)>;

/** The search over the motion and sensor factors at tempering `tp`: for each motion factor the
 *  sensor factors up to the first consistent one, the next motion factor only while the last
 *  stayed competitive. True when a setting was consistent. */
bool search(const Trial& run, const std::vector<TConsistencyTrial>& trials, double tp,
            bool motionFitted, const SensorCalibration::TConsistencyOptions& o)
{
    bool consistent = false;
    for (const double su : o.motionScales)
    {
        if (!motionFitted && su != o.motionScales.front())
        {
            break;  // the base's motion model is kept: nothing to widen
        }
        const size_t row = trials.size();
        for (const double sz : o.sensorScales)
        {
            if (run(sz, su, tp))
            {
                consistent = true;
                break;  // wider sensor noise only spreads the cloud further
            }
        }
        if (!competitive(trials, row, o.errorTolerance))
        {
            break;  // more motion noise has only made the error worse
        }
    }
    return consistent;
}
}  // namespace

bool SensorCalibration::Consistent(const TConsistencyTrial& t, double minShare)
{
    const double n = static_cast<double>(std::max<size_t>(t.steps, 1));
    const double tolerance = 2 * std::sqrt(minShare * (1 - minShare) / n);
    return t.runs > 0 && t.converged == t.runs && t.steps > 0 &&
           t.insideShare >= minShare - tolerance;
}

TCalibrationResult SensorCalibration::Widened(const TCalibrationResult& r, double sensorScale,
                                              double motionScale, double temper)
{
    using L = CSemanticMap::TLikelihoodOptions;
    using M = MotionModelConfig::TOptions;
    TCalibrationResult w = r;
    w.temper = temper;
    widen(w.sigma_range_m, sensorScale, L::range("sigma_range_m"));
    widen(w.sigma_bearing_deg, sensorScale, L::range("sigma_bearing_deg"));
    for (const auto& [key, fit] :
         {std::pair{"a1", &w.a1}, std::pair{"a2", &w.a2}, std::pair{"a3", &w.a3},
          std::pair{"a4", &w.a4}, std::pair{"minStdXY", &w.minStdXY},
          std::pair{"minStdPHI", &w.minStdPHI}})
    {
        widen(*fit, motionScale, M::range(key));
    }
    return w;
}

TCalibrationResult SensorCalibration::Consistency(
    TCalibrationResult r, const std::string& baseIni, const std::string& baseName,
    const std::string& worldPath, const std::string& rawlogPath, const std::string& groundTruthPath,
    const TConsistencyOptions& o, const std::function<void(const TConsistencyTrial&)>& trial,
    const CalibrationProgress& progress)
{
    if (o.seeds.empty() || o.sensorScales.empty() || o.motionScales.empty() || o.tempers.empty())
    {
        throw std::invalid_argument("the consistency stage needs seeds and factors to try");
    }
    const auto fitted = [](const TCalibrationFit& f)
    { return f.status != TCalibrationFit::Status::TooLittleData && f.value > 0; };
    if (!fitted(r.sigma_range_m) && !fitted(r.sigma_bearing_deg) && !fitted(r.minStdXY) &&
        !fitted(r.minStdPHI))
    {
        return r;  // nothing fitted to widen: the stage does not run
    }
    const detail::TemporaryDirectory dir(fs::temp_directory_path(), "semloc-calibrate-");
    const std::string iniPath = dir.path("trial.ini");
    // The settings are copies of the fits: without their samples (as large as the log is
    // long), given back at the end.
    TCalibrationSamples samples = std::move(r.samples);
    r.samples = TCalibrationSamples();
    TConsistency c;
    c.minInsideShare = o.minInsideShare;
    const Trial run = [&](double sz, double su, double tp)
    {
        {
            std::ofstream f(iniPath, std::ios::binary);
            f << ApplyToIni(baseIni, baseName, Widened(r, sz, su, tp), worldPath);
            if (!f.flush())
            {
                throw std::runtime_error("cannot write '" + iniPath + "'");
            }
        }
        auto t = runTrial(iniPath, dir, rawlogPath, groundTruthPath, o,
                          "consistency: setting " + std::to_string(c.trials.size() + 1) +
                              " (detector sigmas x" + number(sz) + ", motion noise x" + number(su) +
                              ", likelihood tempered x" + number(tp) + ")",
                          progress);
        t.sensorScale = sz;
        t.motionScale = su;
        t.temper = tp;
        c.trials.push_back(t);
        if (trial)
        {
            trial(t);
        }
        return Consistent(t, o.minInsideShare);
    };
    const bool motionFitted = r.a1.status != TCalibrationFit::Status::TooLittleData;
    for (const double tp : o.tempers)
    {
        if (search(run, c.trials, tp, motionFitted, o))
        {
            break;  // a consistent setting: a weaker likelihood only spreads the cloud further
        }
    }
    c.chosen = choose(c.trials, o.minInsideShare, o.errorTolerance);
    c.consistent = Consistent(c.trials[c.chosen], o.minInsideShare);
    const auto& best = c.trials[c.chosen];
    TCalibrationResult out = Widened(r, best.sensorScale, best.motionScale, best.temper);
    out.consistency = std::move(c);
    out.samples = std::move(samples);
    return out;
}

std::string SensorCalibration::ConsistencyText(const TCalibrationResult& r)
{
    const auto& c = r.consistency;
    if (c.trials.empty())
    {
        return "";
    }
    const auto describe = [](const TConsistencyTrial& t)
    {
        return "NEES inside its 95 % bound in " + number(100 * t.insideShare) +
               " % of the steps (mean NEES " + number(t.neesMean) + "), mean error " +
               number(t.meanErr_m) + " m, " + std::to_string(t.converged) + " of " +
               std::to_string(t.runs) + " runs converged";
    };
    const auto& before = c.trials.front();
    const auto& after = c.trials[c.chosen];
    const std::string tempered =
        after.temper != 1 ? ", likelihood tempered x" + number(after.temper) : "";
    return "consistency: as fitted, " + describe(before) + "; written (detector sigmas x" +
           number(after.sensorScale) + ", motion noise x" + number(after.motionScale) + tempered +
           "), " + describe(after) +
           (c.consistent ? ""
                         : " (no setting tried reached " + number(100 * c.minInsideShare) +
                               " %: the one with the most steps inside written)") +
           "\n";
}

}  // namespace semloc
