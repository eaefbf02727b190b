/* semloc — MRPT's range-only beacon maps filled from the world's beacons. */
#include "models/beacon/BeaconMapFromWorld.h"

#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <mrpt/maps/CBeaconMap.h>
#include <mrpt/poses/CPoint3D.h>

#include <cmath>

namespace semloc::detail
{
namespace
{
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
}  // namespace

void fillBeaconMaps(LocalizationMap& lm,
                    const std::vector<std::pair<std::string, unsigned>>& aliases,
                    const std::string& mapFile, const std::string& section)
{
    for (size_t k = 0; k < lm.map->maps.size(); k++)
    {
        auto* beacons = dynamic_cast<mrpt::maps::CBeaconMap*>(lm.map->maps[k].get());
        if (!beacons)
        {
            continue;
        }
        const std::string countKey = "ini [" + section + "] " + aliases[k].first + "_count: ";
        const std::string prefix =
            section + "_" + aliases[k].first + mrpt::format("_%02u", aliases[k].second);
        const double rangeStd = beacons->likelihoodOptions.rangeStd;
        if (!(rangeStd > 0))
        {
            THROW_EXCEPTION(mrpt::format(
                "ini [%s_likelihoodOpts] rangeStd: %g is not > 0 (the beacon ranges' standard "
                "deviation [m])",
                prefix.c_str(), rangeStd));
        }
        if (lm.world && lm.world->beacons.empty())
        {
            THROW_EXCEPTION(countKey + "the beacon map takes its beacons from the world file '" +
                            lm.world->source +
                            "', which has none (add a `beacons:` list, docs/design.md, "
                            "\"World file\")");
        }
        if (lm.world)
        {
            loadBeacons(*beacons, lm.world->beacons);
        }
        else if (beacons->size() == 0)
        {
            THROW_EXCEPTION(countKey +
                            "the beacon map is empty: its beacons come from a world "
                            "YAML with a `beacons:` list as map_file" +
                            (mapFile.empty() ? std::string(" (map_file is empty)")
                                             : " (map_file is '" + mapFile + "')"));
        }
    }
}
}  // namespace semloc::detail
