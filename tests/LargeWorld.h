/* semloc tests — a kilometre-scale world: a few hundred objects over a large square, most of
 * them scattered far apart, some around a short lawnmower survey in the middle. */
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>

namespace semloc::test
{
/** Side of the large test world [m]: an AUV survey area. */
constexpr double kLargeWorldSide_m = 20000;

/** A survey leg's clearance from every object centre [m] (objects are at most 1.5 m wide). */
constexpr double kLargeWorldClearance_m = 4;

/** World YAML of a side_m x side_m square: `near` objects within ~50 m of a three-leg
 *  lawnmower survey (200 m long legs 20 m apart, centred in the square, speed 1 m/s), `far`
 *  objects uniform over the rest; shapes box, cylinder, triangle and point in turn, six
 *  labels. Deterministic. */
inline std::string largeWorldYaml(double side_m = kLargeWorldSide_m, int near = 60, int far = 240)
{
    std::mt19937_64 gen(7);
    auto uniform = [&gen](double lo, double hi)
    { return lo + (hi - lo) * static_cast<double>(gen() >> 11) * 0x1.0p-53; };
    const double cx = side_m / 2, cy = side_m / 2;
    const double legY[3] = {cy, cy + 20, cy + 40};
    auto clear = [&](double x, double y)
    {
        // Off the legs (y), and off the joins at x = cx + 100 (legs 0-1), cx - 100 (1-2).
        for (double ly : legY)
        {
            if (std::abs(y - ly) <= kLargeWorldClearance_m && std::abs(x - cx) <= 104)
            {
                return false;
            }
        }
        const bool joinA = std::abs(x - (cx + 100)) <= kLargeWorldClearance_m && y > legY[0] - 4 &&
                           y < legY[1] + 4;
        const bool joinB = std::abs(x - (cx - 100)) <= kLargeWorldClearance_m && y > legY[1] - 4 &&
                           y < legY[2] + 4;
        return !joinA && !joinB;
    };
    const char* labels[] = {"wellhead", "pillar", "anchor", "wreck", "manifold", "marker"};
    char buf[512];
    std::snprintf(buf, sizeof(buf),
                  "name: large\nbounds: {x_min: 0, x_max: %.17g, y_min: 0, y_max: %.17g}\n"
                  "objects:\n",
                  side_m, side_m);
    std::string out = buf;
    for (int n = 0; n < near + far; n++)
    {
        double x = 0, y = 0;
        do
        {
            if (n < near)
            {
                x = uniform(cx - 110, cx + 110);
                y = uniform(cy - 15, cy + 55);
            }
            else
            {
                x = uniform(50, side_m - 50);
                y = uniform(50, side_m - 50);
            }
        } while (!clear(x, y) || (n >= near && std::abs(x - cx) < 300 && std::abs(y - cy) < 300));
        const char* label = labels[n % 6];
        const int id = n + 1;
        switch (n % 4)
        {
            case 0:
                std::snprintf(buf, sizeof(buf),
                              "  - {id: %d, label: %s, shape: box, center: [%.3f, %.3f], size: "
                              "[1.5, 1.0], yaw_deg: %d}\n",
                              id, label, x, y, (n * 37) % 180);
                break;
            case 1:
                std::snprintf(buf, sizeof(buf),
                              "  - {id: %d, label: %s, shape: cylinder, center: [%.3f, %.3f], "
                              "radius: 0.5}\n",
                              id, label, x, y);
                break;
            case 2:
                std::snprintf(buf, sizeof(buf),
                              "  - {id: %d, label: %s, shape: polygon, points: [[%.3f, %.3f], "
                              "[%.3f, %.3f], [%.3f, %.3f]]}\n",
                              id, label, x - 1, y - 1, x + 1, y - 1, x, y + 1);
                break;
            default:
                std::snprintf(buf, sizeof(buf),
                              "  - {id: %d, label: %s, shape: point, center: [%.3f, %.3f]}\n", id,
                              label, x, y);
                break;
        }
        out += buf;
    }
    std::snprintf(buf, sizeof(buf),
                  "trajectory:\n  speed_mps: 1.0\n  waypoints: [[%.17g, %.17g], [%.17g, %.17g], "
                  "[%.17g, %.17g], [%.17g, %.17g], [%.17g, %.17g], [%.17g, %.17g]]\n",
                  cx - 100, legY[0], cx + 100, legY[0], cx + 100, legY[1], cx - 100, legY[1],
                  cx - 100, legY[2], cx + 100, legY[2]);
    return out + buf;
}

}  // namespace semloc::test
