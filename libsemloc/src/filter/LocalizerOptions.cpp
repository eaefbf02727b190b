/* semloc — Localizer's options: pf-localization's sections ([LocalizationExperiment]'s
 * filter keys, [PF_options], [KLD_options], [DummyOdometryParams]), [Recovery] and
 * [MotionModel] read strictly and written back. */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <semloc/filter/Localizer.h>
#include <semloc/io/ConfigHelpers.h>

#include <algorithm>
#include <limits>
#include <map>
#include <thread>

#include "io/ExactConfigWrite.h"
#include "io/Text.h"

namespace semloc
{
using mrpt::bayes::CParticleFilter;

namespace
{
using namespace semloc::config;

const char* const kPF = "PF_options";
const char* const kKLD = "KLD_options";
const char* const kOdo = "DummyOdometryParams";
const char* const kRec = "Recovery";

/** The [Recovery] keys; each was [PF_options] recovery_<key> before. */
const std::vector<std::string> kRecoveryKeys = {
    "trigger",      "alpha_slow",      "alpha_fast",      "evidence_margin",   "evidence_threshold",
    "inject_share", "from_detections", "injected_weight", "challenger_frames", "lost_var_xy_m2"};

/** Where a [Recovery] key is read: its section and name there. */
struct KeyPlace
{
    std::string section, key;
};

/** The place of each [Recovery] key: [Recovery] unless only its deprecated name in
 *  [PF_options] is set (a warning in `warnings`); both set is an error. */
std::map<std::string, KeyPlace> recoveryKeyPlaces(const mrpt::config::CConfigFileBase& c,
                                                  std::vector<std::string>& warnings)
{
    std::map<std::string, KeyPlace> places;
    for (const std::string& k : kRecoveryKeys)
    {
        const std::string old = "recovery_" + k;
        places[k] = KeyPlace{kRec, k};
        if (!c.keyExists(kPF, old))
        {
            continue;
        }
        if (c.keyExists(kRec, k))
        {
            THROW_EXCEPTION(
                mrpt::format("ini [%s] %s and [%s] %s: the same setting twice; keep "
                             "[%s] %s (the old name is deprecated)",
                             kPF, old.c_str(), kRec, k.c_str(), kRec, k.c_str()));
        }
        places[k] = KeyPlace{kPF, old};
        warnings.push_back(
            mrpt::format("ini [%s] %s is deprecated: write [%s] %s instead (read "
                         "as that)",
                         kPF, old.c_str(), kRec, k.c_str()));
    }
    return places;
}

const std::vector<std::string> kAlgorithms = {"pfStandardProposal", "pfAuxiliaryPFStandard",
                                              "pfOptimalProposal", "pfAuxiliaryPFOptimal"};
const std::vector<std::string> kResampling = {"prMultinomial", "prResidual", "prStratified",
                                              "prSystematic"};

/** An MRPT enum written as its number or its name (read_enum accepts both). */
int readEnum(const mrpt::config::CConfigFileBase& c, const std::string& s, const std::string& key,
             int value, const std::vector<std::string>& names)
{
    if (!c.keyExists(s, key))
    {
        return value;
    }
    const std::string text = detail::trimValue(c.read_string(s, key, ""));
    for (size_t i = 0; i < names.size(); i++)
    {
        if (text == names[i] || text == std::to_string(i))
        {
            return static_cast<int>(i);
        }
    }
    std::string list;
    for (size_t i = 0; i < names.size(); i++)
    {
        list.append(i ? ", " : "")
            .append(std::to_string(i))
            .append(" (")
            .append(names[i])
            .append(")");
    }
    THROW_EXCEPTION("ini [" + s + "] " + key + ": '" + text + "' is not one of " + list);
}

void put(mrpt::config::CConfigFileBase& c, const std::string& s, const std::string& key,
         const std::string& value, const std::string& comment)
{
    detail::writeText(c, s, key, value, comment);
}
void put(mrpt::config::CConfigFileBase& c, const std::string& s, const std::string& key, double v,
         const std::string& comment)
{
    detail::writeExact(c, s, key, v, comment);
}

std::string recoveryTriggerName(RecoveryTrigger t)
{
    return t == RecoveryTrigger::Off ? "off" : t == RecoveryTrigger::Evidence ? "evidence" : "amcl";
}

[[noreturn]] void bad(const std::string& s, const std::string& key, const std::string& what)
{
    THROW_EXCEPTION("ini [" + s + "] " + key + ": " + what);
}

/** [LocalizationExperiment]'s filter keys: the particles, the initial cloud, the seed. */
void loadInitialCloud(const mrpt::config::CConfigFileBase& c, const std::string& s,
                      Localizer::TOptions& o)
{
    // [LocalizationExperiment] (its other keys belong to LocalizationExperiment).
    if (std::string v = c.read_string(s, "particles_count", "");
        v.find_first_of(" \t,", v.find_first_not_of(" \t")) < v.find_last_not_of(" \t\r"))
    {
        bad(s, "particles_count",
            "'" + v +
                "': one number of particles (pf-localization's list of runs is not "
                "supported)");
    }
    readInt(c, s, "particles_count", o.particles_count, 1, Localizer::TOptions::kMaxParticles);
    {
        int mode = static_cast<int>(o.init_PDF_mode);
        if (c.keyExists(s, "init_PDF_mode"))
        {
            // pf-localization reads it as a boolean: accept true/false as 1/0.
            const std::string v = detail::trimValue(c.read_string(s, "init_PDF_mode", ""));
            if (v == "true" || v == "false")
            {
                mode = v == "true" ? 1 : 0;
            }
            else
            {
                readInt(c, s, "init_PDF_mode", mode, 0, 3);
            }
        }
        o.init_PDF_mode = static_cast<Localizer::InitMode>(mode);
    }
    constexpr double kBig = 1e9;
    readDouble(c, s, "init_PDF_min_x", o.init_PDF_min_x, -kBig, kBig);
    readDouble(c, s, "init_PDF_max_x", o.init_PDF_max_x, -kBig, kBig);
    readDouble(c, s, "init_PDF_min_y", o.init_PDF_min_y, -kBig, kBig);
    readDouble(c, s, "init_PDF_max_y", o.init_PDF_max_y, -kBig, kBig);
    readDouble(c, s, "init_PDF_min_yaw_deg", o.init_PDF_min_yaw_deg, -360, 360);
    readDouble(c, s, "init_PDF_max_yaw_deg", o.init_PDF_max_yaw_deg, -360, 360);
    readDouble(c, s, "init_PDF_mean_x", o.init_PDF_mean_x, -kBig, kBig);
    readDouble(c, s, "init_PDF_mean_y", o.init_PDF_mean_y, -kBig, kBig);
    readDouble(c, s, "init_PDF_mean_yaw_deg", o.init_PDF_mean_yaw_deg, -360, 360);
    readDouble(c, s, "init_PDF_std_xy", o.init_PDF_std_xy, 0, kBig);
    readDouble(c, s, "init_PDF_std_yaw_deg", o.init_PDF_std_yaw_deg, 0, 360);
    readDouble(c, s, "init_PDF_from_detections", o.init_PDF_from_detections, 0, 1);
    {
        int sd = static_cast<int>(o.seed);
        readInt(c, s, "seed", sd, 0, std::numeric_limits<int>::max());
        o.seed = static_cast<uint32_t>(sd);
    }
    if (o.init_PDF_min_yaw_deg > o.init_PDF_max_yaw_deg)
    {
        bad(s, "init_PDF_max_yaw_deg", "must be >= init_PDF_min_yaw_deg");
    }
    if (o.init_PDF_mode == Localizer::InitMode::Box &&
        !(o.init_PDF_min_x < o.init_PDF_max_x && o.init_PDF_min_y < o.init_PDF_max_y))
    {
        bad(s, "init_PDF_mode",
            "1 (uniform in a box) needs init_PDF_min_x < init_PDF_max_x and init_PDF_min_y < "
            "init_PDF_max_y");
    }
}

/** [PF_options]: MRPT's TParticleFilterOptions, then ours. */
void loadParticleFilter(const mrpt::config::CConfigFileBase& c, Localizer::TOptions& o)
{
    // [PF_options]: MRPT's TParticleFilterOptions, strictly, plus ours.
    {
        auto known = keysOf(o.pf);
        known.insert(known.end(), {"threads", "free_space_prior", "kld_at_resampling"});
        for (const std::string& k : kRecoveryKeys)
        {
            known.push_back("recovery_" + k);  // deprecated: [Recovery] k
        }
        rejectUnknownKeys(c, kPF, known);
    }
    o.pf.PF_algorithm = static_cast<CParticleFilter::TParticleFilterAlgorithm>(
        readEnum(c, kPF, "PF_algorithm", o.pf.PF_algorithm, kAlgorithms));
    o.pf.resamplingMethod = static_cast<CParticleFilter::TParticleResamplingAlgorithm>(
        readEnum(c, kPF, "resamplingMethod", o.pf.resamplingMethod, kResampling));
    readBool(c, kPF, "adaptiveSampleSize", o.pf.adaptiveSampleSize);
    readDouble(c, kPF, "BETA", o.pf.BETA, 0, 1);
    {
        int ss = static_cast<int>(o.pf.sampleSize);
        readInt(c, kPF, "sampleSize", ss, 0, 100000000);  // pf-localization ignores it too
        o.pf.sampleSize = static_cast<unsigned>(ss);
        int ms = static_cast<int>(o.pf.pfAuxFilterOptimal_MaximumSearchSamples);
        readInt(c, kPF, "pfAuxFilterOptimal_MaximumSearchSamples", ms, 1, 100000000);
        o.pf.pfAuxFilterOptimal_MaximumSearchSamples = static_cast<unsigned>(ms);
    }
    readDouble(c, kPF, "powFactor", o.pf.powFactor, 1e-9, 1e9);
    readDouble(c, kPF, "max_loglikelihood_dyn_range", o.pf.max_loglikelihood_dyn_range, 0, 1e9);
    readBool(c, kPF, "pfAuxFilterStandard_FirstStageWeightsMonteCarlo",
             o.pf.pfAuxFilterStandard_FirstStageWeightsMonteCarlo);
    readBool(c, kPF, "pfAuxFilterOptimal_MLE", o.pf.pfAuxFilterOptimal_MLE);
    readInt(c, kPF, "threads", o.threads, 0, Localizer::TOptions::kMaxThreads);
    readBool(c, kPF, "free_space_prior", o.free_space_prior);
    readBool(c, kPF, "kld_at_resampling", o.kld_at_resampling);
}

/** [Recovery] (or its keys' deprecated names in [PF_options]: `places`). */
void loadRecovery(const mrpt::config::CConfigFileBase& c, const std::map<std::string, KeyPlace>& at,
                  AugmentedMCL::TOptions& r)
{
    rejectUnknownKeys(c, kRec, kRecoveryKeys);
    auto num = [&](const std::string& k, double& v, double lo, double hi)
    { readDouble(c, at.at(k).section, at.at(k).key, v, lo, hi); };
    {
        std::string t = recoveryTriggerName(r.trigger);
        readChoice(c, at.at("trigger").section, at.at("trigger").key, t,
                   {"off", "amcl", "evidence"});
        r.trigger = t == "off"        ? RecoveryTrigger::Off
                    : t == "evidence" ? RecoveryTrigger::Evidence
                                      : RecoveryTrigger::Amcl;
    }
    num("alpha_slow", r.alpha_slow, 0, 1);
    num("alpha_fast", r.alpha_fast, 0, 1);
    num("evidence_margin", r.evidence_margin, -1e3, 1e3);
    num("evidence_threshold", r.evidence_threshold, 1e-3, 1e6);
    num("inject_share", r.inject_share, 1e-6, 1);
    num("from_detections", r.from_detections, 0, 1);
    num("injected_weight", r.injected_weight, 1e-12, 1);
    int frames = static_cast<int>(r.challenger_frames);
    readInt(c, at.at("challenger_frames").section, at.at("challenger_frames").key, frames, 0,
            1000000);
    r.challenger_frames = static_cast<size_t>(frames);
    num("lost_var_xy_m2", r.lost_var_xy_m2, 0, 1e12);
}

/** The [PF_options] and [Recovery] combinations MRPT or semloc do not implement (a recovery
 *  key named at `at`, its place). */
void checkParticleFilter(const Localizer::TOptions& o, const std::map<std::string, KeyPlace>& at)
{
    auto badRec = [&](const std::string& k, const std::string& what)
    { bad(at.at(k).section, at.at(k).key, what); };
    auto name = [&](const std::string& k) { return at.at(k).section == kRec ? k : at.at(k).key; };
    if (o.pf.PF_algorithm == CParticleFilter::pfOptimalProposal)
    {
        bad(kPF, "PF_algorithm",
            "2 (pfOptimalProposal) is not implemented by MRPT's CMonteCarloLocalization2D; use "
            "0, 1 or 3");
    }
    if (o.pf.adaptiveSampleSize && !o.kld_at_resampling &&
        (o.pf.PF_algorithm != CParticleFilter::pfStandardProposal ||
         o.pf.resamplingMethod != CParticleFilter::prMultinomial))
    {
        bad(kPF, "adaptiveSampleSize",
            "1 (KLD sampling) needs PF_algorithm = 0 (pfStandardProposal) and resamplingMethod "
            "= 0 (prMultinomial), or kld_at_resampling = 1");
    }
    if (o.kld_at_resampling &&
        (!o.pf.adaptiveSampleSize || o.pf.PF_algorithm != CParticleFilter::pfStandardProposal))
    {
        bad(kPF, "kld_at_resampling",
            "1 needs adaptiveSampleSize = 1 and PF_algorithm = 0 (pfStandardProposal)");
    }
    const bool ratesOff = o.recovery.alpha_slow == 0 && o.recovery.alpha_fast == 0;
    if (o.recovery.trigger != RecoveryTrigger::Amcl && !ratesOff)
    {
        badRec("alpha_slow", "the rates are augmented MCL's (" + name("trigger") +
                                 " = amcl); with " + name("trigger") + " = " +
                                 recoveryTriggerName(o.recovery.trigger) + " set both to 0");
    }
    const bool recoveryOff = !o.recovery.enabled();
    if (o.recovery.trigger == RecoveryTrigger::Amcl && !ratesOff && recoveryOff)
    {
        badRec("alpha_fast", "augmented MCL needs 0 < " + name("alpha_slow") + " < " +
                                 name("alpha_fast") + " <= 1 (both 0: off)");
    }
    if (o.free_space_prior && o.pf.PF_algorithm != CParticleFilter::pfStandardProposal)
    {
        bad(kPF, "free_space_prior", "needs PF_algorithm = 0 (pfStandardProposal)");
    }
    if (!recoveryOff && o.pf.PF_algorithm != CParticleFilter::pfStandardProposal)
    {
        badRec(o.recovery.trigger == RecoveryTrigger::Amcl ? "alpha_slow" : "trigger",
               "recovery needs [PF_options] PF_algorithm = 0 (pfStandardProposal)");
    }
    if (recoveryOff && o.recovery.lost_var_xy_m2 > 0)
    {
        badRec("lost_var_xy_m2", "the sensor resetting while lost is part of the recovery: set " +
                                     name("trigger") + " (amcl or evidence) or 0 here");
    }
    if (!recoveryOff && o.recovery.challenger_frames > 0 && o.pf.adaptiveSampleSize &&
        !o.kld_at_resampling)
    {
        badRec("challenger_frames",
               "challengers move with the filter's own prediction: with [PF_options] "
               "adaptiveSampleSize = 1 set kld_at_resampling = 1");
    }
}

/** [KLD_options]: MRPT's KLD-sampling parameters. */
void loadKLD(const mrpt::config::CConfigFileBase& c, mrpt::slam::TKLDParams& kld)
{
    // [KLD_options]
    rejectUnknownKeys(c, kKLD,
                      {"KLD_binSize_XY", "KLD_binSize_PHI_deg", "KLD_delta", "KLD_epsilon",
                       "KLD_minSampleSize", "KLD_maxSampleSize", "KLD_minSamplesPerBin"});
    readDouble(c, kKLD, "KLD_binSize_XY", kld.KLD_binSize_XY, 1e-6, 1e6);
    {
        double phiDeg = mrpt::RAD2DEG(kld.KLD_binSize_PHI);
        readDouble(c, kKLD, "KLD_binSize_PHI_deg", phiDeg, 1e-6, 360);
        kld.KLD_binSize_PHI = mrpt::DEG2RAD(phiDeg);
    }
    readDouble(c, kKLD, "KLD_delta", kld.KLD_delta, 1e-12, 1 - 1e-12);
    readDouble(c, kKLD, "KLD_epsilon", kld.KLD_epsilon, 1e-12, 1e6);
    int kMin = static_cast<int>(kld.KLD_minSampleSize),
        kMax = static_cast<int>(kld.KLD_maxSampleSize);
    readInt(c, kKLD, "KLD_minSampleSize", kMin, 1, 100000000);
    readInt(c, kKLD, "KLD_maxSampleSize", kMax, 1, 100000000);
    if (kMax < kMin)
    {
        bad(kKLD, "KLD_maxSampleSize", "must be >= KLD_minSampleSize");
    }
    kld.KLD_minSampleSize = static_cast<unsigned>(kMin);
    kld.KLD_maxSampleSize = static_cast<unsigned>(kMax);
    readDouble(c, kKLD, "KLD_minSamplesPerBin", kld.KLD_minSamplesPerBin, 0, 1e9);
}

/** [DummyOdometryParams]: the odometry noise of observations-only rawlogs. */
void loadOdometryNoise(const mrpt::config::CConfigFileBase& c, Localizer::TOptions& o)
{
    // [DummyOdometryParams]; the 3D keys are pf-localization's, checked and unused here.
    rejectUnknownKeys(c, kOdo,
                      {"minStdXY", "minStdPHI", "allow_no_odometry", "additional_std_XYZ",
                       "additional_std_angle"});
    readDouble(c, kOdo, "minStdXY", o.odometry_min_std_xy, 0, 1e3);
    readDouble(c, kOdo, "minStdPHI", o.odometry_min_std_phi_deg, 0, 360);
    readBool(c, kOdo, "allow_no_odometry", o.allow_no_odometry);
    double unused3D = 0;
    readDouble(c, kOdo, "additional_std_XYZ", unused3D, 0, 1e3);
    readDouble(c, kOdo, "additional_std_angle", unused3D, 0, 360);
}
}  // namespace

Localizer::TOptions::TOptions()
{
    pf.PF_algorithm = CParticleFilter::pfStandardProposal;
    pf.resamplingMethod = CParticleFilter::prMultinomial;
}

std::vector<std::string> Localizer::TOptions::experimentKeys()
{
    return {"particles_count",
            "init_PDF_mode",
            "init_PDF_min_x",
            "init_PDF_max_x",
            "init_PDF_min_y",
            "init_PDF_max_y",
            "init_PDF_min_yaw_deg",
            "init_PDF_max_yaw_deg",
            "init_PDF_mean_x",
            "init_PDF_mean_y",
            "init_PDF_mean_yaw_deg",
            "init_PDF_std_xy",
            "init_PDF_std_yaw_deg",
            "init_PDF_from_detections",
            "seed"};
}

size_t Localizer::TOptions::effectiveThreads() const
{
    return threads > 0 ? static_cast<size_t>(threads)
                       : std::max<size_t>(1, std::thread::hardware_concurrency());
}

uint64_t Localizer::TOptions::particleMemoryBytes() const
{
    uint64_t bytes = kBytesPerParticle * static_cast<uint64_t>(particles_count);
    if (pf.adaptiveSampleSize)
    {
        bytes += kBytesPerKLDParticle * static_cast<uint64_t>(kld.KLD_maxSampleSize);
    }
    return bytes;
}

void Localizer::TOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                             const std::string& s)
{
    loadInitialCloud(c, s, *this);
    loadParticleFilter(c, *this);
    warnings.clear();
    const auto recoveryAt = recoveryKeyPlaces(c, warnings);
    loadRecovery(c, recoveryAt, recovery);
    checkParticleFilter(*this, recoveryAt);
    loadKLD(c, kld);
    loadOdometryNoise(c, *this);
    motion_model.loadFromConfigFile(c, MotionModelConfig::kSection);
    if (motion_model.headingDrift() && (pf.PF_algorithm != CParticleFilter::pfStandardProposal ||
                                        (pf.adaptiveSampleSize && !kld_at_resampling)))
    {
        bad(MotionModelConfig::kSection, "heading_drift_std_deg_per_min",
            "the heading drift state needs [PF_options] PF_algorithm = 0 (pfStandardProposal) "
            "and, with adaptiveSampleSize = 1, kld_at_resampling = 1");
    }
}

