/* semloc — libFuzzer target: semloc-import's odometry CSV (DatasetImport::readOdometry: t,x,y,phi
 * or t,v,w) (docs/testing.md, "Fuzzing"). Any input must either be read or throw naming the
 * file; an accepted track has two rows or more, finite times strictly increasing, finite poses
 * with wrapped headings, and interpolates to its own poses at its times and to a finite pose
 * between them. */
#include <semloc/dataset/DatasetImport.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <istream>
#include <string>

#include "FuzzImport.h"

namespace
{
bool finite(const mrpt::math::TPose2D& p)
{
    return std::isfinite(p.x) && std::isfinite(p.y) && semloc::fuzz::wrapped(p.phi);
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    using semloc::fuzz::require;
    const auto odo = semloc::fuzz::readCsv(data, size,
                                           [](std::istream& in, const std::string& name) {
                                               return semloc::DatasetImport::readOdometry(in, name);
                                           });
    if (!odo)
    {
        return 0;
    }
    require(odo->t.size() >= 2 && odo->pose.size() == odo->t.size(), "fewer than 2 rows");
    require(semloc::fuzz::increasing(odo->t), "times not finite and strictly increasing");
    for (size_t i = 0; i < odo->t.size(); i++)
    {
        const auto& p = odo->pose[i];
        require(finite(p), "a pose not finite or its heading not in [-pi, pi]");
        const auto q = odo->at(odo->t[i]);
        require(q.x == p.x && q.y == p.y, "the track at a row's time is not the row's pose");
        if (i > 0)
        {
            require(finite(odo->at(0.5 * (odo->t[i - 1] + odo->t[i]))),
                    "the pose between two rows is not finite");
        }
    }
    return 0;
}
