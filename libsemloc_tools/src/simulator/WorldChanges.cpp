/* semloc — changeWorld: the world a vehicle meets, changed since its map was made. */
#include <mrpt/random/RandomGenerators.h>
#include <semloc/simulator/WorldChanges.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "simulator/SimRandom.h"

namespace semloc
{
namespace
{
/** `o` translated by (dx, dy): its centre and its outline's points. */
void translate(WorldObject& o, double dx, double dy)
{
    o.center.x += dx;
    o.center.y += dy;
    for (auto& p : o.points)
    {
        p.x += dx;
        p.y += dy;
    }
}
}  // namespace

World changeWorld(const World& world, const TWorldChanges& c)
{
    mrpt::random::CRandomGenerator rng(c.seed);
    World out = world;
    for (auto& o : out.objects)
    {
        const double dx = c.shift_sigma_m * rng.drawGaussian1D_normalized();
        const double dy = c.shift_sigma_m * rng.drawGaussian1D_normalized();
        translate(o, dx, dy);
    }
    // The gone ones: a random subset of round(share * n), the others kept in their order.
    const size_t n = out.objects.size();
    const auto gone = static_cast<size_t>(std::lround(c.removed_share * static_cast<double>(n)));
    std::vector<size_t> order(n);
    std::iota(order.begin(), order.end(), size_t{0});
    for (size_t i = 0; i < gone; i++)  // the first `gone` of a partial Fisher-Yates shuffle
    {
        std::swap(order[i], order[i + detail::uniformIndex(rng, n - i)]);
    }
    std::vector<bool> keep(n, true);
    for (size_t i = 0; i < gone; i++)
    {
        keep[order[i]] = false;
    }
    std::vector<WorldObject> kept;
    for (size_t i = 0; i < n; i++)
    {
        if (keep[i])
        {
            kept.push_back(out.objects[i]);
        }
    }
    int nextId = 1;
    for (const auto& o : world.objects)
    {
        nextId = std::max(nextId, o.id + 1);
    }
    for (int k = 0; k < c.added && !world.objects.empty(); k++)
    {
        WorldObject o = world.objects[detail::uniformIndex(rng, world.objects.size())];
        const auto p = world.sampleFreePose(rng);
        translate(o, p.x - o.center.x, p.y - o.center.y);
        o.id = nextId++;
        kept.push_back(std::move(o));
    }
    out.objects = std::move(kept);
    return out;
}
}  // namespace semloc
