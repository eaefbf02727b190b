/* semloc — Simulator::writeCsvDataset: a simulated dataset in semloc-import's CSV format. */
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/system/datetime.h>
#include <semloc/io/Interrupt.h>
#include <semloc/io/StagedDirectory.h>
#include <semloc/observation/CObservationDepth.h>
#include <semloc/observation/CObservationSemantic.h>
#include <semloc/simulator/Simulator.h>

#include <cmath>
#include <sstream>
#include <utility>

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
/** Whether any of the AUV's sensors is on: the dataset is then written in the AUV form. */
bool anyAuvSensor(const TAuvSensorOptions& a)
{
    return a.depth.enabled || a.compass.enabled || a.usbl.enabled || a.dvl.enabled ||
           a.sidescan.enabled || a.fls.enabled || a.camera.enabled;
}

/** The AUV form's semloc-import command line (coverage and mount of each detector). */
std::string auvImportOptions(const TAuvSensorOptions& a, const SemanticDetectorModel::TOptions& d,
                             bool semantic)
{
    std::string o = semantic ? " " + importOptions(d) : "";
    for (const auto* s : {&a.sidescan, &a.fls, &a.camera})
    {
        if (!s->enabled)
        {
            continue;
        }
        const bool side = s->kind == TObjectDetectorSimOptions::Kind::SideScan;
        const auto option = [&](const char* name, const std::string& value) {
            o.append(" --")
                .append(name)
                .append(" ")
                .append(s->sensor_label)
                .append("=")
                .append(value);
        };
        option("max-range-m", detail::shortestText(s->max_range_m));
        option("fov-deg", detail::shortestText(side ? 360 : s->fov_deg));
        std::string pose = detail::shortestText(s->sensor_x_m);
        for (const double v : {s->sensor_y_m, s->sensor_yaw_deg, s->sensor_z_m})
        {
            pose += "," + detail::shortestText(v);
        }
        option("sensor-pose", pose);
    }
    return o;
}

/** The AUV form's files: odometry (`t,vx,vy,w` from a DVL, else `t,x,y,phi`), detections of
 *  every detector with a `sensor` column (the side-scan's side in `side`, a camera's range
 *  empty), and the depth, heading and fixes of the sensors that are on. */
struct AuvCsv
{
    std::ostringstream odo, det, depth, heading, fixes;
    const TAuvSensorOptions& a;
    std::string lastOdometryRow;  // t of the last row, its speeds written with the next step
    bool dvl;

    AuvCsv(const TAuvSensorOptions& auv, const std::string& options) : a(auv), dvl(auv.dvl.enabled)
    {
        odo << (dvl ? "# a DVL's body-frame velocities over the ground and the yaw rate, each "
                      "held to the next row\nt,vx,vy,w\n"
                    : "# dead-reckoned pose: the odometry increments composed from (0, 0, 0)\n"
                      "t,x,y,phi\n");
        det << "# simulated detectors; import with semloc-import" << options
            << "\n# a row with only t and sensor: a scan of that sensor that recognized nothing\n"
            << "t,sensor,label,range_m,bearing_rad,side,id,confidence\n";
        depth << "t,depth_m,altitude_m\n";
        heading << "t,heading_rad\n";
        fixes << "t,x,y,z,sigma_m\n";
    }

    /** The odometry row of a step at `t` whose increment (from the previous step, `dt`
     *  before) is `inc`, the dead-reckoned pose then `dead`. */
    void odometry(double t, double dt, const mrpt::poses::CPose2D& inc,
                  const mrpt::poses::CPose2D& dead)
    {
        if (!dvl)
        {
            odo << fixedText(t) << ',' << fixedText(dead.x()) << ',' << fixedText(dead.y()) << ','
                << fixedText(dead.phi()) << '\n';
            return;
        }
        // The velocities whose exact arc over dt (semloc-import's integration) is `inc`.
        double vx = 0, vy = 0, w = 0;
        if (!lastOdometryRow.empty() && dt > 0)
        {
            const double d = inc.phi();
            w = d / dt;
            if (std::abs(d) < 1e-9)
            {
                vx = inc.x() / dt;
                vy = inc.y() / dt;
            }
            else
            {
                // inc = (dt / d) [[s, c - 1], [1 - c, s]] (vx, vy): a scaled rotation.
                const double sn = std::sin(d), cm = 1 - std::cos(d), k = d / dt;
                const double n2 = sn * sn + cm * cm;
                vx = k * (sn * inc.x() + cm * inc.y()) / n2;
                vy = k * (-cm * inc.x() + sn * inc.y()) / n2;
            }
            odo << lastOdometryRow << ',' << fixedText(vx) << ',' << fixedText(vy) << ','
                << fixedText(w) << '\n';
        }
        lastOdometryRow = fixedText(t);
    }

    /** The last odometry row (its speeds 0: nothing follows). */
    void finish()
    {
        if (dvl && !lastOdometryRow.empty())
        {
            odo << lastOdometryRow << ",0,0,0\n";
        }
    }