void Localizer::TOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                           const std::string& s) const
{
    put(c, s, "particles_count", std::to_string(particles_count), "number of particles");
    put(c, s, "init_PDF_mode", std::to_string(static_cast<int>(init_PDF_mode)),
        "0: uniform over the free space, 1: uniform in the box, 2: Gaussian, 3: 0 then the "
        "first detections");
    put(c, s, "init_PDF_min_x", init_PDF_min_x, "box [m] (mode 0: empty = whole free space)");
    put(c, s, "init_PDF_max_x", init_PDF_max_x, "");
    put(c, s, "init_PDF_min_y", init_PDF_min_y, "");
    put(c, s, "init_PDF_max_y", init_PDF_max_y, "");
    put(c, s, "init_PDF_min_yaw_deg", init_PDF_min_yaw_deg, "heading interval [deg]");
    put(c, s, "init_PDF_max_yaw_deg", init_PDF_max_yaw_deg, "");
    put(c, s, "init_PDF_mean_x", init_PDF_mean_x, "mode 2: mean [m]");
    put(c, s, "init_PDF_mean_y", init_PDF_mean_y, "");
    put(c, s, "init_PDF_mean_yaw_deg", init_PDF_mean_yaw_deg, "mode 2: mean heading [deg]");
    put(c, s, "init_PDF_std_xy", init_PDF_std_xy, "mode 2: std of x and y [m]");
    put(c, s, "init_PDF_std_yaw_deg", init_PDF_std_yaw_deg, "mode 2: std of the heading [deg]");
    put(c, s, "init_PDF_from_detections", init_PDF_from_detections,
        "mode 3: share of the particles drawn from the first detections");
    put(c, s, "seed", std::to_string(seed), "seed of MRPT's random generator");

    put(c, kPF, "PF_algorithm", std::to_string(static_cast<int>(pf.PF_algorithm)),
        kAlgorithms[pf.PF_algorithm]);
    put(c, kPF, "resamplingMethod", std::to_string(static_cast<int>(pf.resamplingMethod)),
        kResampling[pf.resamplingMethod]);
    put(c, kPF, "adaptiveSampleSize", pf.adaptiveSampleSize ? "1" : "0", "KLD sampling");
    put(c, kPF, "BETA", pf.BETA, "resample when ESS < BETA");
    put(c, kPF, "sampleSize", std::to_string(pf.sampleSize), "ignored: see particles_count");
    put(c, kPF, "pfAuxFilterOptimal_MaximumSearchSamples",
        std::to_string(pf.pfAuxFilterOptimal_MaximumSearchSamples), "PF_algorithm 1 and 3");
    put(c, kPF, "powFactor", pf.powFactor, "log-likelihoods are multiplied by this");
    put(c, kPF, "max_loglikelihood_dyn_range", pf.max_loglikelihood_dyn_range, "PF_algorithm 3");
    put(c, kPF, "pfAuxFilterStandard_FirstStageWeightsMonteCarlo",
        pf.pfAuxFilterStandard_FirstStageWeightsMonteCarlo ? "1" : "0", "PF_algorithm 1");
    put(c, kPF, "pfAuxFilterOptimal_MLE", pf.pfAuxFilterOptimal_MLE ? "1" : "0", "PF_algorithm 3");
    put(c, kPF, "threads", std::to_string(threads), "0: every hardware thread");
    put(c, kPF, "free_space_prior", free_space_prior ? "1" : "0",
        "weight 0 outside the free space");
    put(c, kPF, "kld_at_resampling", kld_at_resampling ? "1" : "0",
        "KLD sampling when resampling, not at every step");

    put(c, kKLD, "KLD_binSize_XY", kld.KLD_binSize_XY, "[m]");
    put(c, kKLD, "KLD_binSize_PHI_deg", mrpt::RAD2DEG(kld.KLD_binSize_PHI), "[deg]");
    put(c, kKLD, "KLD_delta", kld.KLD_delta, "");
    put(c, kKLD, "KLD_epsilon", kld.KLD_epsilon, "");
    put(c, kKLD, "KLD_minSampleSize", std::to_string(kld.KLD_minSampleSize), "");
    put(c, kKLD, "KLD_maxSampleSize", std::to_string(kld.KLD_maxSampleSize), "");
    put(c, kKLD, "KLD_minSamplesPerBin", kld.KLD_minSamplesPerBin, "");

    put(c, kOdo, "minStdXY", odometry_min_std_xy, "[m] observations-only rawlogs");
    put(c, kOdo, "minStdPHI", odometry_min_std_phi_deg, "[deg]");
    put(c, kOdo, "allow_no_odometry", allow_no_odometry ? "true" : "false",
        "true: a rawlog without odometry moves by zero + this noise");
    put(c, kRec, "trigger", recoveryTriggerName(recovery.trigger), "off | amcl | evidence");
    put(c, kRec, "alpha_slow", recovery.alpha_slow, "amcl (0 0: off)");
    put(c, kRec, "alpha_fast", recovery.alpha_fast, "");
    put(c, kRec, "evidence_margin", recovery.evidence_margin, "evidence [nats per frame]");
    put(c, kRec, "evidence_threshold", recovery.evidence_threshold, "evidence [nats]");
    put(c, kRec, "inject_share", recovery.inject_share, "evidence: share replaced per frame");
    put(c, kRec, "from_detections", recovery.from_detections,
        "fraction of injected particles drawn from the detections");
    put(c, kRec, "injected_weight", recovery.injected_weight,
        "weight of an injected particle relative to a resampled one, (0, 1]");
    put(c, kRec, "challenger_frames", std::to_string(recovery.challenger_frames),
        "0: injected into the cloud; n: a challenger set, at most n frames");
    put(c, kRec, "lost_var_xy_m2", recovery.lost_var_xy_m2,
        "lost above this x-y variance [m^2]: detections re-seed the cloud; 0: off");
    motion_model.saveToConfigFile(c, MotionModelConfig::kSection);
}

}  // namespace semloc
