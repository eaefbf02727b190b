/* semloc — the bad-input table's rows of an AUV's models and simulated sensors: their ini keys
 * in semloc-localize and semloc-simulate, and their observations in a rawlog. */
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <semloc/observation/CObservationDepth.h>
#include <semloc/simulator/Simulator.h>

#include <filesystem>
#include <string>
#include <vector>

#include "io/BadInputBuilders.h"

namespace semloc::test::bad_input
{
namespace
{
using semloc::Simulator;
using semloc::TSimulatorOptions;

const std::string kSeabed = kSrc + "/maps/seabed_200x200.yaml";

/** semloc-localize with config/localize/auv/<config>.ini on the seabed, `keys` replaced and
 *  `extra` appended, on the simulated rawlog (config errors come before it is read). */
std::vector<std::string> localizeAuv(const fs::path& d, const std::string& config, const Keys& keys,
                                     const std::string& extra = "")
{
    saveGz(simulate().rawlog, d / "data.rawlog");
    Keys k = keys;
    k.emplace_back("map_file", kSeabed);
    return localize(d, writeIni(d, extra, k, "auv/" + config), d / "data.rawlog");
}

/** semloc-simulate of the seabed with `sections` (ini text). */
std::vector<std::string> simulateAuv(const fs::path& d, const std::string& sections)
{
    writeText(d / "sim.ini",
              "[Simulation]\nworld_file = " + kSeabed + "\nmax_steps = 5\n" + sections);
    return {"semloc-simulate", (d / "sim.ini").string(), "-o", (d / "sim.rawlog").string()};
}

/** A simulated AUV survey (config/simulate/simulate_auv.ini, 30 steps) with `obs` added to
 *  the frame of step 3, localized with config/localize/auv/<config>.ini. */
std::vector<std::string> localizeWithObservation(const fs::path& d, const std::string& config,
                                                 const mrpt::obs::CObservation::Ptr& obs)
{
    auto o = TSimulatorOptions::FromConfigFile(kSrc + "/config/simulate/simulate_auv.ini");
    o.simulation.max_steps = 30;
    auto sim = Simulator(o).run();
    auto frame = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(sim.rawlog.getAsGeneric(7));
    obs->timestamp = frame->getObservationByIndex(0)->timestamp;
    frame->insert(obs);
    saveGz(sim.rawlog, d / "data.rawlog");
    return localize(d, writeIni(d, "", {{"map_file", kSeabed}}, "auv/" + config),
                    d / "data.rawlog");
}
}  // namespace

Cases auvModelCases()
{
    return {
        {"auv-ini-sidescan-beam-out-of-range",
         [](const fs::path& d) {
             return localizeAuv(d, "sidescan", {{"beam_width_deg", "0"}});
         }},
        {"auv-ini-sidescan-unknown-key",
         [](const fs::path& d)
         {
             return localizeAuv(d, "sidescan", {},
                                "[MetricMap_sideScanMap_00_likelihoodOpts]\nbeam_width = 4\n");
         }},
        {"auv-ini-sidescan-range-kind",
         [](const fs::path& d) {
             return localizeAuv(d, "sidescan", {{"range_kind", "sloped"}});
         }},
        {"auv-ini-compass-sigma-zero",
         [](const fs::path& d) {
             return localizeAuv(d, "dead_reckoning", {{"sigma_deg", "0"}});
         }},
        {"auv-ini-fix-outlier-sigma-zero",
         [](const fs::path& d) {
             return localizeAuv(d, "usbl", {{"outlier_sigma_m", "0"}});
         }},
        {"auv-ini-dvl-a1-negative",
         [](const fs::path& d) {
             return localizeAuv(d, "dead_reckoning", {{"a1", "-0.1"}});
         }},
        {"auv-ini-motion-kind-unknown",
         [](const fs::path& d) {
             return localizeAuv(d, "dead_reckoning", {{"kind", "dvll"}});
         }},
        {"auv-sim-usbl-period-zero", [](const fs::path& d)
         { return simulateAuv(d, "[USBL]\nenabled = true\nperiod_steps = 0\n"); }},
        {"auv-sim-sidescan-unknown-key", [](const fs::path& d)
         { return simulateAuv(d, "[SideScan]\nenabled = true\nbeam_width = 4\n"); }},
        {"auv-sim-compass-sigma-negative", [](const fs::path& d)
         { return simulateAuv(d, "[Compass]\nenabled = true\nsigma_deg = -1\n"); }},
        {"auv-rawlog-depth-nan",
         [](const fs::path& d)
         {
             auto depth = CObservationDepth::Create();
             depth->depth_m = std::nan("");
             return localizeWithObservation(d, "sidescan", depth);
         }},
        {"auv-rawlog-fix-covariance-not-positive",
         [](const fs::path& d)
         {
             auto fix = mrpt::obs::CObservationRobotPose::Create();
             fix->sensorLabel = "usbl";
             fix->pose.cov.setZero();
             return localizeWithObservation(d, "usbl", fix);
         }},
    };
}

}  // namespace semloc::test::bad_input
