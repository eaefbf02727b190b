/* semloc — semantic-aided particle filter localization for AUVs.
 * World description: the one source of every map (docs/design.md, "World file"). */
#pragma once

#include <mrpt/math/TPoint2D.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/math/TSegment2D.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace mrpt::containers
{
class yaml;
}
namespace mrpt::maps
{
class COccupancyGridMap2D;
}
namespace mrpt::random
{
class CRandomGenerator;
}

namespace semloc
{
/** Shape of a world object, as written in the world YAML (`shape:`). */
enum class ShapeType
{
    Box,       //!< Rotated rectangle: `center`, `size: [sx, sy]`, optional `yaw_deg`.
    Cylinder,  //!< Vertical cylinder: `center`, `radius`.
    Polygon,   //!< Simple polygon: `points: [[x, y], ...]`, at least 3 vertices.
    Point      //!< Seen by the detector, invisible to the sonar: `center`.
};

/** Name of a shape as written in the world YAML ("box", "cylinder", ...). */
const char* shapeName(ShapeType s);

/** Default chord tolerance of a cylinder's polygon [m] (see cylinderSides()). */
constexpr double kDefaultCylinderTolerance_m = 0.01;

/** Bound of every coordinate and length in a world file [m]: bounds, centres, points, sizes,
 *  radii, extents and z lie in [-kMaxWorldCoordinate_m, kMaxWorldCoordinate_m] (10 000 km,
 *  far beyond any survey, and small enough that squares and sums of coordinates stay
 *  finite and precise to well under a millimetre). */
constexpr double kMaxWorldCoordinate_m = 1e7;

/** Most cells World::makeOccupancyGrid() builds (2^25: e.g. 5.8 x 5.8 km at 1 m): an MRPT
 *  grid takes about 9 bytes per cell with its likelihood cache, and its free cells more
 *  again in a FreeSpaceSampler. */
constexpr size_t kMaxOccupancyGridCells = size_t{1} << 25;

/** One labelled object of the world. */
struct WorldObject
{
    /** Unique positive identifier. */
    int id = 0;
    /** Object class, free string (e.g. "wellhead"). */
    std::string label;
    /** Shape of the outline seen by the sonar (none for Point). */
    ShapeType shape = ShapeType::Point;
    /** Semantic position: the centre (the vertex centroid for a polygon) [m]. */
    mrpt::math::TPoint2D center{0, 0};
    /** Depth/height of the object's reference point [m] (optional key `z`). */
    double z = 0;
    /** Box: full side length along its own x [m]. */
    double size_x = 0;
    /** Box: full side length along its own y [m]. */
    double size_y = 0;
    /** Box: rotation [rad] (key `yaw_deg` in degrees). */
    double yaw = 0;
    /** Cylinder: radius [m]. */
    double radius = 0;
    /** Polygon: vertices as given; Box: its 4 corners (counter-clockwise). */
    std::vector<mrpt::math::TPoint2D> points;
    /** Radius of the smallest centre-based disc containing the outline [m]
     *  (key `extent_m` for points; computed for every other shape). */
    double extent_m = 0;
    /** @name How sure a map is of the object (optional keys; docs/design.md, "World file")
     *  @{ */
    /** Standard deviation of the object's position, isotropic, in x and in y [m] (`sigma_m`;
     *  0: exactly where `center` says). */
    double sigma_m = 0;
    /** Probability that the object is still there (`p_exist`, in (0, 1]). */
    double p_exist = 1;
    /** Its class distribution (`classes: {label: probability, ...}`, summing to 1, `label`
     *  among them), sorted by label; empty: certainly of class `label`. */
    std::vector<std::pair<std::string, double>> classes;
    /** @} */
};

/** What is wrong with `classes` as the class distribution of an object labelled `label`
 *  (labels valid, distinct and sorted, each probability in (0, 1], summing to 1 within 1e-6,
 *  `label` among them), or "" if nothing. */
std::string classesProblem(const std::vector<std::pair<std::string, double>>& classes,
                           const std::string& label);

/** Axis-aligned area particles may occupy [m]. */
struct WorldBounds
{
    /** Lower x bound [m]. */
    double x_min = 0;
    /** Upper x bound [m]. */
    double x_max = 0;
    /** Lower y bound [m]. */
    double y_min = 0;
    /** Upper y bound [m]. */
    double y_max = 0;
    /** True if (x, y) is inside (borders included). */
    bool contains(double x, double y) const
    {
        return x >= x_min && x <= x_max && y >= y_min && y <= y_max;
    }
};

/** A range-only acoustic beacon (an LBL transponder): what MRPT's CBeaconMap holds and
 *  semloc-simulate's [BeaconRanging] sensor measures its range to (optional list
 *  `beacons:` of the world file). */
struct WorldBeacon
{
    /** Identifier the ranges carry: a non-negative integer, unique among the beacons. */
    int id = 0;
    /** Position [m] (key `x`); may lie outside the bounds. */
    double x = 0;
    /** Position [m] (key `y`); may lie outside the bounds. */
    double y = 0;
    /** Height above the vehicle's plane [m] (optional key `z`; negative: below it). Ranges
     *  are slant ranges in 3D. */
    double z = 0;
};

/** Optional path for the simulator: waypoints followed at constant speed. */
struct WorldTrajectory
{
    /** Cruise speed [m/s]. */
    double speed_mps = 0.5;
    /** Waypoints [m], at least two. */
    std::vector<mrpt::math::TPoint2D> waypoints;
};

/** The objects of a world made one at a time, in file order, for a map too large to hold as
 *  WorldObjects (a million point landmarks held in a compact form): `count` of them,
 *  `at(i)` the i-th. */
struct WorldObjectList
{
    size_t count = 0;
    std::function<WorldObject(size_t)> at;
};

/** A world: bounds, labelled objects with outlines, optional acoustic beacons and an
 *  optional trajectory.
 *
 * Loaded from the YAML schema of docs/design.md and validated strictly: every error
 * names the file, the object index (and id) and the key, and is thrown as an
 * MRPT exception (std::exception). */
class World
{
public:
    /** Name of the world (`name:`). */
    std::string name;
    /** Area particles may occupy. */
    WorldBounds bounds;
    /** Objects in file order. */
    std::vector<WorldObject> objects;
    /** Acoustic beacons in file order (none if the file lists none). */
    std::vector<WorldBeacon> beacons;
    /** Optional trajectory for the simulator. */
    std::optional<WorldTrajectory> trajectory;
    /** Where the world was read from (used in error messages). */
    std::string source;

