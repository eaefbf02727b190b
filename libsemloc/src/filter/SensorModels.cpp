/* semloc — the sensor models among a filter's maps. */
#include "filter/SensorModels.h"

#include <mrpt/maps/CMultiMetricMap.h>

namespace semloc::detail
{
std::vector<const BatchLikelihood*> sensorModels(const mrpt::maps::CMetricMap& map)
{
    std::vector<const BatchLikelihood*> out;
    if (const auto* multi = dynamic_cast<const mrpt::maps::CMultiMetricMap*>(&map))
    {
        for (const auto& m : multi->maps)
        {
            if (const auto* model = dynamic_cast<const BatchLikelihood*>(m.get()))
            {
                out.push_back(model);
            }
        }
    }
    else if (const auto* model = dynamic_cast<const BatchLikelihood*>(&map))
    {
        out.push_back(model);
    }
    return out;
}

std::unique_ptr<BatchLikelihood::PoseProposal> poseProposal(const mrpt::obs::CSensoryFrame& sf,
                                                            const mrpt::maps::CMetricMap* map)
{
    if (!map)
    {
        return nullptr;
    }
    for (const auto* model : sensorModels(*map))
    {
        if (auto p = model->proposal(sf))
        {
            return p;
        }
    }
    return nullptr;
}
}  // namespace semloc::detail
