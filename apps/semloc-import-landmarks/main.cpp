/* semloc-import-landmarks: turns a landmark dataset made by MRPT's simul-landmarks into a
 * semantic dataset semloc-localize runs on directly:
 *   semloc-import-landmarks OUT/kf-slam_demo.rawlog -o landmarks.rawlog
 * writes landmarks.rawlog (CObservationBearingRange -> CObservationSemantic),
 * landmarks_world.yaml (the landmarks as point objects) and landmarks_gt.txt (t x y phi). */
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/core/format.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/system/filesystem.h>
#include <semloc/dataset/GroundTruthFile.h>
#include <semloc/dataset/LandmarkImport.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/io/OutputPaths.h>
#include <semloc/io/ProcessControl.h>
#include <semloc/io/RawlogReader.h>
#include <semloc/io/RawlogWriter.h>
#include <semloc/simulator/Simulator.h>
#include <semloc/world/World.h>

#include <iostream>
#include <string>
#include <vector>

#include "common/AppMain.h"

namespace
{
TCLAP::CmdLine cmd("semloc-import-landmarks", ' ', "0.1");
TCLAP::UnlabeledValueArg<std::string> argIn("input", "Rawlog written by simul-landmarks", true, "",
                                            "in.rawlog", cmd);
TCLAP::ValueArg<std::string> argOut("o", "output", "Semantic rawlog to write", true, "",
                                    "out.rawlog", cmd);
TCLAP::ValueArg<std::string> argLabel("l", "label", "Label of every landmark", false, "landmark",
                                      "word", cmd);
TCLAP::ValueArg<std::string> argLandmarks("", "landmarks",
                                          "Landmark file (default: <input>_ground_truth.txt)",
                                          false, "", "file", cmd);
TCLAP::ValueArg<std::string> argPath(
    "", "path", "Robot path file (default: <input>_ground_truth_robot_path.txt)", false, "", "file",
    cmd);
TCLAP::ValueArg<double> argMargin("", "margin", "World bounds margin around landmarks and path [m]",
                                  false, 5.0, "m", cmd);

/** Before any work: the outputs replace neither an input nor a file of the user's. */
void checkOutputs(const std::string& out, const std::string& worldOut, const std::string& gtOut,
                  const std::vector<std::string>& inputs)
{
    semloc::checkOutputFile(out, inputs, semloc::RawlogReader::IsSemlocRawlog);
    semloc::checkOutputFile(gtOut, inputs, semloc::GroundTruthFile::IsGroundTruthFile);
    semloc::checkOutputFile(worldOut, inputs,
                            [](const std::string& p)
                            {
                                try
                                {
                                    (void)semloc::World::FromFile(p);
                                    return true;
                                }
                                catch (const std::exception&)
                                {
                                    return false;
                                }
                            });
}

void run()
{
    using semloc::LandmarkImport;
    LandmarkImport::checkOptions(argLabel.getValue(), argMargin.getValue());
    const std::string in = argIn.getValue(), out = argOut.getValue();
    const std::string landmarks =
        argLandmarks.isSet() ? argLandmarks.getValue() : in + "_ground_truth.txt";
    const std::string pathFile =
        argPath.isSet() ? argPath.getValue() : in + "_ground_truth_robot_path.txt";
    const std::string stem = mrpt::system::fileNameChangeExtension(out, "");
    const std::string base =
        stem.empty() || stem.back() != '.' ? stem : stem.substr(0, stem.size() - 1);
    const std::string worldOut = base + "_world.yaml", gtOut = base + "_gt.txt";
    checkOutputs(out, worldOut, gtOut, {in, landmarks, pathFile});

    mrpt::obs::CRawlog log = semloc::RawlogReader::Load(in);
    // The landmarks held compactly, the world without them: a million landmarks in 40 MB.
    const auto objects = LandmarkImport::readLandmarkSet(landmarks, argLabel.getValue());
    const auto path = LandmarkImport::readPath(pathFile);
    const auto world = LandmarkImport::makeWorldFrame(objects, path, argMargin.getValue(),
                                                      mrpt::system::extractFileName(in));
    const size_t n = LandmarkImport::convertRawlog(log, argLabel.getValue());
    if (n == 0)
    {
        THROW_EXCEPTION("'" + in + "' holds no CObservationBearingRange to convert");
    }
    const auto times = LandmarkImport::frameTimes(log);
    // Everything is checked; write the outputs.
    // Ctrl-C: exit 130, the temporary files removed, the outputs as they were.
    semloc::installInterruptHandlers();
    semloc::writeOutputFiles({gtOut, worldOut, out},
                             [&](const std::vector<std::string>& tmp)
                             {
                                 LandmarkImport::writeGroundTruth(times, path, tmp[0]);
                                 world.saveToFile(tmp[1], objects.objectList());
                                 // Its errors name the file and why.
                                 semloc::saveRawlog(log, tmp[2], "semloc-import-landmarks");
                             });
    std::cout << "Converted " << n << " observations of " << objects.size() << " landmarks: " << out
              << ", " << worldOut << ", " << gtOut << "\n";
}
}  // namespace

int main(int argc, char** argv)
{
    return semloc::apps::runMain(cmd, argc, argv, "semloc-import-landmarks", run);
}
