/* semloc — Simulator::writeCsvDataset: a simulated dataset in semloc-import's CSV format. */
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/system/datetime.h>
#include <semloc/io/Interrupt.h>
#include <semloc/io/StagedDirectory.h>
#include <semloc/observation/CObservationSemantic.h>
#include <semloc/simulator/Simulator.h>

#include <sstream>

#include "io/Text.h"
#include "io/TextFiles.h"

namespace semloc
{
namespace
{
using detail::fixedText;

/** The detector's options as semloc-import's command line, for the detections' header. */
std::string importOptions(const SemanticDetectorModel::TOptions& d)
{
    return "--max-range-m " + detail::shortestText(d.max_range_m) + " --fov-deg " +
           detail::shortestText(d.fov_deg) + " --sensor-pose " +
           detail::shortestText(d.sensor_x_m) + "," + detail::shortestText(d.sensor_y_m) + "," +
           detail::shortestText(d.sensor_yaw_deg);
}
}  // namespace

void Simulator::writeCsvDataset(const SimulationResult& result, const std::string& dir,
                                const std::vector<std::string>& inputs) const
{
    StagedDirectory out(dir, inputs);
    std::ostringstream odo, det, gt, lm;
    odo << "# dead-reckoned pose: the odometry increments composed from (0, 0, 0)\nt,x,y,phi\n";
    det << "# simulated detector; import with semloc-import " << importOptions(m_options.detector)
        << "\n# a row with only t: a scan that recognized nothing\n"
        << "t,label,range_m,bearing_rad,id,confidence\n";
    mrpt::poses::CPose2D dead(0, 0, 0);
    for (size_t i = 0; i + 1 < result.rawlog.size(); i += 2)
    {
        const auto acts = result.rawlog.getAsAction(i);
        const auto move = acts->getBestMovementEstimation();
        dead = dead + move->poseChange->getMeanVal();
        const double t = mrpt::Clock::toDouble(move->timestamp);
        odo << fixedText(t) << ',' << fixedText(dead.x()) << ',' << fixedText(dead.y()) << ','
            << fixedText(dead.phi()) << '\n';
        const auto sem =
            result.rawlog.getAsObservations(i + 1)->getObservationByClass<CObservationSemantic>();
        if (!sem)
        {
            continue;
        }
        const std::string ts = fixedText(mrpt::Clock::toDouble(sem->timestamp));
        for (const auto& x : sem->detections)
        {
            det << ts << ',' << x.label << ',' << fixedText(x.range_m) << ','
                << fixedText(x.bearing_rad) << ','
                << (x.object_id >= 0 ? std::to_string(x.object_id) : "") << ','
                << fixedText(x.confidence) << '\n';
        }
        if (sem->detections.empty())
        {
            det << ts << ",,,,,\n";
        }
        if (interruptRequested())
        {
            throw Interrupted();
        }
    }
    gt << "t,x,y,phi\n";
    for (const auto& r : result.groundTruth)
    {
        gt << fixedText(r.t) << ',' << fixedText(r.x) << ',' << fixedText(r.y) << ','
           << fixedText(r.phi) << '\n';
    }
    lm << "# the world's objects, each at its centre\nid,label,x,y\n";
    for (const auto& ob : m_world.objects)
    {
        lm << ob.id << ',' << ob.label << ',' << fixedText(ob.center.x) << ','
           << fixedText(ob.center.y) << '\n';
    }
    detail::writeFile(out.path("odometry.csv"), odo.str());
    detail::writeFile(out.path("detections.csv"), det.str());
    detail::writeFile(out.path("ground_truth.csv"), gt.str());
    detail::writeFile(out.path("landmarks.csv"), lm.str());
    if (interruptRequested())
    {
        throw Interrupted();
    }
    out.commit();
}

}  // namespace semloc
