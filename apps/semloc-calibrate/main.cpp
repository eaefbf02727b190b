/* semloc-calibrate: the detector's and the odometry's noise of a dataset with ground truth, as a
 * semloc-localize configuration:
 *   semloc-calibrate run.rawlog --world w.yaml --ground-truth run_gt.txt --base semantic.ini \
 *                    -o calibrated.ini [--report DIR]
 * docs/tools.md, "semloc-calibrate". */
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <semloc/calibration/SensorCalibration.h>
#include <semloc/calibration/SensorModelCalibration.h>
#include <semloc/dataset/GroundTruthFile.h>
#include <semloc/experiment/LocalizationExperiment.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/io/OutputPaths.h>
#include <semloc/io/ProcessControl.h>
#include <semloc/io/StagedDirectory.h>
#include <semloc/simulator/Simulator.h>
#include <semloc/world/World.h>

#include <fstream>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "common/AppMain.h"
#include "common/ProgressBar.h"

namespace
{
TCLAP::CmdLine cmd(
    "semloc-calibrate: a dataset's detector and odometry noise, fitted against "
    "its ground truth, as a semloc-localize configuration",
    ' ', "0.1");
TCLAP::UnlabeledValueArg<std::string> argRawlog("rawlog", "Dataset (rawlog)", true, "",
                                                "DATASET.rawlog", cmd);
TCLAP::ValueArg<std::string> argWorld("", "world", "World file (YAML) of the dataset", true, "",
                                      "W.yaml", cmd);
TCLAP::ValueArg<std::string> argGroundTruth("", "ground-truth", "Ground truth: t x y phi per line",
                                            true, "", "GT.txt", cmd);
TCLAP::ValueArg<std::string> argBase("", "base", "semloc-localize ini the fits are written into",
                                     true, "", "BASE.ini", cmd);
TCLAP::ValueArg<std::string> argOut("o", "output", "Calibrated ini to write", true, "", "OUT.ini",
                                    cmd);
TCLAP::ValueArg<std::string> argReport("", "report", "Directory for report.md and its figures",
                                       false, "", "DIR", cmd);
TCLAP::ValueArg<int> argConsistencySeeds(
    "", "consistency-seeds",
    "Filter runs per setting of the consistency stage (default 2; 0: no consistency stage, "
    "the fits written as fitted)",
    false, 2, "N", cmd);
TCLAP::ValueArg<double> argGate("", "gate-m",
                                "Matching gate around an object's centre [m] (default 3)", false,
                                3.0, "G", cmd);

/** The calibrated ini `written` (to be renamed `out`) loads in semloc-localize: it always
 *  should (every fit is kept to its key's range, the base was checked). */
void checkWritten(const std::string& written, const std::string& out)
{
    try
    {
        semloc::LocalizationExperiment::CheckConfig(written, argWorld.getValue());
    }
    catch (const std::exception& e)
    {
        throw std::runtime_error(
            "the calibrated ini '" + out +
            "' would be refused by semloc-localize (not written): " + semloc::errorMessage(e));
    }
}

/** The progress of the long steps, shown by `bar` (nothing when stderr is not a terminal). */
semloc::CalibrationProgress progressOn(semloc::apps::ProgressBar& bar)
{
    if (!bar.shown())
    {
        return {};
    }
    return [&bar](const semloc::TCalibrationProgress& p)
    { bar.show("semloc-calibrate: " + p.stage, p.done, p.total, p.unit); };
}

/** The consistency stage (SensorCalibration::Consistency), each setting shown on stderr. */
semloc::TCalibrationResult consistency(semloc::TCalibrationResult fitted,
                                       const std::string& baseText, semloc::apps::ProgressBar& bar)
{
    semloc::SensorCalibration::TConsistencyOptions c;
    c.seeds.clear();
    for (int s = 1; s <= argConsistencySeeds.getValue(); s++)
    {
        c.seeds.push_back(static_cast<uint32_t>(s));
    }
    return semloc::SensorCalibration::Consistency(
        std::move(fitted), baseText, argBase.getValue(), argWorld.getValue(), argRawlog.getValue(),
        argGroundTruth.getValue(), c,
        [&bar](const semloc::TConsistencyTrial& t)
        {
            bar.erase();
            std::cerr << "semloc-calibrate: consistency: detector sigmas x" << t.sensorScale
                      << ", motion noise x" << t.motionScale << ", likelihood tempered x"
                      << t.temper << ": NEES inside its 95 % bound in " << 100 * t.insideShare
                      << " % of the steps, mean error " << t.meanErr_m << " m, " << t.converged
                      << " of " << t.runs << " runs converged\n";
        },
        progressOn(bar));
}

/** The rawlog, the world, the ground truth and every base of the base ini's chain. */
std::vector<std::string> inputFiles()
{
    std::vector<std::string> in = semloc::config::iniFileAndBases(argBase.getValue());
    in.insert(in.end(), {argRawlog.getValue(), argWorld.getValue(), argGroundTruth.getValue()});
    return in;
}

/** What is fitted and written. */
struct Calibration
{
    /** The base has a semantic map (SensorCalibration) and models of the water column
     *  (SensorModelCalibration). */
    bool semantic = false;
    semloc::TCalibrationResult result;
    std::vector<semloc::TModelFits> modelFits;
    std::string ini;
};

/** Checks the base (as semloc-localize would), then fits what it runs. */
Calibration calibrate(semloc::SensorCalibration::TOptions o)
{
    const std::string base = argBase.getValue(), rawlogPath = argRawlog.getValue();
    // Everything is read and checked before anything is written.
    const std::string baseText = semloc::config::readIniText(base);  // its bases resolved
    Calibration c;
    c.semantic =
        mrpt::config::CConfigFileMemory(baseText).read_int("MetricMap", "semanticMap_count", 0) > 0;
    const bool models = semloc::SensorModelCalibration::HasModels(baseText);
    if (c.semantic || !models)
    {
        semloc::SensorCalibration::CheckBase(base, argWorld.getValue());
    }
    else
    {
        semloc::LocalizationExperiment::CheckConfig(base, argWorld.getValue());
    }
    semloc::SensorCalibration::ReadBaseOptions(baseText, o);
    const auto world = semloc::World::FromFile(argWorld.getValue());
    auto gt = semloc::GroundTruthFile::Read(argGroundTruth.getValue());
    if (models)
    {
        c.modelFits = semloc::SensorModelCalibration::Estimate(
            rawlogPath, baseText, base, argWorld.getValue(), gt, o.gtTolerance_s, o.gate_m);
    }
    semloc::apps::ProgressBar bar;
    if (c.semantic)
    {
        // The rawlog is streamed through the passes: memory does not grow with its length.
        c.result = semloc::SensorCalibration::EstimateFromFile(rawlogPath, world, std::move(gt), o,
                                                               progressOn(bar));
        bar.erase();
        if (argConsistencySeeds.getValue() > 0)
        {
            c.result = consistency(std::move(c.result), baseText, bar);
            bar.erase();
        }
        c.ini =
            semloc::SensorCalibration::ApplyToIni(baseText, base, c.result, argWorld.getValue());
    }
    else
    {
        c.ini = std::string(semloc::SensorCalibration::kIniHeader) + "the fits written into " +
                base + "\n" + baseText;
    }
    c.ini = semloc::SensorModelCalibration::ApplyToIni(c.ini, base, c.modelFits,
                                                       c.semantic ? "" : argWorld.getValue());
    return c;
}

/** The warnings on stderr, then the values as the ini has them on stdout, and why where they
 *  are not the fits. */
void printOutcome(const Calibration& c, const std::vector<semloc::TFigureWarning>& figureWarnings)
{
    for (const auto& w : figureWarnings)
    {
        std::cerr << "semloc-calibrate: warning: " << w.text() << "\n";
    }
    auto warnings = semloc::SensorModelCalibration::Warnings(c.modelFits);
    if (c.semantic)
    {
        const auto w = semloc::SensorCalibration::Warnings(c.result);
        warnings.insert(warnings.begin(), w.begin(), w.end());
    }
    for (const auto& w : warnings)
    {
        std::cerr << "semloc-calibrate: warning: " << w << "\n";
    }
    const std::string report = argReport.getValue();
    const std::string wrote =
        "wrote " + argOut.getValue() + (report.empty() ? "" : " and " + report) + "\n";
    if (c.semantic)
    {
        std::cout << "semloc-calibrate: " << semloc::SensorCalibration::SummaryText(c.result, c.ini)
                  << "; " << wrote << semloc::SensorCalibration::BiasText(c.result)
                  << semloc::SensorCalibration::ConsistencyText(c.result);
    }
    else
    {
        std::cout << "semloc-calibrate: " << wrote;
    }
    std::cout << semloc::SensorModelCalibration::SummaryText(c.modelFits);
}

void run()
{
    const std::string out = argOut.getValue(), report = argReport.getValue();
    const std::vector<std::string> inputs = inputFiles();
    semloc::checkOutputFile(
        out, inputs,
        [](const std::string& p)
        { return semloc::fileStartsWith(p, semloc::SensorCalibration::kIniHeader); });
    std::unique_ptr<semloc::StagedDirectory> staged;
    if (!report.empty())
    {
        staged = std::make_unique<semloc::StagedDirectory>(report, inputs);
    }
    semloc::SensorCalibration::TOptions o;
    o.gate_m = argGate.getValue();
    if (!(o.gate_m > 0))
    {
        throw std::invalid_argument("--gate-m must be > 0");
    }
    if (argConsistencySeeds.getValue() < 0 || argConsistencySeeds.getValue() > 100)
    {
        throw std::invalid_argument("--consistency-seeds must be in [0, 100]");
    }
    const Calibration c = calibrate(o);

    semloc::installInterruptHandlers();
    std::vector<semloc::TFigureWarning> figureWarnings;
    if (staged)
    {
        figureWarnings = c.semantic
                             ? semloc::SensorCalibration::WriteReport(c.result, *staged)
                             : semloc::SensorModelCalibration::WriteReport(c.modelFits, *staged);
    }
    semloc::writeOutputFiles({out},
                             [&](const std::vector<std::string>& tmp)
                             {
                                 std::ofstream f(tmp[0], std::ios::binary);
                                 f << c.ini;
                                 if (!f.flush())
                                 {
                                     throw std::runtime_error("cannot write '" + out + "'");
                                 }
                                 f.close();
                                 checkWritten(tmp[0], out);
                             });
    if (staged)
    {
        staged->commit();
    }
    printOutcome(c, figureWarnings);
}
}  // namespace

int main(int argc, char** argv)
{
    return semloc::apps::runMain(cmd, argc, argv, "semloc-calibrate", run);
}