    void frame(const mrpt::obs::CSensoryFrame& f)
    {
        for (const auto& o : f)
        {
            const std::string ts = fixedText(mrpt::Clock::toDouble(o->timestamp));
            if (const auto* s = dynamic_cast<const CObservationSemantic*>(o.get()))
            {
                scan(*s, ts);
            }
            else if (const auto* d = dynamic_cast<const CObservationDepth*>(o.get()))
            {
                depth << ts << ',' << fixedText(d->depth_m) << ','
                      << (std::isnan(d->altitude_m) ? "" : fixedText(d->altitude_m)) << '\n';
            }
            else if (const auto* c = dynamic_cast<const mrpt::obs::CObservationIMU*>(o.get()))
            {
                heading << ts << ',' << fixedText(c->get(mrpt::obs::IMU_YAW)) << '\n';
            }
            else if (const auto* p = dynamic_cast<const mrpt::obs::CObservationRobotPose*>(o.get()))
            {
                fixes << ts << ',' << fixedText(p->pose.mean.x()) << ','
                      << fixedText(p->pose.mean.y()) << ',' << fixedText(p->pose.mean.z()) << ','
                      << fixedText(std::sqrt(p->pose.cov(0, 0))) << '\n';
            }
        }
    }

    void scan(const CObservationSemantic& s, const std::string& ts)
    {
        const bool side = a.sidescan.enabled && s.sensorLabel == a.sidescan.sensor_label;
        for (const auto& x : s.detections)
        {
            det << ts << ',' << s.sensorLabel << ',' << x.label << ','
                << (std::isnan(x.range_m) ? "" : fixedText(x.range_m)) << ','
                << (side ? "" : fixedText(x.bearing_rad)) << ','
                << (side ? (x.bearing_rad > 0 ? "port" : "starboard") : "") << ','
                << (x.object_id >= 0 ? std::to_string(x.object_id) : "") << ','
                << fixedText(x.confidence) << '\n';
        }
        if (s.detections.empty())
        {
            det << ts << ',' << s.sensorLabel << ",,,,,,\n";
        }
    }
};

/** The world's objects as semloc-import's landmarks (`z` in the AUV form). */
std::string landmarksText(const World& world, bool withZ)
{
    std::ostringstream lm;
    lm << "# the world's objects, each at its centre\nid,label,x,y" << (withZ ? ",z" : "") << "\n";
    for (const auto& ob : world.objects)
    {
        lm << ob.id << ',' << ob.label << ',' << fixedText(ob.center.x) << ','
           << fixedText(ob.center.y);
        if (withZ)
        {
            lm << ',' << fixedText(ob.z);
        }
        lm << '\n';
    }
    return lm.str();
}

std::string groundTruthText(const SimulationResult& result)
{
    std::ostringstream gt;
    gt << "t,x,y,phi\n";
    for (const auto& r : result.groundTruth)
    {
        gt << fixedText(r.t) << ',' << fixedText(r.x) << ',' << fixedText(r.y) << ','
           << fixedText(r.phi) << '\n';
    }
    return gt.str();
}
}  // namespace

void Simulator::writeAuvCsvDataset(const SimulationResult& result, StagedDirectory& out) const
{
    const auto& a = m_options.auv;
    AuvCsv csv(a, auvImportOptions(a, m_options.detector, m_options.detector.enabled));
    mrpt::poses::CPose2D dead(0, 0, 0);
    double previous = 0;
    for (size_t i = 0; i + 1 < result.rawlog.size(); i += 2)
    {
        const auto move = result.rawlog.getAsAction(i)->getBestMovementEstimation();
        const mrpt::poses::CPose2D inc = move->poseChange->getMeanVal();
        dead = dead + inc;
        const double t = mrpt::Clock::toDouble(move->timestamp);
        csv.odometry(t, t - previous, inc, dead);
        previous = t;
        csv.frame(*result.rawlog.getAsObservations(i + 1));
        if (interruptRequested())
        {
            throw Interrupted();
        }
    }
    csv.finish();
    detail::writeFile(out.path("odometry.csv"), csv.odo.str());
    detail::writeFile(out.path("detections.csv"), csv.det.str());
    detail::writeFile(out.path("ground_truth.csv"), groundTruthText(result));
    detail::writeFile(out.path("landmarks.csv"), landmarksText(m_world, true));
    const std::pair<bool, const std::ostringstream*> extra[] = {{a.depth.enabled, &csv.depth},
                                                                {a.compass.enabled, &csv.heading},
                                                                {a.usbl.enabled, &csv.fixes}};
    const char* names[] = {"depth.csv", "heading.csv", "fixes.csv"};
    for (size_t k = 0; k < 3; k++)
    {
        if (extra[k].first)
        {
            detail::writeFile(out.path(names[k]), extra[k].second->str());
        }
    }
}

void Simulator::writeCsvDataset(const SimulationResult& result, const std::string& dir,
                                const std::vector<std::string>& inputs) const
{
    StagedDirectory out(dir, inputs);
    if (anyAuvSensor(m_options.auv))
    {
        writeAuvCsvDataset(result, out);
        out.commit();
        return;
    }
    std::ostringstream odo, det;
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
    detail::writeFile(out.path("odometry.csv"), odo.str());
    detail::writeFile(out.path("detections.csv"), det.str());
    detail::writeFile(out.path("ground_truth.csv"), groundTruthText(result));
    detail::writeFile(out.path("landmarks.csv"), landmarksText(m_world, false));
    if (interruptRequested())
    {
        throw Interrupted();
    }
    out.commit();
}

}  // namespace semloc
