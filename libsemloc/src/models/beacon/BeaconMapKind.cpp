/* semloc — MRPT's range-only beacon map as a kind of [MetricMap] (beaconMap_count): filled
 * with the world's beacons. */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/maps/CBeaconMap.h>
#include <mrpt/obs/CObservationBeaconRanges.h>
#include <mrpt/poses/CPoint3D.h>

#include <cmath>
#include <typeinfo>

#include "io/ExactConfigWrite.h"
#include "models/BuiltinKinds.h"
#include "models/beacon/BeaconRangeLikelihood.h"

namespace semloc::detail
{
namespace
{
/** Standard deviation of a beacon's position in its CBeacon [m]: the beacons are where the
 *  world says, to a millimetre (MRPT adds the position's variance along the line of sight
 *  to rangeStd^2). */
constexpr double kBeaconPositionStd_m = 1e-3;

/** The world's beacons as Gaussian CBeacons, in file order. */
void loadBeacons(mrpt::maps::CBeaconMap& map, const std::vector<WorldBeacon>& beacons)
{
    map.clear();
    for (const auto& b : beacons)
    {
        mrpt::maps::CBeacon c;
        c.m_ID = b.id;
        c.m_typePDF = mrpt::maps::CBeacon::pdfGauss;
        c.m_locationGauss.mean = mrpt::poses::CPoint3D(b.x, b.y, b.z);
        c.m_locationGauss.cov.setZero();
        for (int i = 0; i < 3; i++)
        {
            c.m_locationGauss.cov(i, i) = kBeaconPositionStd_m * kBeaconPositionStd_m;
        }
        map.push_back(c);
    }
}

/** A beacon map gets the world's beacons (World::beacons): a Gaussian CBeacon each (m_ID the
 *  beacon's id, mean (x, y, z), covariance kBeaconPositionStd_m^2 I), after the other maps
 *  (a semantic or structure map's own world_file may give the world). Refused: a rangeStd
 *  that is not > 0, a world without beacons (naming it), a map left empty without a world
 *  (naming the map file). */
class BeaconMapKind final : public SensorModelKind
{
public:
    std::string name() const override { return "beaconMap"; }
    const mrpt::rtti::TRuntimeClassId* mapClass() const override
    {
        return CLASS_ID(mrpt::maps::CBeaconMap);
    }
    int fillPass() const override { return 1; }

    /** The exact class only (a subclass may keep state of its own). */
    std::unique_ptr<BatchLikelihood> batchOf(const mrpt::maps::CMetricMap& map) const override
    {
        if (typeid(map) != typeid(mrpt::maps::CBeaconMap))
        {
            return nullptr;
        }
        return std::make_unique<BeaconMapBatch>(static_cast<const mrpt::maps::CBeaconMap&>(map));
    }

    void fill(TFill& f) const override
    {
        auto& beacons = dynamic_cast<mrpt::maps::CBeaconMap&>(f.map);
        const double rangeStd = beacons.likelihoodOptions.rangeStd;
        if (!(rangeStd > 0))
        {
            THROW_EXCEPTION(mrpt::format(
                "ini [%s_likelihoodOpts] rangeStd: %g is not > 0 (the beacon ranges' standard "
                "deviation [m])",
                f.prefix.c_str(), rangeStd));
        }
        if (f.world && f.world->beacons.empty())
        {
            THROW_EXCEPTION(f.countKey + "the beacon map takes its beacons from the world file '" +
                            f.world->source +
                            "', which has none (add a `beacons:` list, docs/design.md, "
                            "\"World file\")");
        }
        if (f.world)
        {
            loadBeacons(beacons, f.world->beacons);
        }
        else if (beacons.size() == 0)
        {
            THROW_EXCEPTION(f.countKey +
                            "the beacon map is empty: its beacons come from a world "
                            "YAML with a `beacons:` list as map_file" +
                            (f.mapFile.empty() ? std::string(" (map_file is empty)")
                                               : " (map_file is '" + f.mapFile + "')"));
        }
    }

    void writeOptions(const mrpt::maps::TMetricMapInitializer& definition,
                      mrpt::config::CConfigFileBase& out, const std::string& prefix,
                      const std::string&) const override
    {
        const auto& d = dynamic_cast<const mrpt::maps::CBeaconMap::TMapDefinition&>(definition);
        writeExact(out, prefix + "_likelihoodOpts", "rangeStd", d.likelihoodOpts.rangeStd, "");
    }

    /** A range (or its sensor's place on the vehicle) that is not finite, whatever the maps:
     *  MRPT's CBeaconMap throws on the non-finite likelihood it gives. */
    std::string invalidObservation(const mrpt::obs::CObservation& obs,
                                   const mrpt::maps::CMetricMap&) const override
    {
        const auto* lbl = dynamic_cast<const mrpt::obs::CObservationBeaconRanges*>(&obs);
        if (!lbl)
        {
            return {};
        }
        for (const auto& m : lbl->sensedData)
        {
            const auto& at = m.sensorLocationOnRobot;
            if (!std::isfinite(m.sensedDistance) || !std::isfinite(at.x()) ||
                !std::isfinite(at.y()) || !std::isfinite(at.z()))
            {
                return mrpt::format(
                    "its range %g to beacon %d (from (%g, %g, %g) on the "
                    "vehicle) is not finite",
                    static_cast<double>(m.sensedDistance), static_cast<int>(m.beaconID), at.x(),
                    at.y(), at.z());
            }
        }
        return {};
    }
};
}  // namespace

std::shared_ptr<const SensorModelKind> beaconMapKind()
{
    return std::make_shared<BeaconMapKind>();
}
}  // namespace semloc::detail