    /** Reads and validates a world YAML file. Throws on any error. */
    static World FromFile(const std::string& path);
    /** Parses and validates world YAML text; `sourceName` is used in messages. */
    static World FromText(const std::string& yamlText, const std::string& sourceName);

    /** Writes this world in the YAML schema of docs/design.md (round-trips through FromFile:
     *  the text is read back as it is made, then written as it is made, never held whole;
     *  memory beyond the world about 40 bytes an object). Throws "not writing world file
     *  'PATH': semloc could not read it back: ..." (nothing written) or "cannot write world
     *  file 'PATH': ...". */
    void saveToFile(const std::string& path) const;
    /** saveToFile() of this world with the objects of `list` (this world's own must be
     *  empty): the same file as for the world holding them, without holding them. */
    void saveToFile(const std::string& path, const WorldObjectList& list) const;
    /** The world as YAML text, one object and one beacon per line in flow style. */
    std::string toYamlText() const;

    /** Index of the object with this id in `objects`, or -1. */
    int indexOfId(int id) const;

    /** @name Geometry: the outlines the sonar sees, free space, rasterization
     *  @{ */
    /** Outline polygon of one object (counter-clockwise for boxes and cylinders; as given
     *  for polygons; empty for points). A cylinder becomes the regular polygon of
     *  cylinderSides(radius, tolerance) vertices inscribed in its circle. */
    static std::vector<mrpt::math::TPoint2D> outlinePolygon(
        const WorldObject& o, double cylinderTolerance_m = kDefaultCylinderTolerance_m);

    /** Sides n of the regular polygon inscribed in a circle of radius r whose sagitta
     *  r (1 - cos(pi / n)), the largest gap between chord and arc, is <= `tolerance_m`:
     *  the smallest such n, at least 6. Throws if `tolerance_m` <= 0 or n > 65536. */
    static int cylinderSides(double radius_m, double tolerance_m);

    /** Every edge of every outline, objects in file order: 4 per box, one per polygon
     *  vertex, cylinderSides() per cylinder (so no point of a cylinder's circle is farther
     *  than `cylinderTolerance_m` [m] from the segments, and every segment lies inside the
     *  circle); none for points. */
    std::vector<mrpt::math::TSegment2D> outlineSegments(
        double cylinderTolerance_m = kDefaultCylinderTolerance_m) const;

    /** True if (x, y) is inside `bounds` and strictly outside every outline (box,
     *  polygon, the exact circle of a cylinder; a point on an outline is not free). */
    bool isFree(double x, double y) const;

    /** A pose uniform over the free space (isFree) with a heading uniform in [-pi, pi),
     *  by rejection sampling from `bounds`. Throws if none of 100000 draws is free (no
     *  free space, or less than about 1e-4 of the bounds' area). */
    mrpt::math::TPose2D sampleFreePose(mrpt::random::CRandomGenerator& rng) const;

    /** MRPT occupancy grid over `bounds` with cells of `resolution_m` [m]: a cell is
     *  occupied (value 0) if its centre is inside an object (isFree's shapes) or an
     *  outline segment (default cylinder tolerance) touches it, and free (value 1)
     *  elsewhere. Throws, naming the bounds and the resolution, if the grid would have more
     *  than kMaxOccupancyGridCells cells. Needs <mrpt/maps/COccupancyGridMap2D.h> at the
     *  call site. */
    mrpt::maps::COccupancyGridMap2D makeOccupancyGrid(double resolution_m) const;

    /** A raster of nx x ny square cells of side `cell_m` [m] from (x0, y0), row-major (cell
     *  (i, j) is [x0 + i cell_m, x0 + (i + 1) cell_m] x [y0 + j cell_m, ...]): 1 where no
     *  object's closed shape (isFree's shapes: a cylinder's exact circle) touches the closed
     *  cell widened by a small margin, 0 where one may. Exact in the sense that a 1 cell is
     *  free everywhere (bounds aside); a 0 cell may be partly or (by the margin) wholly
     *  free. Time about the cells the outlines cross plus one exact test per run of
     *  untouched cells in a row of each object's bounding box; memory the raster. */
    std::vector<uint8_t> freeRaster(double x0, double y0, double cell_m, size_t nx,
                                    size_t ny) const;

    /** Index in `objects` of the first object (box, cylinder, polygon) whose closed shape
     *  (isFree's) the closed segment [a, b] touches, or -1. */
    int firstObjectOnSegment(const mrpt::math::TPoint2D& a, const mrpt::math::TPoint2D& b) const;
    /** @} */
};

}  // namespace semloc
