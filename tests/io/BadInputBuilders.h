/* semloc tests — what the cases of docs/bad-input.md's table are built from: a small simulated
 * dataset, the shipped ini files with keys replaced, and the tools' command lines. Each case is
 * a Builder: it writes its bad input into a fresh directory and returns the command line. */
#pragma once

#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <semloc/simulator/Simulator.h>

#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "TestHelpers.h"

namespace semloc::test::bad_input
{
namespace fs = std::filesystem;

inline const std::string kSrc = SEMLOC_SOURCE_DIR;
inline const std::string kBin = SEMLOC_BIN_DIR;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
/** A valid world's name and bounds, followed by the YAML of a case. */
inline const std::string kBounds = "name: w\nbounds: {x_min: 0, x_max: 20, y_min: 0, y_max: 20}\n";

using semloc::test::readText;
void writeText(const fs::path& p, const std::string& s);

/** A 6-step simulated paper dataset (action / sensory-frame pairs). */
semloc::SimulationResult simulate();
void saveGz(const mrpt::obs::CRawlog& log, const fs::path& p);
void savePlain(const mrpt::obs::CRawlog& log, const fs::path& p);

using Keys = std::vector<std::pair<std::string, std::string>>;

/** config/<name>.ini (semantic.ini by default) with an absolute map, 200 particles, the
 *  `keys` replaced (each must be in the file) and `extra` appended, written as dir/loc.ini. */
fs::path writeIni(const fs::path& dir, const std::string& extra = "", Keys keys = {},
                  const std::string& name = "semantic");
/** config/<name>.ini as writeIni() writes semantic.ini. */
fs::path writeConfig(const fs::path& dir, const std::string& name, const Keys& keys = {});

/** Command line of a semloc-localize run with `ini` on `rawlog` into dir/out. */
std::vector<std::string> localize(const fs::path& dir, const fs::path& ini, const fs::path& rawlog,
                                  std::vector<std::string> extra = {});
/** A good dataset (gz rawlog) and the ini (see writeIni). */
std::vector<std::string> localizeGood(const fs::path& dir, const std::string& extra = "",
                                      const Keys& keys = {}, std::vector<std::string> args = {});
/** The uncompressed bytes of the simulated rawlog. */
std::string plainBytes(const fs::path& dir);
/** A ground-truth case: the good dataset plus `gt` as its ground truth file. */
std::vector<std::string> localizeWithGroundTruth(const fs::path& dir, const std::string& gt);
/** A world case: `objects`/`bounds` YAML text drawn by semloc-plot-world. */
std::vector<std::string> plotWorld(const fs::path& dir, const std::string& yaml);
/** A small landmark dataset as MRPT's simul-landmarks writes it (in.rawlog: 3 sensory frames
 *  of CObservationBearingRange seeing landmarks 1 and 2; its landmark and robot-path files)
 *  and the command line importing it with `options`. */
std::vector<std::string> importLandmarks(const fs::path& dir,
                                         const std::vector<std::string>& options);
/** A small CSV dataset (odom.csv, det.csv, gt.csv, lm.csv; `files` replaces the text of
 *  those it names) and the semloc-import command line importing it into out.rawlog with
 *  `options` (relative paths: the tool runs in `dir`). */
std::vector<std::string> importCsv(const fs::path& dir,
                                   const std::map<std::string, std::string>& files,
                                   const std::vector<std::string>& options = {});
/** The simulated rawlog with `edit` applied to it (in memory), saved gz. */
std::vector<std::string> localizeEdited(const fs::path& dir,
                                        const std::function<void(mrpt::obs::CRawlog&)>& edit);
/** The simulated rawlog with `edit` applied, localized with config/<config>.ini. */
std::vector<std::string> localizeEditedWith(const fs::path& dir, const std::string& config,
                                            const std::function<void(mrpt::obs::CRawlog&)>& edit);
/** The simulated rawlog with `edit` applied and its ground truth with every time multiplied
 *  by `timeScale`, as gt.txt. */
std::vector<std::string> localizeEditedWithGroundTruth(
    const fs::path& dir, const std::function<void(mrpt::obs::CRawlog&)>& edit,
    double timeScale = 1);

/** Every observation of the rawlog's sensory frames, in order. */
/** semloc-calibrate: the simulated dataset, its first `gtRows` ground-truth rows, the base
 *  config/<base>.ini copied as base.ini, the calibrated ini written to `out`. */
std::vector<std::string> calibrate(const fs::path& d, size_t gtRows, const std::string& base,
                                   const std::string& out);
/** A gnuplot in `d`/fake-bin (test_BadInput puts that directory first on the tool's PATH)
 *  that refuses to draw `figure` with a gnuplot-like error line and runs the real one for
 *  every other. */
void gnuplotRefusing(const fs::path& d, const std::string& figure);

std::vector<mrpt::obs::CObservation::Ptr> allObservations(mrpt::obs::CRawlog& log);

/** The first sensory frame's observation of class T. */
template <typename T>
std::shared_ptr<T> firstObservation(mrpt::obs::CRawlog& log)
{
    for (size_t i = 0; i < log.size(); i++)
    {
        if (const auto sf =
                std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(log.getAsGeneric(i)))
        {
            if (auto o = sf->getObservationByClass<T>())
            {
                return o;
            }
        }
    }
    return nullptr;
}

/** The observations of class T of the rawlog's sensory frames, in order. */
template <typename T>
std::vector<std::shared_ptr<T>> observationsOf(mrpt::obs::CRawlog& log)
{
    std::vector<std::shared_ptr<T>> out;
    for (const auto& o : allObservations(log))
    {
        if (auto t = std::dynamic_pointer_cast<T>(o))
        {
            out.push_back(t);
        }
    }
    return out;
}

/** A case: writes its input into the directory, returns the tool's command line. */
using Builder = std::function<std::vector<std::string>(const fs::path&)>;
using Cases = std::map<std::string, Builder>;

// The cases, by what is wrong (BadInputConfigCases.cpp, BadInputDataCases.cpp,
// BadInputImportCases.cpp, BadInputFigureCases.cpp).
Cases commandLineCases();
Cases iniFileCases();
Cases iniMapCases();
Cases shardCases();
Cases iniModelCases();
Cases iniRecoveryCases();
Cases outputDirectoryCases();
Cases outputFileCases();
Cases outputOverUserFileCases();
Cases worldSyntaxCases();
Cases worldContentCases();
Cases rawlogFileCases();
Cases rawlogDamagedCases();
Cases rawlogOdometryCases();
Cases timeCases();
Cases observationCases();
Cases importCases();
Cases csvBytesCases();
Cases csvValueCases();
Cases csvRealLogCases();
Cases csvAuvDetectionCases();
Cases csvAuvReadingCases();
Cases auvModelCases();
Cases iniMessageCases();
Cases calibrateCases();
Cases runPlotCases();
Cases figureCases();
// The hostile user's cases (BadInputSafetyCases.cpp): special files, shards and merges,
// calibration, large maps, the benchmark's active control.
Cases specialFileCases();
Cases benchmarkSafetyCases();
Cases calibrateSafetyCases();
Cases largeMapCases();
Cases reportSafetyCases();

inline std::vector<Cases> allCaseGroups()
{
    return {commandLineCases(),
            iniFileCases(),
            iniMapCases(),
            iniModelCases(),
            iniRecoveryCases(),
            outputDirectoryCases(),
            outputFileCases(),
            worldSyntaxCases(),
            worldContentCases(),
            rawlogFileCases(),
            rawlogDamagedCases(),
            rawlogOdometryCases(),
            timeCases(),
            observationCases(),
            importCases(),
            csvBytesCases(),
            csvValueCases(),
            csvRealLogCases(),
            csvAuvDetectionCases(),
            csvAuvReadingCases(),
            auvModelCases(),
            iniMessageCases(),
            calibrateCases(),
            runPlotCases(),
            figureCases(),
            outputOverUserFileCases(),
            shardCases(),
            specialFileCases(),
            benchmarkSafetyCases(),
            calibrateSafetyCases(),
            largeMapCases(),
            reportSafetyCases()};
}
}  // namespace semloc::test::bad_input
