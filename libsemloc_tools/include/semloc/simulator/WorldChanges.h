/* semloc — a world changed since its map was made: objects moved, gone, new. */
#pragma once

#include <semloc/world/World.h>

#include <cstdint>

namespace semloc
{
/** How the world a vehicle meets differs from the map it carries (a survey some time ago):
 *  every object moved by a Gaussian offset, a share of them gone, new ones. The map the
 *  filter gets stays the original; the simulator runs in the changed world
 *  (Simulator(world, options)). */
struct TWorldChanges
{
    /** Standard deviation of each object's offset along x and along y [m]. */
    double shift_sigma_m = 0;
    /** Share of the objects gone from the world, in [0, 1] (rounded to a count). */
    double removed_share = 0;
    /** New objects: each a copy of a random object of the world (label, shape) centred
     *  at a random free position, with a new id. */
    int added = 0;
    /** Seed of the changes (one changed world per seed). */
    uint32_t seed = 1;

    /** True if anything changes. */
    bool any() const { return shift_sigma_m > 0 || removed_share > 0 || added > 0; }
};

/** `world` with `changes` applied: the objects (and their outlines) moved, then the gone
 *  ones left out, then the new ones added (ids above every id of the world); bounds and
 *  trajectory as they were. Deterministic in changes.seed. */
World changeWorld(const World& world, const TWorldChanges& changes);
}  // namespace semloc
