/* semloc — libFuzzer target: semloc-import's landmarks CSV (DatasetImport::readLandmarks:
 * id,label,x,y, optional sigma_x_m,sigma_y_m) and the world made of them
 * (DatasetImport::makeWorld) (docs/testing.md, "Fuzzing"). Any input must either be read or
 * throw naming the file; accepted landmarks are at least one, point objects with unique
 * positive ids, valid labels, finite centres and a finite sigma_m >= 0 (standard deviations
 * both or neither). Their world must be made or refused with an exception; a world made
 * writes YAML that loads again to the same text. */
#include <semloc/dataset/DatasetImport.h>
#include <semloc/observation/Labels.h>
#include <semloc/world/World.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <istream>
#include <set>
#include <string>

#include "FuzzImport.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    using semloc::fuzz::require;
    const auto landmarks =
        semloc::fuzz::readCsv(data, size,
                              [](std::istream& in, const std::string& name)
                              { return semloc::DatasetImport::readLandmarks(in, name); });
    if (!landmarks)
    {
        return 0;
    }
    require(!landmarks->empty(), "no landmark");
    std::set<int> ids;
    for (const auto& l : *landmarks)
    {
        const auto& o = l.object;
        require(o.id > 0 && ids.insert(o.id).second, "an id not positive or not unique");
        require(semloc::labelProblem(o.label).empty(), "an invalid label");
        require(o.shape == semloc::ShapeType::Point, "not a point object");
        require(std::isfinite(o.center.x) && std::isfinite(o.center.y), "a centre not finite");
        require(std::isnan(l.sigma_x_m) == std::isnan(l.sigma_y_m),
                "one standard deviation without the other");
        require(std::isfinite(o.sigma_m) && o.sigma_m >= 0, "sigma_m not finite and >= 0");
    }
    semloc::World world;
    try
    {
        world = semloc::DatasetImport::makeWorld(*landmarks, {}, 10.0, "fuzz");
    }
    catch (const std::exception&)
    {
        return 0;  // landmarks the world loader refuses (e.g. beyond its coordinate bound)
    }
    const std::string yaml = world.toYamlText();
    require(semloc::World::FromText(yaml, "fuzz-roundtrip.yaml").toYamlText() == yaml,
            "the world's YAML does not load again to the same text");
    return 0;
}
