/* semloc — CSemanticMap: labelled objects, grid index and the semantic likelihoods. */
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>
#include <mrpt/opengl/CCylinder.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/opengl/CText.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/filesystem.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/maps/CSemanticMap.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <type_traits>
#include <unordered_map>
#include <unordered_set>

#include "filter/FastMath.h"
#include "io/BoundedRead.h"
#include "io/ExactConfigWrite.h"
#include "maps/LabelIndex.h"
#include "maps/VisibilityTable.h"
#include "world/Geometry2D.h"

using mrpt::math::TPose2D;
using semloc::detail::finitePose;
using semloc::detail::Vec2;

//  =========== Map definition (CMultiMetricMap factory) ============
MAP_DEFINITION_REGISTER("semanticMap,semloc::CSemanticMap", semloc::CSemanticMap)

namespace semloc
{
CSemanticMap::TMapDefinition::TMapDefinition() = default;

void CSemanticMap::TMapDefinition::loadFromConfigFile_map_specific(
    const mrpt::config::CConfigFileBase& source, const std::string& sectionNamePrefix)
{
    const std::string sc = sectionNamePrefix + "_creationOpts";
    // MRPT reads genericMapParams (enableObservationLikelihood, ...) from this section too.
    auto known = config::keysOf(genericMapParams);
    known.push_back("world_file");
    config::rejectUnknownKeys(source, sc, known);
    world_file = config::resolveNextToIni(source, source.read_string(sc, "world_file", world_file));
    likelihoodOpts.loadFromConfigFile(source, sectionNamePrefix + "_likelihoodOpts");
    insertionOpts.loadFromConfigFile(source, sectionNamePrefix + "_insertOpts");
}

void CSemanticMap::TMapDefinition::dumpToTextStream_map_specific(std::ostream& out) const
{
    out << "world_file = " << world_file << "\n";
    likelihoodOpts.dumpToTextStream(out);
    insertionOpts.dumpToTextStream(out);
}

mrpt::maps::CMetricMap* CSemanticMap::internal_CreateFromMapDefinition(
    const mrpt::maps::TMetricMapInitializer& _def)
{
    const auto& def = dynamic_cast<const CSemanticMap::TMapDefinition&>(_def);
    auto* m = new CSemanticMap();
    m->likelihoodOptions = def.likelihoodOpts;
    m->insertionOptions = def.insertionOpts;
    if (!def.world_file.empty())
    {
        try
        {
            m->loadFromWorldFile(def.world_file);
        }
        catch (...)
        {
            delete m;
            throw;
        }
    }
    return m;
}
}  // namespace semloc
//  =========== End of map definition ============

IMPLEMENTS_SERIALIZABLE(CSemanticMap, CMetricMap, semloc)

namespace semloc
{
// ------------------------------------------------------------------ options

namespace
{
const char* modelName(CSemanticMap::Model m)
{
    return m == CSemanticMap::Model::Paper ? "paper" : "probabilistic";
}

/** What the map accepts of an object, from addObject or from a file: a positive id, a label,
 *  finite coordinates. */
void checkObject(const CSemanticMap::TObject& o)
{
    ASSERT_GT_(o.id, 0);
    ASSERT_(!o.label.empty());
    ASSERT_(std::isfinite(o.x) && std::isfinite(o.y) && std::isfinite(o.z));
}
}  // namespace

void CSemanticMap::TLikelihoodOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                                          const std::string& s)
{
    config::rejectUnknownKeys(c, s, config::keysOf(*this));
    std::string m = modelName(model);
    config::readChoice(c, s, "model", m, {"paper", "probabilistic"});
    model = (m == "paper") ? Model::Paper : Model::Probabilistic;
    config::readDouble(c, s, "sigma_range_m", sigma_range_m, 1e-6, 1e6);
    config::readDouble(c, s, "sigma_bearing_deg", sigma_bearing_deg, 1e-6, 360);
    config::readDouble(c, s, "unmatched_penalty", unmatched_penalty, 1e-12, 0.999999);
    config::readDouble(c, s, "p_detect_near", p_detect_near, 1e-6, 0.999999);
    config::readDouble(c, s, "p_detect_far", p_detect_far, 1e-6, 0.999999);
    config::readDouble(c, s, "clutter_per_scan", clutter_per_scan, 1e-9, 1e6);
    config::readDouble(c, s, "p_confusion", p_confusion, 0, 0.999999);
    config::readDouble(c, s, "min_confidence", min_confidence, 0, 1);
    config::readDouble(c, s, "max_range_m", max_range_m, 0, 1e6);
    config::readDouble(c, s, "fov_deg", fov_deg, 0, 360);
    config::readDouble(c, s, "index_cell_m", index_cell_m, 0.01, 1e6);
}

void CSemanticMap::TLikelihoodOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                                        const std::string& s) const
{
    c.write(s, "model", std::string(modelName(model)), 24, 24, "paper | probabilistic");
    detail::writeExact(c, s, "sigma_range_m", sigma_range_m, "range noise sigma_rho [m]");
    detail::writeExact(c, s, "sigma_bearing_deg", sigma_bearing_deg,
                       "bearing noise sigma_theta [deg]");
    detail::writeExact(c, s, "unmatched_penalty", unmatched_penalty,
                       "paper: factor per object in one observation only, (0,1)");
    detail::writeExact(c, s, "p_detect_near", p_detect_near, "probabilistic: P_D at range 0");
    detail::writeExact(c, s, "p_detect_far", p_detect_far, "probabilistic: P_D at max range");
    detail::writeExact(c, s, "clutter_per_scan", clutter_per_scan,
                       "probabilistic: mean false positives per scan");
    detail::writeExact(c, s, "p_confusion", p_confusion, "probabilistic: P(wrong label)");
    detail::writeExact(c, s, "min_confidence", min_confidence, "ignore detections below this");
    detail::writeExact(c, s, "max_range_m", max_range_m,
                       ">0 overrides the observation's max range");
    detail::writeExact(c, s, "fov_deg", fov_deg, ">0 overrides the observation's field of view");
    detail::writeExact(c, s, "index_cell_m", index_cell_m, "cell of the object index [m]");
}

void CSemanticMap::TInsertionOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                                         const std::string& s)
{
    config::rejectUnknownKeys(c, s, config::keysOf(*this));
    config::readDouble(c, s, "merge_distance_m", merge_distance_m, 0, 1e6);
    landmark_label = c.read_string(s, "landmark_label", landmark_label);
    if (landmark_label.empty() || landmark_label.find_first_of(" \t") != std::string::npos)
    {
        THROW_EXCEPTION("ini [" + s + "] landmark_label: must be a non-empty word");
    }
}

void CSemanticMap::TInsertionOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                                       const std::string& s) const
{
    detail::writeExact(c, s, "merge_distance_m", merge_distance_m,
                       "merge a detection into a same-label object this close [m]");
    detail::writeText(c, s, "landmark_label", landmark_label,
                      "label of CObservationBearingRange landmarks");
}

// ------------------------------------------------------------------ index

namespace detail
{
/** The visibility candidate table of one (index build, range R, FOV): for a square cell of
 *  sensor positions and a heading bin, the objects that may be inside range and FOV from
 *  some position of the cell with some heading of the bin (a superset), in increasing
 *  sorted index, i.e. in the order the grid scan visits them. */
struct VisTable
{
    double x0 = 0, y0 = 0, inv = 0;  // origin and 1 / cell side of the table's grid
    double ox = 0, oy = 0;           // the origin less one cell (visRange)
    uint32_t nx = 0, ny = 0, bins = 1;
    /** bins / 4 (0 with one bin): bins are uniform in the "diamond angle" [0, 4). */
    double binScale = 0, lastBin = 0;
    /** cells * bins + 1: the candidates of list i are [start[i], start[i + 1]). */
    std::vector<uint32_t> start;
    std::vector<uint16_t> c16;  // the candidates (sorted indices) when there are < 65536
    std::vector<uint32_t> c32;  // objects, else here; either has one padding element
    size_t bytes = 0;
};

/** The tables of one index build, per (R, FOV); filled lazily under the mutex. A null
 *  table: one would be too large, the grid scan serves those calls. */
struct VisCache
{
    std::mutex mu;
    struct Entry
    {
        double R, fov;
        std::shared_ptr<const VisTable> table;
    };
    std::vector<Entry> entries;
};

namespace
{
std::atomic<bool> g_visEnabled{true};
std::atomic<size_t> g_visLastBytes{0};
}  // namespace

void setVisibilityTableEnabled(bool enabled)
{
    g_visEnabled.store(enabled);
}

bool visibilityTableEnabled()
{
    return g_visEnabled.load();
}

size_t lastVisibilityTableBytes()
{
    return g_visLastBytes.load();
}
}  // namespace detail

/** Objects sorted by grid cell (row-major), structure-of-arrays, so the cells of one
 *  grid row that overlap the detector's disc are one contiguous range. */
struct CSemanticMap::Index
{
    double x0 = 0, y0 = 0, cell = 10, inv_cell = 0.1;
    int nx = 0, ny = 0;
    std::vector<uint32_t> cellStart;  // nx*ny + 1
    std::vector<double> x, y;         // n + 1: one padding element
    std::vector<int32_t> label;
    std::vector<int32_t> objIdx;  // index into m_objects
    std::unordered_map<int32_t, int32_t> idToSorted;
    /** Unique per build of an index (any map, any thread): keys what callers cache. */
    uint64_t stamp = 0;
    /** Visibility candidate tables of this build (null: no objects). */
    std::shared_ptr<detail::VisCache> vis;
};

CSemanticMap::CSemanticMap()
    : m_labels(std::make_unique<LabelIndex>()), m_index(std::make_unique<Index>())
{
}

CSemanticMap::~CSemanticMap() = default;

CSemanticMap::CSemanticMap(const CSemanticMap& o)
    : mrpt::maps::CMetricMap(o),
      likelihoodOptions(o.likelihoodOptions),
      insertionOptions(o.insertionOptions),
      m_objects(o.m_objects),
      m_bounds(o.m_bounds),
      m_hasBounds(o.m_hasBounds),
      m_labels(std::make_unique<LabelIndex>()),
      m_index(std::make_unique<Index>())
{
    rebuildIndex();
}

CSemanticMap& CSemanticMap::operator=(const CSemanticMap& o)
{
    if (this != &o)
    {
        mrpt::maps::CMetricMap::operator=(o);
        likelihoodOptions = o.likelihoodOptions;
        insertionOptions = o.insertionOptions;
        m_objects = o.m_objects;
        m_bounds = o.m_bounds;
        m_hasBounds = o.m_hasBounds;
        rebuildIndex();
    }
    return *this;
}

void CSemanticMap::rebuildIndex()
{
    m_labels->clear();
    Index& ix = *m_index;
    static std::atomic<uint64_t> stamps{0};
    ix = Index();
    ix.stamp = ++stamps;
    const size_t n = m_objects.size();
    if (n == 0)
    {
        return;
    }
    ix.vis = std::make_shared<detail::VisCache>();
    double xmin = m_objects[0].x, xmax = xmin, ymin = m_objects[0].y, ymax = ymin;
    for (const auto& o : m_objects)
    {
        m_labels->intern(o.label);
        xmin = std::min(xmin, o.x);
        xmax = std::max(xmax, o.x);
        ymin = std::min(ymin, o.y);
        ymax = std::max(ymax, o.y);
    }
    ix.cell = likelihoodOptions.index_cell_m;
    // Keep the grid at most ~1M cells whatever the extent.
    while (((xmax - xmin) / ix.cell + 1) * ((ymax - ymin) / ix.cell + 1) > 1e6)
    {
        ix.cell *= 2;
    }
    ix.inv_cell = 1.0 / ix.cell;
    ix.x0 = xmin;
    ix.y0 = ymin;
    ix.nx = static_cast<int>((xmax - xmin) * ix.inv_cell) + 1;
    ix.ny = static_cast<int>((ymax - ymin) * ix.inv_cell) + 1;
    const size_t ncell = static_cast<size_t>(ix.nx) * static_cast<size_t>(ix.ny);
    std::vector<uint32_t> cellOf(n);
    ix.cellStart.assign(ncell + 1, 0);
    for (size_t i = 0; i < n; i++)
    {
        const int cx =
            std::min(ix.nx - 1, static_cast<int>((m_objects[i].x - ix.x0) * ix.inv_cell));
        const int cy =
            std::min(ix.ny - 1, static_cast<int>((m_objects[i].y - ix.y0) * ix.inv_cell));
        cellOf[i] = static_cast<uint32_t>(cy * ix.nx + cx);
        ix.cellStart[cellOf[i] + 1]++;
    }
    for (size_t c = 0; c < ncell; c++)
    {
        ix.cellStart[c + 1] += ix.cellStart[c];
    }
    // One padding element: the scan reads candidates in pairs (predictVisible).
    ix.x.assign(n + 1, 0.0);
    ix.y.assign(n + 1, 0.0);
    ix.label.resize(n);
    ix.objIdx.resize(n);
    std::vector<uint32_t> fill(ix.cellStart.begin(), ix.cellStart.end() - 1);
    for (size_t i = 0; i < n; i++)
    {
        const uint32_t k = fill[cellOf[i]]++;
        ix.x[k] = m_objects[i].x;
        ix.y[k] = m_objects[i].y;
        ix.label[k] = m_labels->find(m_objects[i].label);
        ix.objIdx[k] = static_cast<int32_t>(i);
        ix.idToSorted[m_objects[i].id] = static_cast<int32_t>(k);
    }
}

size_t CSemanticMap::labelCount() const
{
    return m_labels->size();
}

void CSemanticMap::internal_clear()
{
    m_objects.clear();
    m_hasBounds = false;
    rebuildIndex();
}

void CSemanticMap::loadFromWorld(const World& world)
{
    m_objects.clear();
    for (const auto& wo : world.objects)
    {
        TObject o;
        o.id = wo.id;
        o.label = wo.label;
        o.x = wo.center.x;
        o.y = wo.center.y;
        o.z = wo.z;
        o.extent_m = wo.extent_m;
        m_objects.push_back(std::move(o));
    }
    m_bounds = world.bounds;
    m_hasBounds = true;
    rebuildIndex();
}

void CSemanticMap::loadFromWorldFile(const std::string& path)
{
    loadFromWorld(World::FromFile(path));
}

void CSemanticMap::addObject(const TObject& o)
{
    checkObject(o);
    if (m_index->idToSorted.count(o.id))
    {
        THROW_EXCEPTION_FMT("CSemanticMap::addObject: duplicate object id %d", o.id);
    }
    m_objects.push_back(o);
    rebuildIndex();
}

int CSemanticMap::nextFreeId() const
{
    int id = 0;
    for (const auto& o : m_objects)
    {
        id = std::max(id, o.id);
    }
    return id + 1;
}

World CSemanticMap::toWorld() const
{
    World w;
    w.name = "semantic_map";
    if (m_hasBounds)
    {
        w.bounds = m_bounds;
    }
    else if (!m_objects.empty())
    {
        w.bounds = {m_objects[0].x, m_objects[0].x, m_objects[0].y, m_objects[0].y};
        for (const auto& o : m_objects)
        {
            w.bounds.x_min = std::min(w.bounds.x_min, o.x - 1);
            w.bounds.x_max = std::max(w.bounds.x_max, o.x + 1);
            w.bounds.y_min = std::min(w.bounds.y_min, o.y - 1);
            w.bounds.y_max = std::max(w.bounds.y_max, o.y + 1);
        }
    }
    else
    {
        w.bounds = {0, 1, 0, 1};
    }
    for (const auto& o : m_objects)
    {
        WorldObject wo;
        wo.id = o.id;
        wo.label = o.label;
        wo.shape = ShapeType::Point;
        wo.center = {o.x, o.y};
        wo.z = o.z;
        wo.extent_m = o.extent_m;
        w.objects.push_back(std::move(wo));
    }
    return w;
}

// ------------------------------------------------------------------ likelihood

namespace
{
/** A detection prepared for matching. */
struct Det
{
    double r;       // range [m]
    double uc, us;  // unit vector of the bearing (cos, sin), computed once per observation
    int32_t label;  // label id, or -1 = any label (MRPT landmarks without id)
    int32_t fixed;  // sorted index of the object it names, or -1
};

Det makeDet(double r, double bearing, int32_t label, int32_t fixed)
{
    return {r, std::cos(bearing), std::sin(bearing), label, fixed};
}

/** A map object predicted visible from the particle: one element of z^k. */
struct Vis
{
    double lx, ly, d2;  // position in the sensor frame, squared range
    double r;           // range
    int32_t label, sorted;
};

struct Pair
{
    double gain;
    uint32_t j, v;
    double q = 0;  // probabilistic: P_D / (1 - P_D) of the pair's object (totalsBlock)
};

/** A detection as one of a label's slots (planPairs). */
struct Slot
{
    Det d;
    uint32_t j;  // index into Scratch::dets
};

/** A visible object, of particle p of a block, that may pair (scorePaperBlock). */
struct Gated
{
    Vis o;
    uint32_t p, v;
};

/** A (detection j, gated object e) pair that passed the range and bearing gates. */
struct Cand
{
    uint32_t j, e;
};

constexpr double kInf = std::numeric_limits<double>::infinity();

/** Lazily recomputed value of f(key): the per-step angles and options are the same
 *  for every particle of a step, so their trig/log is computed once per change. */
struct Memo
{
    double key = std::numeric_limits<double>::quiet_NaN(), val = 0;
    template <typename F>
    double get(double k, F&& f)
    {
        if (k != key)
        {
            key = k;
            val = f(k);
        }
        return val;
    }
};

/** What a model needs that is the same for every particle of a call (options, sensor
 *  range and FOV): computed once per call, not per particle. */
struct ModelConsts
{
    double ir = 0, ib = 0;  // 1 / sigma_rho, 1 / sigma_theta [1/m, 1/rad]
    /** Largest (dr/sigma_r)^2 + (db/sigma_b)^2 a pair may cost and still gain. */
    double budget = 0;
    /** cos of the largest |dtheta| the budget allows (-2: no bearing gate). */
    double cosGate = -2;
    double logPu = 0;  // paper: log p_u
    // probabilistic
    double sb = 0, logNorm = 0, logKappa = 0, logSame = 0, logOther = 0, lambda = 0;
    /** log(P_D / (1 - P_D)) at P_D's smallest and largest, widened by 1e-9 (gainBlock). */
    double logQLo = 0, logQHi = 0;
    bool confusable = false;
};

/** Per-thread scratch (one TLS access per call): no allocation per particle once
 *  warmed up, and safe for concurrent const calls from many threads. */
struct Scratch
{
    std::vector<Det> dets;
    size_t nVis = 0;
    std::vector<uint32_t> hits;  // sorted indices of the visible objects (first nVis)
    std::vector<double> hitD2;   // and their squared ranges
    /** Per call: the detections that may pair with a visible object of label l are
     *  detByLabel[detStart[l] .. detStart[l + 1]) (planPairs). */
    std::vector<uint32_t> detByLabel, detStart, detFill;
    /** Per call: squared ranges [gateLo2[l], gateHi2[l]] outside which no detection may
     *  pair with a visible object of label l (planPairs; empty interval: none may). */
    std::vector<double> gateLo2, gateHi2;
    /** Per call: the detections that may pair with label l, padded to slotCount each with
     *  a detection no object can pair with (planPairs), so every object tests as many. */
    std::vector<Slot> slots;
    size_t slotCount = 0;
    /** Per call: the range bins of the slots (planRangeBins): count, 1 / width, spans. */
    size_t binCount = 1;
    double binInv = 0;
    std::vector<uint32_t> binSpan;
    /** The most slots of any bin (planRangeBins). */
    size_t maxSpan = 0;
    /** The block stages: per particle of the block, its q (paper) or number of visible
     *  objects (probabilistic), its number of pairs (paper) and where its objects start
     *  (probabilistic); the objects that may pair (paper) and the gated candidate pairs of
     *  the whole block. */
    std::vector<uint32_t> blockVis, pairCount, visStart;
    std::vector<Gated> gated;
    std::vector<Cand> cands;
    /** gateBlock's (slot, entry) pairs to test, when bins hold few slots. */
    std::vector<Cand> tasks;
    /** Per particle of the block: the product of 1 - P_D of its visible objects, and the
     *  terms of its log-likelihood that do not depend on the association (missBlock). */
    std::vector<double> bMiss, bBase;
    /** planPairs() of the last call is kept while these stay the same. */
    std::vector<Det> planDets;
    std::array<double, 4> planKey{};
    bool planConfusable = false, planValid = false;
    /** scoreProbabilisticBlock's visible objects of the whole block, structure of arrays:
     *  sorted index, particle, squared range, position in the sensor frame, range, P_D. */
    std::vector<uint32_t> bHit, bPart;
    std::vector<double> bD2, bLx, bLy, bR, bPd;
    /** modelConsts() of the last call, kept while its inputs stay the same (MRPT's
     *  per-particle path makes one call per particle). */
    std::array<double, 11> constsKey{};
    ModelConsts consts;
    bool constsValid = false;
    std::vector<Pair> pairs;
    /** The visibility table of this call (null: grid scan) and the last one looked up,
     *  kept (with its key) so calls with the same index build, R and FOV lock nothing. */
    const detail::VisTable* vis = nullptr;
    std::shared_ptr<const detail::VisTable> visHold;
    uint64_t visStamp = 0;
    double visR = 0, visFov = 0;
    /** assignGreedy's marks: all zero between calls (it clears what it set). */
    std::vector<uint8_t> used;
    Memo cosHalf, sinHalf, cosYaw, sinYaw;
};

Scratch& scratch()
{
    thread_local Scratch s;
    return s;
}

/** Sensor geometry for one particle. */
struct Geom
{
    double sx, sy, c, s;  // sensor position and heading cos/sin in the world
    double R, fov, cosHalf, sinHalf;
};

/** What makeGeom needs that is the same for every particle of a call: the sensor's place
 *  on the vehicle, cos/sin of its yaw there, and range, FOV and cos/sin of the half FOV. */
struct GeomConsts
{
    double ox = 0, oy = 0, cosYaw = 1, sinYaw = 0;
    bool yawed = false;
    double R = 0, fov = 0, cosHalf = -1, sinHalf = 0;
};

GeomConsts geomConsts(Scratch& sc, double ox, double oy, double oyaw, double R, double fov)
{
    GeomConsts gc;
    gc.ox = ox;
    gc.oy = oy;
    gc.yawed = oyaw != 0;
    if (gc.yawed)
    {
        gc.cosYaw = sc.cosYaw.get(oyaw, [](double a) { return std::cos(a); });
        gc.sinYaw = sc.sinYaw.get(oyaw, [](double a) { return std::sin(a); });
    }
    gc.R = R;
    gc.fov = fov;
    if (fov < 2 * M_PI)
    {
        gc.cosHalf = sc.cosHalf.get(0.5 * fov, [](double a) { return std::cos(a); });
        gc.sinHalf = sc.sinHalf.get(0.5 * fov, [](double a) { return std::sin(a); });
    }
    return gc;
}

/** The geometry of `pose`, sp and cp the sin and cos of its heading. */
Geom makeGeom(const GeomConsts& gc, const TPose2D& pose, double sp, double cp)
{
    Geom g;
    g.sx = pose.x + cp * gc.ox - sp * gc.oy;
    g.sy = pose.y + sp * gc.ox + cp * gc.oy;
    if (gc.yawed)
    {
        g.c = cp * gc.cosYaw - sp * gc.sinYaw;
        g.s = sp * gc.cosYaw + cp * gc.sinYaw;
    }
    else
    {
        g.c = cp;
        g.s = sp;
    }
    g.R = gc.R;
    g.fov = gc.fov;
    g.cosHalf = gc.cosHalf;
    g.sinHalf = gc.sinHalf;
    return g;
}

/** The cells [cx0, cx1] x [cy0, cy1] of the grid that the bounding box of the FOV sector
 *  overlaps (apex, both arc ends, and the arc's extreme points along the axes that lie
 *  inside the FOV); empty when the box misses the grid. Branch-free, x and y together. */
void sectorCells(const CSemanticMap::Index& ix, const Geom& g, int& cx0, int& cx1, int& cy0,
                 int& cy1)
{
#if defined(SEMLOC_FASTMATH_SSE2)
    const __m128d p = _mm_set_pd(g.sy, g.sx);
    __m128d lo = p, hi = p;
    const __m128d R = _mm_set1_pd(g.R);
    if (g.fov < 2 * M_PI)
    {
        const double ch = g.cosHalf, sh = g.sinHalf;
        const __m128d e1 =
            _mm_add_pd(p, _mm_mul_pd(R, _mm_set_pd(g.s * ch + g.c * sh, g.c * ch - g.s * sh)));
        const __m128d e2 =
            _mm_add_pd(p, _mm_mul_pd(R, _mm_set_pd(g.s * ch - g.c * sh, g.c * ch + g.s * sh)));
        lo = _mm_min_pd(lo, _mm_min_pd(e1, e2));
        hi = _mm_max_pd(hi, _mm_max_pd(e1, e2));
        // The arc reaches +R (-R) along an axis if that direction is inside the FOV.
        const __m128d dir = _mm_set_pd(g.s, g.c), vch = _mm_set1_pd(ch);
        hi = _mm_max_pd(hi, _mm_add_pd(p, _mm_and_pd(_mm_cmpge_pd(dir, vch), R)));
        lo = _mm_min_pd(
            lo, _mm_sub_pd(p, _mm_and_pd(_mm_cmpge_pd(_mm_sub_pd(_mm_setzero_pd(), dir), vch), R)));
    }
    else
    {
        lo = _mm_sub_pd(p, R);
        hi = _mm_add_pd(p, R);
    }
    const __m128d origin = _mm_set_pd(ix.y0, ix.x0), inv = _mm_set1_pd(ix.inv_cell);
    const __m128d last = _mm_set_pd(ix.ny - 1.0, ix.nx - 1.0);
    // low: clamp to [0, n-1], truncate; high: clamp to [-1, n-1], floor (-1: box before
    // the grid, then the range is empty).
    const __m128i c0 = _mm_cvttpd_epi32(
        _mm_min_pd(last, _mm_max_pd(_mm_mul_pd(_mm_sub_pd(lo, origin), inv), _mm_setzero_pd())));
    const __m128d h =
        _mm_min_pd(last, _mm_max_pd(_mm_mul_pd(_mm_sub_pd(hi, origin), inv), _mm_set1_pd(-1.0)));
    const __m128d t = _mm_cvtepi32_pd(_mm_cvttpd_epi32(h));
    const __m128i c1 =
        _mm_cvttpd_epi32(_mm_sub_pd(t, _mm_and_pd(_mm_cmplt_pd(h, t), _mm_set1_pd(1.0))));
    cx0 = _mm_cvtsi128_si32(c0);
    cy0 = _mm_cvtsi128_si32(_mm_srli_si128(c0, 4));
    cx1 = _mm_cvtsi128_si32(c1);
    cy1 = _mm_cvtsi128_si32(_mm_srli_si128(c1, 4));
#else
    double bx0 = g.sx, bx1 = g.sx, by0 = g.sy, by1 = g.sy;
    auto grow = [&](double x, double y)
    {
        bx0 = std::min(bx0, x);
        bx1 = std::max(bx1, x);
        by0 = std::min(by0, y);
        by1 = std::max(by1, y);
    };
    if (g.fov < 2 * M_PI)
    {
        const double ch = g.cosHalf, sh = g.sinHalf;
        grow(g.sx + g.R * (g.c * ch - g.s * sh), g.sy + g.R * (g.s * ch + g.c * sh));
        grow(g.sx + g.R * (g.c * ch + g.s * sh), g.sy + g.R * (g.s * ch - g.c * sh));
        if (g.c >= ch)
        {
            grow(g.sx + g.R, g.sy);
        }
        if (-g.c >= ch)
        {
            grow(g.sx - g.R, g.sy);
        }
        if (g.s >= ch)
        {
            grow(g.sx, g.sy + g.R);
        }
        if (-g.s >= ch)
        {
            grow(g.sx, g.sy - g.R);
        }
    }
    else
    {
        grow(g.sx - g.R, g.sy - g.R);
        grow(g.sx + g.R, g.sy + g.R);
    }
    auto lowCell = [](double v, int n)
    { return v <= 0 ? 0 : static_cast<int>(std::min(n - 1.0, v)); };
    auto highCell = [](double v, int n)
    { return v < 0 ? -1 : static_cast<int>(std::min(n - 1.0, v)); };
    cx0 = lowCell((bx0 - ix.x0) * ix.inv_cell, ix.nx);
    cx1 = highCell((bx1 - ix.x0) * ix.inv_cell, ix.nx);
    cy0 = lowCell((by0 - ix.y0) * ix.inv_cell, ix.ny);
    cy1 = highCell((by1 - ix.y0) * ix.inv_cell, ix.ny);
#endif
}

/** The angle [rad] of the direction with "diamond angle" a in [-1, 3] (the table's bins):
 *  a = s / (|c| + |s|) for c >= 0, 2 - s / (|c| + |s|) for c < 0; monotonic in the angle,
 *  [-pi/2, 3 pi/2]. */
double diamondToAngle(double a)
{
    if (a <= 1)
    {
        return std::atan2(a, 1 - std::abs(a));
    }
    const double t = 2 - a;
    return M_PI - std::atan2(t, 1 - std::abs(t));
}

/** Builds the visibility table of index ix for range R and FOV fov (cells of R / 10, 32
 *  heading bins; one with a full FOV), or null when it would take more than kVisMaxBytes:
 *  a larger table, read at random places by particles spread over a large map, misses the
 *  cache and made the likelihood slower than the grid scan (5 000 and 10 000 objects at the
 *  paper map's density: 209-270 ns per particle against 191-218 with 8 MB tables of coarser
 *  cells), so large maps keep the grid scan. */
std::shared_ptr<const detail::VisTable> buildVisTable(const CSemanticMap::Index& ix, double R,
                                                      double fov)
{
    constexpr size_t kVisMaxBytes = size_t{1} << 20;
    constexpr size_t kVisMaxPairs = size_t{64} << 20;  // (cell, object) pairs looked at
    const size_t n = ix.objIdx.size();
    if (n == 0 || !(R > 0) || !std::isfinite(R))
    {
        return nullptr;
    }
    const double* X = ix.x.data();
    const double* Y = ix.y.data();
    double xmin = X[0], xmax = X[0], ymin = Y[0], ymax = Y[0], maxAbs = 0;
    for (size_t k = 0; k < n; k++)
    {
        xmin = std::min(xmin, X[k]);
        xmax = std::max(xmax, X[k]);
        ymin = std::min(ymin, Y[k]);
        ymax = std::max(ymax, Y[k]);
        maxAbs = std::max({maxAbs, std::abs(X[k]), std::abs(Y[k])});
    }
    const uint32_t bins = fov >= 2 * M_PI ? 1 : 32;
    // Heading bins: bin b is the headings of angles [edges[b], edges[b + 1]], increasing
    // from -pi/2 to 3 pi/2.
    std::vector<double> edges(bins + 1);
    for (uint32_t b = 0; b <= bins; b++)
    {
        edges[b] = diamondToAngle(4.0 * b / bins - 1);
    }
    auto binOf = [&](double ang)  // ang in [-pi/2, 3 pi/2)
    {
        // Bins are within ~4 degrees of uniform in angle: guess, then step to the bin.
        auto b = static_cast<uint32_t>(
            std::min(bins - 1.0, std::max(0.0, (ang + 0.5 * M_PI) * (bins / (2 * M_PI)))));
        while (b > 0 && edges[b] > ang)
        {
            b--;
        }
        while (b + 1 < bins && edges[b + 1] <= ang)
        {
            b++;
        }
        return b;
    };
    const uint64_t allBins = bins == 64 ? ~uint64_t{0} : (uint64_t{1} << bins) - 1;
    auto bitsOf = [](uint32_t b0, uint32_t b1)  // bins b0..b1, b0 <= b1 < 64
    { return (uint64_t{2} << b1) - (uint64_t{1} << b0); };
    const bool small = n < 65536;
    const double halfFov = std::min(0.5 * fov, M_PI);
    // Margins, far above the rounding of the lookup and of the exact test.
    const double eps = 1e-9 * (1 + maxAbs + R), angMargin = 1e-5;
    const double Rm = R * (1 + 1e-9) + eps;
    const double side = R / 10;
    {
        const double nxD = std::floor((xmax - xmin + 2 * R) / side) + 3;
        const double nyD = std::floor((ymax - ymin + 2 * R) / side) + 3;
        const double lists = nxD * nyD * bins;
        if (!(side < 1e300))
        {
            detail::g_visLastBytes.store(0);
            return nullptr;  // a degenerate extent: the grid scan serves
        }
        if (!(lists * 4 <= 0.5 * static_cast<double>(kVisMaxBytes)))
        {
            detail::g_visLastBytes.store(0);
            return nullptr;  // the list offsets alone too large: the grid scan serves
        }
        auto t = std::make_shared<detail::VisTable>();
        t->x0 = xmin - R - side;
        t->y0 = ymin - R - side;
        t->inv = 1 / side;
        t->ox = t->x0 - side;
        t->oy = t->y0 - side;
        t->nx = static_cast<uint32_t>(nxD);
        t->ny = static_cast<uint32_t>(nyD);
        t->bins = bins;
        t->binScale = bins > 1 ? bins / 4.0 : 0.0;
        t->lastBin = bins - 1.0;
        const auto nl = static_cast<size_t>(lists);
        t->start.assign(nl + 1, 0);
        const size_t maxEntries = (kVisMaxBytes - 4 * (nl + 1)) / (small ? 2 : 4);
        std::vector<uint32_t> cand;
        // Per cell, the lists of its bins, each in increasing sorted index (the objects are
        // visited in that order).
        std::vector<std::vector<uint32_t>> perBin(bins);
        const double h = 0.5 * side + eps;  // half side of a cell, widened
        const double rc = h * std::sqrt(2.0);
        bool tooLarge = false;
        size_t pairs = 0;
        for (size_t cy = 0; cy < t->ny && !tooLarge; cy++)
        {
            for (size_t cx = 0; cx < t->nx && !tooLarge; cx++)
            {
                const double mx = t->x0 + (static_cast<double>(cx) + 0.5) * side;
                const double my = t->y0 + (static_cast<double>(cy) + 0.5) * side;
                // The index cells of the objects within h + Rm of the centre, per axis.
                auto cells =
                    [](double lo, double hi, double o, double inv, int nc, int& c0, int& c1)
                {
                    const double l = std::max(0.0, (lo - o) * inv);
                    const double u = std::min(nc - 1.0, (hi - o) * inv);
                    c0 = static_cast<int>(std::min(l, nc - 1.0));
                    c1 = u < 0 ? -1 : static_cast<int>(u);
                };
                int ix0, ix1, iy0, iy1;
                cells(mx - h - Rm, mx + h + Rm, ix.x0, ix.inv_cell, ix.nx, ix0, ix1);
                cells(my - h - Rm, my + h + Rm, ix.y0, ix.inv_cell, ix.ny, iy0, iy1);
                for (auto& l : perBin)
                {
                    l.clear();
                }
                for (int icy = iy0; icy <= iy1 && ix0 <= ix1; icy++)
                {
                    const size_t row = static_cast<size_t>(icy) * static_cast<size_t>(ix.nx);
                    for (uint32_t k = ix.cellStart[row + static_cast<size_t>(ix0)];
                         k < ix.cellStart[row + static_cast<size_t>(ix1) + 1]; k++)
                    {
                        const double dx = X[k] - mx, dy = Y[k] - my;
                        tooLarge |= ++pairs > kVisMaxPairs;  // the build's work, bounded
                        const double ex = std::max(std::abs(dx) - h, 0.0);
                        const double ey = std::max(std::abs(dy) - h, 0.0);
                        if (ex * ex + ey * ey > Rm * Rm)
                        {
                            continue;  // out of range from the whole cell
                        }
                        uint64_t mask = 0;
                        const double d = std::sqrt(dx * dx + dy * dy);
                        if (bins == 1 || d <= rc * (1 + 1e-6))
                        {
                            mask = allBins;  // any direction
                        }
                        else
                        {
                            // Directions from the cell: within asin(rc / d) of the centre's.
                            const double phi = detail::fastAtan2(dy, dx);  // |error| < 1e-7
                            // Headings that see it: within spread of that direction.
                            const double spread =
                                std::asin(std::min(1.0, rc / d)) + halfFov + angMargin;
                            if (spread >= M_PI)
                            {
                                mask = allBins;
                            }
                            else
                            {
                                double lo = phi - spread;  // (-2 pi, pi) -> [-pi/2, 3 pi/2)
                                lo += lo < -0.5 * M_PI ? 2 * M_PI : 0;
                                const double hi = lo + 2 * spread;
                                const uint32_t b0 = binOf(lo);
                                mask = hi < 1.5 * M_PI
                                           ? bitsOf(b0, binOf(hi))
                                           : bitsOf(b0, bins - 1) | bitsOf(0, binOf(hi - 2 * M_PI));
                            }
                        }
                        for (; mask != 0; mask &= mask - 1)  // k goes to its bins' lists
                        {
                            perBin[static_cast<size_t>(__builtin_ctzll(mask))].push_back(k);
                        }
                    }
                }
                const size_t list0 = (cy * t->nx + cx) * bins;  // < 2^31: the byte cap
                for (uint32_t b = 0; b < bins; b++)
                {
                    cand.insert(cand.end(), perBin[b].begin(), perBin[b].end());
                    t->start[list0 + b + 1] = static_cast<uint32_t>(cand.size());
                }
                tooLarge |= cand.size() > maxEntries;
            }
        }
        if (tooLarge)
        {
            detail::g_visLastBytes.store(0);
            return nullptr;  // too large: the grid scan serves
        }
        cand.push_back(0);  // padding: the scan reads candidates in pairs
        if (small)
        {
            t->c16.assign(cand.begin(), cand.end());
        }
        else
        {
            t->c32 = std::move(cand);
        }
        t->bytes = 4 * t->start.size() + 2 * t->c16.size() + 4 * t->c32.size();
        detail::g_visLastBytes.store(t->bytes);
        return t;
    }
}

/** The table's candidates [a, b) for the particle's sensor position and heading; false if
 *  the position is outside the table or (c, s) is not a unit vector to 1e-12 (the table's
 *  angle margin assumes it: fastSinCos is exact to ~1e-15 for |phi| <= 1e6): then the grid
 *  scan serves it. */
inline bool visRange(const detail::VisTable& t, const Geom& g, uint32_t& a, uint32_t& b)
{
    // Cell + 1 (truncation toward 0 maps (-1, 1) to 0: outside, as are NaN and huge values).
#if defined(SEMLOC_FASTMATH_SSE2)
    // cvttpd gives INT_MIN for NaN and out-of-range values: no undefined conversion.
    const __m128i ci = _mm_cvttpd_epi32(
        _mm_mul_pd(_mm_sub_pd(_mm_set_pd(g.sy, g.sx), _mm_set_pd(t.oy, t.ox)), _mm_set1_pd(t.inv)));
    const uint32_t cx = static_cast<uint32_t>(_mm_cvtsi128_si32(ci)) - 1u;
    const uint32_t cy = static_cast<uint32_t>(_mm_cvtsi128_si32(_mm_srli_si128(ci, 4))) - 1u;
#else
    const double fx = (g.sx - t.ox) * t.inv, fy = (g.sy - t.oy) * t.inv;
    if (!(std::abs(fx) < 1e9 && std::abs(fy) < 1e9))
    {
        return false;
    }
    const uint32_t cx = static_cast<uint32_t>(static_cast<int32_t>(fx)) - 1u;
    const uint32_t cy = static_cast<uint32_t>(static_cast<int32_t>(fy)) - 1u;
#endif
    if (cx >= t.nx || cy >= t.ny)
    {
        return false;
    }
    if (!(std::abs(g.c * g.c + g.s * g.s - 1) < 1e-12))
    {
        return false;
    }
    const double q = g.s / (std::abs(g.c) + std::abs(g.s));
    const double ad = (g.c >= 0 ? q : 2 - q) + 1;  // diamond angle + 1, in [0, 4]
    const auto bin = static_cast<uint32_t>(std::min(ad * t.binScale, t.lastBin));
    const uint32_t list = (cy * t.nx + cx) * t.bins + bin;
    a = t.start[list];
    b = t.start[list + 1];
    return true;
}

/** A particle's candidate list in the visibility table: [a, b) if `table`, else none (the
 *  grid scan serves it). */
struct ListRange
{
    uint32_t a = 0, b = 0;
    bool table = false;
};

/** visRange() of geometry g in table vt (null: none). */
inline ListRange listOf(const detail::VisTable* vt, const Geom& g)
{
    ListRange r;
    r.table = vt != nullptr && visRange(*vt, g, r.a, r.b);
    return r;
}

/** The table of (R, fov) for index ix (built on first use), or null: grid scan. */
const detail::VisTable* visTableFor(const CSemanticMap::Index& ix, double R, double fov,
                                    Scratch& sc)
{
    if (!ix.vis || !detail::visibilityTableEnabled())
    {
        return nullptr;
    }
    if (sc.visStamp != ix.stamp || sc.visR != R || sc.visFov != fov)
    {
        std::shared_ptr<const detail::VisTable> t;
        {
            std::lock_guard<std::mutex> lock(ix.vis->mu);
            auto& es = ix.vis->entries;
            const auto it = std::find_if(es.begin(), es.end(),
                                         [&](const detail::VisCache::Entry& e)
                                         { return e.R == R && e.fov == fov; });
            if (it != es.end())
            {
                t = it->table;
            }
            else
            {
                t = buildVisTable(ix, R, fov);
                if (es.size() >= 4)
                {
                    es.erase(es.begin());  // a few (R, FOV) at most: the oldest goes
                }
                es.push_back({R, fov, t});
            }
        }
        sc.visHold = std::move(t);
        sc.visStamp = ix.stamp;
        sc.visR = R;
        sc.visFov = fov;
    }
    return sc.visHold.get();
}

/** Where scanVisible() writes z^k, compacted: sorted indices and squared ranges and, with
 *  kFrame, the positions in the sensor frame (lx ahead, ly to the left) and `partId` (the
 *  particle's index in its block) in `part`. Every array must have room for the number of
 *  objects + 1 (entries are written always, kept if visible). */
struct VisOut
{
    uint32_t* hits;
    double* d2;
    double* lx;
    double* ly;
    uint32_t* part = nullptr;
    uint32_t partId = 0;
};

/** Finds the objects inside range and FOV (z^k) into `out`; returns how many. The
 *  candidates are the visibility table's list of the particle's cell and heading bin (vt,
 *  if any and the particle is inside it: lr = listOf(vt, g)), else the grid cells the FOV
 *  sector overlaps;
 *  both in increasing sorted index, so the same z^k in the same order.
 *  The test is branch-free (compaction by a counter) and takes no square root until an
 *  object is known to be visible: most candidates are not, and mispredicted branches
 *  and sqrt latency were the cost of this loop. */
template <bool kFrame>
size_t scanVisible(const CSemanticMap::Index& ix, const Geom& g, const VisOut& vo,
                   const detail::VisTable* vt, const ListRange& lr)
{
    size_t cnt = 0;
    if (ix.nx > 0)
    {
        const double R2 = g.R * g.R;
        const double ch2 = g.cosHalf * g.cosHalf;
        const bool narrow = g.cosHalf >= 0;  // FOV <= 180 deg
        // Locals, not members: the stores to `out` could alias them, which made the compiler
        // reload every member and vector pointer at each candidate.
        const double sx = g.sx, sy = g.sy, c = g.c, sn = g.s;
        const double* X = ix.x.data();
        const double* Y = ix.y.data();
        const uint32_t* cellStart = ix.cellStart.data();
        const auto nx = static_cast<size_t>(ix.nx);
        uint32_t* out = vo.hits;
        double* outD2 = vo.d2;
        double* outLx = vo.lx;
        double* outLy = vo.ly;
        uint32_t* outPart = vo.part;
        const uint32_t partId = vo.partId;
        // The candidates: a table list, or grid rows (each a contiguous range of indices).
        // visit(step2) calls step2(k0, k1, lanes, adjacent) for candidates k0, k1 (lanes: 3
        // both, 1 the first only; the arrays have one padding element for the second lane;
        // adjacent: std::true_type when k1 = k0 + 1, loaded as one pair).
        const uint32_t ta = lr.a, tb = lr.b;
        const bool fromTable = lr.table;
        auto visit = [&](auto step2)
        {
            if (fromTable)
            {
                auto list = [&](const auto* C)
                {
                    for (uint32_t j = ta; j < tb; j += 2)
                    {
                        step2(C[j], C[j + 1], tb - j >= 2 ? 3u : 1u, std::false_type());
                    }
                };
                if (vt->c16.empty())
                {
                    list(vt->c32.data());
                }
                else
                {
                    list(vt->c16.data());
                }
                return;
            }
            int cx0 = 0, cx1 = -1, cy0 = 0, cy1 = -1;
            sectorCells(ix, g, cx0, cx1, cy0, cy1);
            for (int cy = cy0; cy <= cy1 && cx0 <= cx1; cy++)
            {
                const size_t row = static_cast<size_t>(cy) * nx;
                const uint32_t a = cellStart[row + static_cast<size_t>(cx0)];
                const uint32_t b = cellStart[row + static_cast<size_t>(cx1) + 1];
                for (uint32_t k = a; k < b; k += 2)
                {
                    step2(k, k + 1, b - k >= 2 ? 3u : 1u, std::true_type());
                }
            }
        };
        // One loop per FOV kind (the test inlined, not selected at every candidate).
#if defined(SEMLOC_FASTMATH_SSE2)
        // Two candidates per step in SSE2 (every x86-64 CPU has it): the same IEEE double
        // operations in the same order as the scalar test below, so the same decisions.
        // Rows hold ~2-3 candidates, so a 2-wide step (the lane past the end is masked)
        // suits them better than wider vectors.
        const __m128d vsx = _mm_set1_pd(sx), vsy = _mm_set1_pd(sy), vc = _mm_set1_pd(c),
                      vsn = _mm_set1_pd(sn), vR2 = _mm_set1_pd(R2), vch2 = _mm_set1_pd(ch2),
                      zero = _mm_setzero_pd();
        auto scanAll = [&](auto inFov)
        {
            visit(
                [&](uint32_t k0, uint32_t k1, unsigned lanes, auto adjacent)
                {
                    __m128d x, y;
                    if constexpr (decltype(adjacent)::value)
                    {
                        x = _mm_loadu_pd(X + k0);
                        y = _mm_loadu_pd(Y + k0);
                    }
                    else
                    {
                        x = _mm_set_pd(X[k1], X[k0]);
                        y = _mm_set_pd(Y[k1], Y[k0]);
                    }
                    const __m128d dx = _mm_sub_pd(x, vsx);
                    const __m128d dy = _mm_sub_pd(y, vsy);
                    const __m128d d2 = _mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy));
                    const __m128d lx = _mm_add_pd(_mm_mul_pd(vc, dx), _mm_mul_pd(vsn, dy));
                    const __m128d in = _mm_and_pd(_mm_cmple_pd(d2, vR2), inFov(lx, d2));
                    const auto m = static_cast<unsigned>(_mm_movemask_pd(in)) & lanes;
                    // ly = (-sn) dx + c dy, as the scalar code writes it.
                    const __m128d ly =
                        kFrame ? _mm_sub_pd(_mm_mul_pd(vc, dy), _mm_mul_pd(vsn, dx)) : zero;
                    out[cnt] = k0;  // written always, kept only if visible
                    _mm_storel_pd(outD2 + cnt, d2);
                    if constexpr (kFrame)
                    {
                        _mm_storel_pd(outLx + cnt, lx);
                        _mm_storel_pd(outLy + cnt, ly);
                        outPart[cnt] = partId;
                    }
                    cnt += m & 1u;
                    out[cnt] = k1;
                    _mm_storeh_pd(outD2 + cnt, d2);
                    if constexpr (kFrame)
                    {
                        _mm_storeh_pd(outLx + cnt, lx);
                        _mm_storeh_pd(outLy + cnt, ly);
                        outPart[cnt] = partId;
                    }
                    cnt += m >> 1;
                });
        };
        // lx >= cos(fov/2) * d, squared without the sqrt, per sign of cos(fov/2).
        if (narrow)
        {
            scanAll(
                [&](__m128d lx, __m128d d2)
                {
                    return _mm_and_pd(_mm_cmpge_pd(lx, zero),
                                      _mm_cmpge_pd(_mm_mul_pd(lx, lx), _mm_mul_pd(vch2, d2)));
                });
        }
        else
        {
            scanAll(
                [&](__m128d lx, __m128d d2)
                {
                    return _mm_or_pd(_mm_cmpge_pd(lx, zero),
                                     _mm_cmple_pd(_mm_mul_pd(lx, lx), _mm_mul_pd(vch2, d2)));
                });
        }
#else
        auto scanAll = [&](auto inFov)
        {
            auto one = [&](uint32_t k)
            {
                const double dx = X[k] - sx, dy = Y[k] - sy;
                const double d2 = dx * dx + dy * dy;
                const double lx = c * dx + sn * dy;
                out[cnt] = k;  // written always, kept only if visible
                outD2[cnt] = d2;
                if constexpr (kFrame)
                {
                    outLx[cnt] = lx;
                    outLy[cnt] = -sn * dx + c * dy;
                    outPart[cnt] = partId;
                }
                cnt += static_cast<size_t>((d2 <= R2) & inFov(lx, d2));
            };
            visit(
                [&](uint32_t k0, uint32_t k1, unsigned lanes, auto)
                {
                    one(k0);
                    if (lanes == 3u)
                    {
                        one(k1);
                    }
                });
        };
        // lx >= cos(fov/2) * d, squared without the sqrt, per sign of cos(fov/2).
        if (narrow)
        {
            scanAll([ch2](double lx, double d2) { return (lx >= 0) & (lx * lx >= ch2 * d2); });
        }
        else
        {
            scanAll([ch2](double lx, double d2) { return (lx >= 0) | (lx * lx <= ch2 * d2); });
        }
#endif
    }
    return cnt;
}

/** z^k of one particle into sc.hits / sc.hitD2 (scorePaperBlock). */
void predictVisible(const CSemanticMap::Index& ix, const Geom& g, Scratch& sc)
{
    if (sc.hits.size() < ix.x.size())
    {
        sc.hits.resize(ix.x.size());
        sc.hitD2.resize(ix.x.size());
    }
    const size_t cnt = scanVisible<false>(
        ix, g, {sc.hits.data(), sc.hitD2.data(), nullptr, nullptr}, sc.vis, listOf(sc.vis, g));
    sc.nVis = cnt;
    if (sc.used.size() < sc.dets.size() + cnt)
    {
        sc.used.resize(sc.dets.size() + ix.x.size(), 0);
    }
}

size_t visibleCount(const Scratch& sc)
{
    return sc.nVis;
}

/** Wraps a bearing into [-pi, pi] (detectors may report [0, 2pi)). */
double wrapBearing(double b)
{
    return (b >= -M_PI && b <= M_PI) ? b : std::remainder(b, 2 * M_PI);
}

/** Greedy one-to-one assignment, best pair first; ties broken by (j, v) so the
 *  result never depends on the sort implementation. Returns the summed gain. */
double assignGreedy(Pair* pairs, size_t np, size_t nd, uint8_t* used)
{
    if (np <= 1)
    {
        return np == 0 ? 0.0 : pairs[0].gain;  // the usual case: no conflict to resolve
    }
    auto before = [](const Pair& a, const Pair& b)
    {
        if (a.gain != b.gain)
        {
            return a.gain > b.gain;
        }
        return a.j != b.j ? a.j < b.j : a.v < b.v;
    };
    if (np > 24)
    {
        std::sort(pairs, pairs + np, before);
    }
    else
    {
        for (size_t i = 1; i < np; i++)  // a handful of pairs: insertion sort, inline
        {
            const Pair p = pairs[i];
            size_t k = i;
            for (; k > 0 && before(p, pairs[k - 1]); k--)
            {
                pairs[k] = pairs[k - 1];
            }
            pairs[k] = p;
        }
    }
    double sum = 0;
    for (size_t i = 0; i < np; i++)
    {
        const Pair& p = pairs[i];
        if (used[p.j] | used[nd + p.v])
        {
            continue;
        }
        used[p.j] = used[nd + p.v] = 1;
        sum += p.gain;
    }
    for (size_t i = 0; i < np; i++)
    {
        used[pairs[i].j] = used[nd + pairs[i].v] = 0;
    }
    return sum;
}

ModelConsts modelConsts(const CSemanticMap::TLikelihoodOptions& opt, size_t nLabels, double R,
                        double fov)
{
    ModelConsts k;
    double sigmaB = 0;
    if (opt.model == CSemanticMap::Model::Paper)
    {
        k.ir = 1.0 / opt.sigma_range_m;
        k.ib = 1.0 / (opt.sigma_bearing_deg * M_PI / 180.0);
        k.logPu = std::log(opt.unmatched_penalty);
        // Matching a pair instead of leaving both unmatched gains s - 2 log(p_u) (> 0 to
        // match). Gain > 0 needs (dr/sr)^2 + (db/sb)^2 < -4 log(p_u).
        k.budget = -4 * k.logPu;
        sigmaB = 1.0 / k.ib;
    }
    else
    {
        const double sr = opt.sigma_range_m, sb = opt.sigma_bearing_deg * M_PI / 180.0;
        k.sb = sb;
        k.logNorm = -std::log(2 * M_PI * sr * sb);
        const double K = static_cast<double>(std::max<size_t>(1, nLabels));
        k.lambda = opt.clutter_per_scan;
        k.logKappa = std::log(k.lambda / (R * std::min(fov, 2 * M_PI) * K));
        k.logSame = std::log1p(-opt.p_confusion);
        k.confusable = opt.p_confusion > 0 && nLabels > 1;
        k.logOther = k.confusable ? std::log(opt.p_confusion / (K - 1)) : 0;
        k.ir = 1.0 / sr;
        k.ib = 1.0 / sb;
        // Gain > 0 needs the Gaussian terms to cost less than the best the rest can give:
        // P_D at its largest, a label term <= 0.
        const double pmax =
            std::clamp(std::max(opt.p_detect_near, opt.p_detect_far), 1e-6, 1 - 1e-6);
        k.budget = 2 * (std::log(pmax) - std::log1p(-pmax) + k.logNorm - k.logKappa);
        const double pmin =
            std::clamp(std::min(opt.p_detect_near, opt.p_detect_far), 1e-6, 1 - 1e-6);
        k.logQLo = std::log(pmin / (1 - pmin)) - 1e-9;
        k.logQHi = std::log(pmax / (1 - pmax)) + 1e-9;
        sigmaB = sb;
    }
    const double maxAbsDb = sigmaB * std::sqrt(std::max(0.0, k.budget));
    k.cosGate = maxAbsDb >= M_PI ? -2.0 : std::cos(maxAbsDb);
    return k;
}

const ModelConsts& cachedModelConsts(const CSemanticMap::TLikelihoodOptions& opt, size_t nLabels,
                                     double R, double fov, Scratch& sc)
{
    const std::array<double, 11> key = {static_cast<double>(opt.model),
                                        opt.sigma_range_m,
                                        opt.sigma_bearing_deg,
                                        opt.unmatched_penalty,
                                        opt.p_detect_near,
                                        opt.p_detect_far,
                                        opt.clutter_per_scan,
                                        opt.p_confusion,
                                        static_cast<double>(nLabels),
                                        R,
                                        fov};
    if (!sc.constsValid || key != sc.constsKey)
    {
        sc.consts = modelConsts(opt, nLabels, R, fov);
        sc.constsKey = key;
        sc.constsValid = true;
    }
    return sc.consts;
}

/** The range bins of planPairs(): each label's slots by increasing range, and for an object
 *  of label l in range bin b (width binW, the last bin open-ended) the slots
 *  [binSpan[2 (l nb + b)], binSpan[2 (l nb + b) + 1]) whose range may be within `reach` of
 *  its range (bounds widened by a relative 1e-9 for rounding: a superset of the pairs that
 *  pass the range gate). So an object meets ~2 reach of detections, not all of its label's. */
void planRangeBins(Scratch& sc, size_t nLabels, double reach)
{
    const size_t ns = sc.slotCount;
    double maxR = 0;
    for (size_t l = 0; l < nLabels; l++)
    {
        Slot* sl = sc.slots.data() + l * ns;
        const size_t cnt = sc.detStart[l + 1] - sc.detStart[l];
        std::sort(sl, sl + cnt,
                  [](const Slot& a, const Slot& b)
                  { return a.d.r != b.d.r ? a.d.r < b.d.r : a.j < b.j; });
        maxR = cnt > 0 ? std::max(maxR, sl[cnt - 1].d.r) : maxR;
    }
    // Bins of half the window, at most 1024 of them; one bin (no filtering) if the window
    // is not finite.
    sc.binCount = 1;
    sc.binInv = 0;
    double w = kInf;
    if (std::isfinite(reach) && std::isfinite(maxR))
    {
        w = std::max(reach / 2, (maxR + reach) / 1022);
        if (w > 0)
        {
            sc.binCount = static_cast<size_t>((maxR + reach) / w) + 2;
            sc.binInv = 1 / w;
        }
    }
    const size_t nb = sc.binCount;
    sc.binSpan.resize(2 * nLabels * nb);
    sc.maxSpan = 0;
    for (size_t l = 0; l < nLabels; l++)
    {
        const Slot* sl = sc.slots.data() + l * ns;
        const Slot* end = sl + (sc.detStart[l + 1] - sc.detStart[l]);
        for (size_t b = 0; b < nb; b++)
        {
            const double lo = nb == 1 ? -kInf : static_cast<double>(b) * w - reach;
            const double hi = b + 1 == nb ? kInf : static_cast<double>(b + 1) * w + reach;
            const double margin = 1e-9 * (static_cast<double>(b + 1) * w + reach) + 1e-9;
            const Slot* first = std::lower_bound(sl, end, lo - margin,
                                                 [](const Slot& a, double r) { return a.d.r < r; });
            const Slot* last = std::upper_bound(first, end, hi + margin,
                                                [](double r, const Slot& a) { return r < a.d.r; });
            sc.binSpan[2 * (l * nb + b)] = static_cast<uint32_t>(first - sc.slots.data());
            sc.binSpan[2 * (l * nb + b) + 1] = static_cast<uint32_t>(last - sc.slots.data());
            sc.maxSpan = std::max(sc.maxSpan, static_cast<size_t>(last - first));
        }
    }
}

/** Which detections may pair with an object of label l (once per call):
 *  detByLabel[detStart[l] .. detStart[l + 1]) holds those of label l, those of any label
 *  (`k.confusable`, or a detection without one), and those naming an object of label l
 *  (they pair with that object only: Det::fixed). Also the range hull of each label: a pair
 *  passes the range gate (passesGates) only if |rho^r - rho^k| <= sigma_rho sqrt(budget), so
 *  an object of label l whose squared range is outside [gateLo2[l], gateHi2[l]] pairs with
 *  none of them (bounds widened by a relative 1e-9 for rounding: a necessary condition). */
void planPairs(Scratch& sc, const CSemanticMap::Index& ix, size_t nLabels, const ModelConsts& k)
{
    const bool anyLabel = k.confusable;
    const auto nd = static_cast<uint32_t>(sc.dets.size());
    auto labelsOf = [&](const Det& d, auto&& add)
    {
        if (d.fixed >= 0)
        {
            add(static_cast<size_t>(ix.label[static_cast<size_t>(d.fixed)]));
        }
        else if (anyLabel || d.label < 0)
        {
            for (size_t l = 0; l < nLabels; l++)
            {
                add(l);
            }
        }
        else
        {
            add(static_cast<size_t>(d.label));
        }
    };
    sc.detStart.assign(nLabels + 1, 0);
    for (uint32_t j = 0; j < nd; j++)
    {
        labelsOf(sc.dets[j], [&](size_t l) { sc.detStart[l + 1]++; });
    }
    for (size_t l = 0; l < nLabels; l++)
    {
        sc.detStart[l + 1] += sc.detStart[l];
    }
    sc.detByLabel.resize(sc.detStart[nLabels]);
    auto& fill = sc.detFill;
    fill.assign(sc.detStart.begin(), sc.detStart.end() - 1);
    for (uint32_t j = 0; j < nd; j++)
    {
        labelsOf(sc.dets[j], [&](size_t l) { sc.detByLabel[fill[l]++] = j; });
    }
    size_t slotCount = 0;
    for (size_t l = 0; l < nLabels; l++)
    {
        slotCount = std::max<size_t>(slotCount, sc.detStart[l + 1] - sc.detStart[l]);
    }
    // The padding: an infinite range fails the range gate.
    const Slot none{{kInf, 0, 0, -1, -1}, 0};
    sc.slotCount = slotCount;
    sc.slots.assign(nLabels * slotCount, none);
    for (size_t l = 0; l < nLabels; l++)
    {
        for (uint32_t i = sc.detStart[l]; i < sc.detStart[l + 1]; i++)
        {
            const uint32_t j = sc.detByLabel[i];
            sc.slots[l * slotCount + (i - sc.detStart[l])] = {sc.dets[j], j};
        }
    }
    const double reach = k.ir > 0 ? std::sqrt(std::max(0.0, k.budget)) / k.ir : kInf;
    sc.gateLo2.assign(nLabels, kInf);
    sc.gateHi2.assign(nLabels, -kInf);
    for (size_t l = 0; l < nLabels; l++)
    {
        for (uint32_t i = sc.detStart[l]; i < sc.detStart[l + 1]; i++)
        {
            const double r = sc.dets[sc.detByLabel[i]].r;
            const double lo = std::max(0.0, (r - reach) * (1 - 1e-9) - 1e-9);
            const double hi = (r + reach) * (1 + 1e-9) + 1e-9;
            sc.gateLo2[l] = std::min(sc.gateLo2[l], lo * lo * (1 - 1e-9));
            sc.gateHi2[l] = std::max(sc.gateHi2[l], hi * hi * (1 + 1e-9));
        }
    }
    planRangeBins(sc, nLabels, reach);
}

/** The exact gates of the pair (detection d, visible object at (lx, ly) in the sensor frame,
 *  range r): `k.budget` bounds what the two Gaussian terms may cost for its gain to stay
 *  positive, so (dr/sigma_r)^2 <= budget and |dtheta| <= sigma_theta sqrt(budget) are
 *  necessary conditions, checked before any atan2 (most candidates fail them); the bearing
 *  one as u . v >= cos(max dtheta) |v| with the detection's unit vector u. Branch-free. */
inline bool passesGates(const Det& d, double r, double lx, double ly, double ir, double budget,
                        double cosGate)
{
    const double dr = d.r - r;
    const double dot = d.uc * lx + d.us * ly;
    return ((dr * ir) * (dr * ir) <= budget) & (dot >= cosGate * r);
}

/** The id test of a pair: a detection naming an object (`fixed` >= 0) pairs with it only. */
inline bool namesOrAny(int32_t fixed, int32_t sorted)
{
    return (fixed < 0) | (fixed == sorted);
}

/** True if a detection names an object (then the gates need the id test). */
bool anyNamed(const Scratch& sc)
{
    return std::any_of(sc.dets.begin(), sc.dets.end(), [](const Det& d) { return d.fixed >= 0; });
}

/** |bearing difference| of detection d and the object at (lx, ly): |atan2(u x v, u . v)| of
 *  the detection's unit vector u and the object's direction v, exact, no angle wrapping
 *  (the models use its square only; gated pairs are within 45 degrees: the short path). */
inline double absBearingDiff(const Det& d, double lx, double ly)
{
    return detail::fastAbsAtan2(d.uc * ly - d.us * lx, d.uc * lx + d.us * ly);
}

/** absBearingDiff of two pairs at once (d0 with the object at (lx0, ly0), d1 with
 *  (lx1, ly1)): the same operations lane by lane, so the same bits. */
inline Vec2 absBearingDiff2(const Det& d0, double lx0, double ly0, const Det& d1, double lx1,
                            double ly1)
{
    const Vec2 uc{d0.uc, d1.uc}, us{d0.us, d1.us}, lx{lx0, lx1}, ly{ly0, ly1};
    return detail::fastAbsAtan2x2(uc * ly - us * lx, uc * lx + us * ly);
}

/** Lowest value returned: keeps MRPT's finite-likelihood assertion true even if an
 *  extreme option set ever made the sum overflow. */
constexpr double kMinLogLik = -1e300;

double finite(double v)
{
    return std::isfinite(v) ? v : kMinLogLik;
}

/** Most pairs of a particle whose q totalsBlock folds into the product: q^8 >= 1e-48. */
constexpr uint32_t kFoldPairs = 8;

/** scorePaperBlock's q of a particle whose pose is not finite. */
constexpr uint32_t kNoPose = std::numeric_limits<uint32_t>::max();

/** The paper likelihood of the m particles of a block (sensor geometry geoms[i] of pose
 *  poses[i]) into out[0..m), in stages that each run over the whole block: z^k of every
 *  particle and its objects that may pair (label's range hull); those objects in the
 *  sensor frame and against the exact gates (passesGates) for every detection of their
 *  label; atan2 and gain of the pairs that pass; the assignments. Most of the time of a
 *  particle was spent waiting on short dependent chains (sqrt, then the gates, atan2, the
 *  gain) and on the branches that test them; one stage at a time, the chains of
 *  successive particles overlap. A particle's value depends on its own arithmetic only, so
 *  not on the block (n = 1 takes this path too). The order in which pairs are collected does
 *  not matter: assignGreedy() sorts them by (gain, j, v).
 */
void scorePaperBlock(const CSemanticMap::Index& ix, const ModelConsts& k, Scratch& sc,
                     const Geom* geoms, const TPose2D* poses, size_t m, double* out)
{
    const size_t nd = sc.dets.size(), ns = sc.slotCount;
    const double ir = k.ir, ib = k.ib, logPu = k.logPu, maxBudget = k.budget, cosGate = k.cosGate;
    const double* X = ix.x.data();
    const double* Y = ix.y.data();
    const int32_t* L = ix.label.data();
    const double* lo2 = sc.gateLo2.data();
    const double* hi2 = sc.gateHi2.data();
    for (auto* v : {&sc.blockVis, &sc.pairCount})  // each: the probabilistic block sizes one
    {
        if (v->size() < m)
        {
            v->resize(m);
        }
    }
    uint32_t* blockVis = sc.blockVis.data();
    uint32_t* pairCount = sc.pairCount.data();
    uint8_t* used = nullptr;
    // z^k of every particle (q = blockVis[i]) and the visible objects that may pair.
    size_t ne = 0;
    for (uint32_t i = 0; i < m; i++)
    {
        blockVis[i] = kNoPose;
        pairCount[i] = 0;
        if (!finitePose(poses[i]))
        {
            continue;
        }
        const Geom& g = geoms[i];
        predictVisible(ix, g, sc);
        const auto nv = static_cast<uint32_t>(visibleCount(sc));
        blockVis[i] = nv;
        if (nd == 0)
        {
            continue;
        }
        if (sc.gated.size() < ne + nv)
        {
            sc.gated.resize(2 * (ne + nv));
        }
        const uint32_t* hit = sc.hits.data();
        const double* hitD2 = sc.hitD2.data();
        Gated* gated = sc.gated.data();
        for (uint32_t v = 0; v < nv; v++)
        {
            const uint32_t kk = hit[v];
            const auto l = static_cast<size_t>(L[kk]);
            const double d2 = hitD2[v];
            // Written always, kept only if it may pair.
            gated[ne].o.sorted = static_cast<int32_t>(kk);
            gated[ne].p = i;
            gated[ne].v = v;
            ne += static_cast<size_t>((d2 >= lo2[l]) & (d2 <= hi2[l]));
        }
    }
    // Those objects in the sensor frame, and every (object, detection of its label) against
    // the exact range and bearing gates, branch-free: each object tests
    // slotCount detections, the same number for every particle of the call.
    if (sc.cands.size() < ne * ns)
    {
        sc.cands.resize(2 * ne * ns);
    }
    Gated* gated = sc.gated.data();
    Cand* cands = sc.cands.data();
    const Slot* slots = sc.slots.data();
    size_t nc = 0;
    // Without detections naming an object (the usual case), no id test.
    const bool anyFixed = anyNamed(sc);
    auto gate = [&](auto idTest)
    {
        for (uint32_t e = 0; e < ne; e++)
        {
            Vis& o = gated[e].o;
            const Geom& g = geoms[gated[e].p];
            const auto kk = static_cast<size_t>(o.sorted);
            const double dx = X[kk] - g.sx, dy = Y[kk] - g.sy;
            o.lx = g.c * dx + g.s * dy;
            o.ly = -g.s * dx + g.c * dy;
            o.d2 = dx * dx + dy * dy;
            o.label = L[kk];
            o.r = std::sqrt(o.d2);
            const Slot* sl = slots + static_cast<size_t>(o.label) * ns;
            for (size_t t = 0; t < ns; t++)
            {
                const Det& d = sl[t].d;
                cands[nc] = {sl[t].j, e};  // written always, kept if it passes
                // Both tests evaluated, without a branch.
                nc += static_cast<size_t>(
                    static_cast<int>(passesGates(d, o.r, o.lx, o.ly, ir, maxBudget, cosGate)) &
                    static_cast<int>(idTest(d.fixed, o.sorted)));
            }
        }
    };
    if (anyFixed)
    {
        gate(namesOrAny);
    }
    else
    {
        gate([](int32_t, int32_t) { return true; });
    }
    // atan2 and gain of the candidates: the pairs, in particle order.
    if (sc.pairs.size() < nc + 1)
    {
        sc.pairs.resize(2 * nc + 1);  // at least one: read (not used) when a particle has none
    }
    Pair* pairs = sc.pairs.data();
    used = sc.used.data();  // sized by predictVisible()
    const Det* dets = sc.dets.data();
    size_t np = 0;
    for (size_t t = 0; t < nc; t++)
    {
        const Det& d = dets[cands[t].j];
        const Gated& q = gated[cands[t].e];
        const double dr = d.r - q.o.r;
        const double db = absBearingDiff(d, q.o.lx, q.o.ly);
        const double gain = -0.5 * (dr * ir) * (dr * ir) - 0.5 * (db * ib) * (db * ib) - 2 * logPu;
        pairs[np] = {gain, cands[t].j, q.v};  // written always, kept if it gains
        pairCount[q.p] += static_cast<uint32_t>(gain > 0);
        np += static_cast<size_t>(gain > 0);
    }
    // sum(s_i) + d log p_u  with d = q + l - 2m  ==  (q + l) log p_u + sum(gain_i)
    size_t t = 0;
    for (uint32_t i = 0; i < m; i++)
    {
        const uint32_t c = pairCount[i];
        const double gains =
            c <= 1 ? (c == 0 ? 0.0 : pairs[t].gain) : assignGreedy(pairs + t, c, nd, used);
        t += c;
        out[i] = blockVis[i] == kNoPose
                     ? kMinLogLik
                     : finite(static_cast<double>(nd + blockVis[i]) * logPu + gains);
    }
}

/** Stage 1 of scoreProbabilisticBlock: z^k of particles [0, m) one after the other
 *  (entries e of the block: sorted index, particle, squared range, sensor-frame position)
 *  and per particle its q (kNoPose if its pose is not finite) and first entry. Returns the
 *  number of entries. */
size_t scanBlock(const CSemanticMap::Index& ix, Scratch& sc, const Geom* geoms,
                 const TPose2D* poses, size_t m)
{
    const size_t nObj = ix.x.size();
    uint32_t* blockVis = sc.blockVis.data();
    uint32_t* visStart = sc.visStart.data();
    size_t ne = 0;
    // The table lists of kSub particles first (independent chains of conversions, a
    // division and loads the CPU overlaps across particles), then their scans.
    constexpr uint32_t kSub = 64;
    ListRange lists[kSub];
    for (uint32_t i = 0; i < m; i++)
    {
        if (i % kSub == 0)
        {
            for (uint32_t u = i; u < std::min<uint32_t>(m, i + kSub); u++)
            {
                lists[u - i] = listOf(sc.vis, geoms[u]);
            }
        }
        blockVis[i] = kNoPose;
        visStart[i] = static_cast<uint32_t>(ne);
        if (!finitePose(poses[i]))
        {
            continue;
        }
        if (sc.bHit.size() < ne + nObj + 2)
        {
            const size_t cap = 2 * (ne + nObj + 2);
            sc.bHit.resize(cap);
            sc.bPart.resize(cap);
            for (auto* v : {&sc.bD2, &sc.bLx, &sc.bLy, &sc.bR, &sc.bPd})
            {
                v->resize(cap);
            }
        }
        const auto nv = static_cast<uint32_t>(
            scanVisible<true>(ix, geoms[i],
                              {sc.bHit.data() + ne, sc.bD2.data() + ne, sc.bLx.data() + ne,
                               sc.bLy.data() + ne, sc.bPart.data() + ne, i},
                              sc.vis, lists[i % kSub]));
        blockVis[i] = nv;
        ne += nv;
    }
    return ne;
}

/** Stage 2: the ranges of the ne entries and their P_D(rho), clamped inside (0, 1), two at
 *  a time (the arrays have room for the pair's second lane). */
void rangesBlock(Scratch& sc, size_t ne, const CSemanticMap::TLikelihoodOptions& opt, double R)
{
    const double* D2 = sc.bD2.data();
    double* RR = sc.bR.data();
    double* PD = sc.bPd.data();
    const double pNear = opt.p_detect_near, slope = opt.p_detect_far - opt.p_detect_near;
#if defined(SEMLOC_FASTMATH_SSE2)
    const __m128d vnear = _mm_set1_pd(pNear), vslope = _mm_set1_pd(slope), vR = _mm_set1_pd(R),
                  lo = _mm_set1_pd(1e-6), hi = _mm_set1_pd(1 - 1e-6);
    for (size_t e = 0; e < ne; e += 2)
    {
        const __m128d r = _mm_sqrt_pd(_mm_loadu_pd(D2 + e));
        const __m128d p = _mm_add_pd(vnear, _mm_mul_pd(vslope, _mm_div_pd(r, vR)));
        _mm_storeu_pd(RR + e, r);
        _mm_storeu_pd(PD + e, _mm_max_pd(_mm_min_pd(p, hi), lo));  // = std::clamp: p is finite
    }
#else
    for (size_t e = 0; e < ne; e++)
    {
        RR[e] = std::sqrt(D2[e]);
        PD[e] = std::clamp(pNear + slope * (RR[e] / R), 1e-6, 1 - 1e-6);
    }
#endif
}

/** Stage 2b: per particle, the product of 1 - P_D over its visible objects in sc.bMiss and
 *  -lambda + l log kappa in sc.bBase, one flat loop over the entries (no loop per particle
 *  whose length changes at random). Each factor is >= 1e-6: a product below 1e-250 is
 *  folded into bBase as its log before it could underflow. */
void missBlock(Scratch& sc, const ModelConsts& k, size_t m, size_t ne)
{
    for (auto* v : {&sc.bMiss, &sc.bBase})
    {
        if (v->size() < m)
        {
            v->resize(m);
        }
    }
    double* miss = sc.bMiss.data();
    double* base = sc.bBase.data();
    std::fill(miss, miss + m, 1.0);
    std::fill(base, base + m, -k.lambda + static_cast<double>(sc.dets.size()) * k.logKappa);
    const uint32_t* part = sc.bPart.data();
    const double* PD = sc.bPd.data();
    for (size_t e = 0; e < ne; e++)
    {
        const uint32_t i = part[e];
        double v = miss[i] * (1 - PD[e]);
        if (v < 1e-250)
        {
            base[i] += std::log(v);
            v = 1;
        }
        miss[i] = v;
    }
}

/** Stage 3: every (entry, detection slot of its label in its range bin) against the exact
 *  gates, branch-free, into sc.cands; returns how many pass. When no bin holds more than
 *  kMaxTaskSpan slots, the pairs to test are listed first (each entry writes that many,
 *  keeps those inside its bin) and tested in one flat loop: no inner loop whose length
 *  (0, 1, 2... slots) changes at random from one object to the next. Same pairs, same order. */
constexpr size_t kMaxTaskSpan = 4;

size_t gateBlock(const CSemanticMap::Index& ix, Scratch& sc, const ModelConsts& k, size_t ne)
{
    const size_t span = std::max<size_t>(1, sc.maxSpan);
    if (sc.cands.size() < ne * span + 1)
    {
        sc.cands.resize(2 * ne * span + 1);
    }
    const uint32_t* hit = sc.bHit.data();
    const double* RR = sc.bR.data();
    const double* LX = sc.bLx.data();
    const double* LY = sc.bLy.data();
    const int32_t* L = ix.label.data();
    Cand* cands = sc.cands.data();
    const Slot* slots = sc.slots.data();
    const uint32_t* binSpan = sc.binSpan.data();
    const size_t nb = sc.binCount;
    const double binInv = sc.binInv, lastBin = static_cast<double>(nb - 1);
    const double ir = k.ir, budget = k.budget, cosGate = k.cosGate;
    auto spanOf = [&](uint32_t e)
    {
        const auto b = static_cast<size_t>(std::min(RR[e] * binInv, lastBin));
        return binSpan + 2 * (static_cast<size_t>(L[hit[e]]) * nb + b);
    };
    size_t nc = 0;
    // The pair (slot t, entry e) into cands, kept if it passes.
    auto test = [&](auto idTest, uint32_t t, uint32_t e)
    {
        const Det& d = slots[t].d;
        cands[nc] = {slots[t].j, e};  // written always, kept if it passes
        nc += static_cast<size_t>(
            static_cast<int>(passesGates(d, RR[e], LX[e], LY[e], ir, budget, cosGate)) &
            static_cast<int>(idTest(d.fixed, static_cast<int32_t>(hit[e]))));
    };
    auto listed = [&](auto idTest, auto spanC)
    {
        constexpr uint32_t S = decltype(spanC)::value;
        if (sc.tasks.size() < ne * S + S)
        {
            sc.tasks.resize(2 * (ne * S + S));
        }
        Cand* tasks = sc.tasks.data();
        size_t nt = 0;
        for (uint32_t e = 0; e < ne; e++)
        {
            const uint32_t* sp = spanOf(e);
            const uint32_t a = sp[0], cnt = sp[1] - sp[0];
            for (uint32_t u = 0; u < S; u++)
            {
                tasks[nt] = {a + u, e};  // written always, kept if inside the bin
                nt += static_cast<size_t>(u < cnt);
            }
        }
        for (size_t t = 0; t < nt; t++)
        {
            test(idTest, tasks[t].j, tasks[t].e);
        }
    };
    auto gate = [&](auto idTest)
    {
        switch (sc.maxSpan)
        {
            case 0:
                return;  // no slot in any bin: no pair
            case 1:
                return listed(idTest, std::integral_constant<uint32_t, 1>());
            case 2:
                return listed(idTest, std::integral_constant<uint32_t, 2>());
            case 3:
                return listed(idTest, std::integral_constant<uint32_t, 3>());
            case kMaxTaskSpan:
                return listed(idTest, std::integral_constant<uint32_t, kMaxTaskSpan>());
            default:
                break;
        }
        for (uint32_t e = 0; e < ne; e++)
        {
            const uint32_t* sp = spanOf(e);
            for (uint32_t t = sp[0]; t < sp[1]; t++)
            {
                test(idTest, t, e);
            }
        }
    };
    if (anyNamed(sc))
    {
        gate(namesOrAny);
    }
    else
    {
        gate([](int32_t, int32_t) { return true; });
    }
    return nc;
}

/** The gain of matching detection j with entry e, less log(P_D / (1 - P_D)): the label term,
 *  the Gaussians' normalisation and costs, and the clutter density the detection no longer
 *  needs. */
struct GainParts
{
    const Det* dets;
    const uint32_t* hit;
    const double *RR, *LX, *LY;
    const int32_t* L;
    /** With db = absBearingDiff(dets[j], LX[e], LY[e]). */
    double rest(const ModelConsts& k, uint32_t j, uint32_t e, double db) const
    {
        const Det& d = dets[j];
        const double dr = d.r - RR[e];
        double logC = 0;  // landmarks without a label: no label term
        if (d.label >= 0)
        {
            logC = (d.label == L[hit[e]]) ? k.logSame : k.logOther;
        }
        return logC + k.logNorm - 0.5 * (dr * k.ir) * (dr * k.ir) -
               0.5 * (db * k.ib) * (db * k.ib) - k.logKappa;
    }
};

GainParts gainParts(const CSemanticMap::Index& ix, const Scratch& sc)
{
    return {sc.dets.data(), sc.bHit.data(), sc.bR.data(),
            sc.bLx.data(),  sc.bLy.data(),  ix.label.data()};
}

/** A candidate pair's gain less log q, q = P_D / (1 - P_D), and whether its gain is
 *  positive: decided without log q when log q's range over the FOV decides it by more than
 *  1e-9 (rounding: ~1e-14), else with log q: the same pairs as gain = log q + rest > 0. */
struct PairGain
{
    double rest, q;
    bool gains;
};

PairGain pairGain(const ModelConsts& k, double rest, double q)
{
    PairGain g;
    g.rest = rest;
    g.q = q;
    g.gains = g.rest + k.logQLo > 0;
    if (!g.gains && g.rest + k.logQHi >= 0)
    {
        g.gains = std::log(g.q) + g.rest > 0;
    }
    return g;
}

/** q = P_D / (1 - P_D) of a P_D (or two) clamped inside (0, 1). */
template <typename T>
inline T detectionOdds(T pd)
{
    return pd / (1.0 - pd);
}

/** Stage 4: the gains of the nc candidates; those with a positive gain are the pairs, in
 *  particle order (sc.pairs, sc.pairCount[i] of particle i), each with its gain less log q
 *  and its q. Branch-free but for pairGain's rare log. The bearing differences and the q of
 *  two candidates at a time (one division and one atan polynomial chain for both, the same
 *  bits as one at a time): their latency was much of this loop's time at steps with several
 *  pairs per particle. */
void gainBlock(const CSemanticMap::Index& ix, Scratch& sc, const ModelConsts& k, size_t m,
               size_t nc)
{
    if (sc.pairs.size() < nc + 1)
    {
        sc.pairs.resize(2 * nc + 1);  // at least one: read (not used) when a particle has none
    }
    const Cand* cands = sc.cands.data();
    const uint32_t* part = sc.bPart.data();
    const uint32_t* visStart = sc.visStart.data();
    const double* PD = sc.bPd.data();
    const GainParts gp = gainParts(ix, sc);
    Pair* pairs = sc.pairs.data();
    uint32_t* pairCount = sc.pairCount.data();
    std::fill(pairCount, pairCount + m, 0u);
    size_t np = 0;
    auto emit = [&](const Cand& c, double db, double q)
    {
        const uint32_t i = part[c.e];
        const PairGain g = pairGain(k, gp.rest(k, c.j, c.e, db), q);
        pairs[np] = {g.rest, c.j, c.e - visStart[i], g.q};  // written always, kept if it gains
        pairCount[i] += static_cast<uint32_t>(g.gains);
        np += static_cast<size_t>(g.gains);
    };
    const double* LX = gp.LX;
    const double* LY = gp.LY;
    size_t t = 0;
    for (; t + 1 < nc; t += 2)
    {
        const Cand c0 = cands[t], c1 = cands[t + 1];
        const Det& d0 = gp.dets[c0.j];
        const Det& d1 = gp.dets[c1.j];
        const Vec2 db = absBearingDiff2(d0, LX[c0.e], LY[c0.e], d1, LX[c1.e], LY[c1.e]);
        const Vec2 pd{PD[c0.e], PD[c1.e]};
        const Vec2 q = detectionOdds(pd);
        emit(c0, db[0], q[0]);
        emit(c1, db[1], q[1]);
    }
    if (t < nc)
    {
        const Cand c = cands[t];
        emit(c, absBearingDiff(gp.dets[c.j], LX[c.e], LY[c.e]), detectionOdds(PD[c.e]));
    }
}

/** True if the c pairs (of one particle, in candidate order: an object's pairs are
 *  consecutive) share no detection and no object, so the greedy assignment takes them all;
 *  false also for more than kFoldPairs pairs or detections beyond 64. */
bool disjointPairs(const Pair* pairs, size_t c)
{
    if (c > kFoldPairs)
    {
        return false;
    }
    uint64_t dets = 0;
    bool ok = true;
    for (size_t u = 0; u < c; u++)
    {
        const uint64_t bit = uint64_t{1} << (pairs[u].j & 63u);
        ok &= pairs[u].j < 64 && (dets & bit) == 0 && (u == 0 || pairs[u].v != pairs[u - 1].v);
        dets |= bit;
    }
    return ok;
}

/** Stage 5: per particle, missBlock's terms (sum_v log(1 - P_D(rho_v)) as the log of the
 *  product: one log instead of one per visible object) and the association. Pairs that
 *  share no detection and no object are all taken by the greedy assignment: up to
 *  kFoldPairs of them, their q join the product (one log for the particle) and their gains
 *  less log q are summed in pair order; otherwise each pair's gain log q + rest goes to the
 *  assignment. */
void totalsBlock(Scratch& sc, size_t m, double* out)
{
    const size_t nd = sc.dets.size();
    const uint32_t* blockVis = sc.blockVis.data();
    const uint32_t* pairCount = sc.pairCount.data();
    const double* bMiss = sc.bMiss.data();
    const double* bBase = sc.bBase.data();
    Pair* pairs = sc.pairs.data();
    uint8_t* used = sc.used.data();
    size_t t = 0;
    for (uint32_t i = 0; i < m; i++)
    {
        if (blockVis[i] == kNoPose)
        {
            out[i] = kMinLogLik;
            continue;
        }
        const uint32_t c = pairCount[i];
        double miss = bMiss[i];
        double gains = 0;
        if (disjointPairs(pairs + t, c))
        {
            // q in [1e-6, 1e6]: a product >= 1e-250 times q^c (c <= 8) stays a normal number.
            double qProd = 1;
            for (size_t u = t; u < t + c; u++)
            {
                gains += pairs[u].gain;
                qProd *= pairs[u].q;
            }
            miss *= qProd;
        }
        else
        {
            for (size_t u = t; u < t + c; u++)
            {
                pairs[u].gain += std::log(pairs[u].q);
            }
            gains = assignGreedy(pairs + t, c, nd, used);
        }
        t += c;
        out[i] = finite(bBase[i] + std::log(miss) + gains);
    }
}

/** The probabilistic likelihood of the m particles of a block (sensor geometry geoms[i] of
 *  pose poses[i], range R) into out[0..m), in stages over the whole block as in
 *  scorePaperBlock (above). With class confusion every detection is a slot of every label
 *  (planPairs). A particle's value depends on its own arithmetic only, so not on the block
 *  (n = 1 takes this path too). */
void scoreProbabilisticBlock(const CSemanticMap::Index& ix,
                             const CSemanticMap::TLikelihoodOptions& opt, const ModelConsts& k,
                             Scratch& sc, const Geom* geoms, const TPose2D* poses, size_t m,
                             double* out)
{
    for (auto* v : {&sc.blockVis, &sc.pairCount, &sc.visStart})  // shared with the paper block
    {
        if (v->size() < m)
        {
            v->resize(m);
        }
    }
    if (sc.used.size() < sc.dets.size() + ix.x.size())
    {
        sc.used.resize(sc.dets.size() + ix.x.size(), 0);
    }
    const size_t ne = scanBlock(ix, sc, geoms, poses, m);
    if (m > 0)
    {
        rangesBlock(sc, ne, opt, geoms[0].R);
    }
    missBlock(sc, k, m, ne);
    const size_t nc = gateBlock(ix, sc, k, ne);
    gainBlock(ix, sc, k, m, nc);
    totalsBlock(sc, m, out);
}

/** What a likelihood call knows of the sensor, fixed for all particles of a step. */
struct Sensor
{
    bool usable = false;  // false: nothing to score, every particle gets 0
    double R = 0, fov = 0, ox = 0, oy = 0, oyaw = 0;
};

Sensor sensorOf(double R, double fov, const mrpt::poses::CPose3D& onVehicle)
{
    Sensor s;
    s.R = R;
    s.fov = fov;
    s.usable = R > 0 && std::isfinite(R) && fov > 0 && std::isfinite(fov);
    s.ox = onVehicle.x();
    s.oy = onVehicle.y();
    s.oyaw = onVehicle.yaw();
    return s;
}

/** Fills sc.dets with the detections the likelihood uses (once per observation). */
Sensor prepare(const CObservationSemantic& obs, const CSemanticMap::TLikelihoodOptions& lo,
               const CSemanticMap::Index& ix, const LabelIndex& labels, Scratch& sc)
{
    const double R = lo.max_range_m > 0 ? lo.max_range_m : obs.maxRange_m;
    const double fov = lo.fov_deg > 0 ? lo.fov_deg * M_PI / 180.0 : obs.fov_rad;
    const Sensor s = sensorOf(R, fov, obs.sensorPose);
    sc.dets.clear();
    if (!s.usable)
    {
        return s;
    }
    for (const auto& d : obs.detections)
    {
        if (!CObservationSemantic::isValid(d, R, fov) || d.confidence < lo.min_confidence)
        {
            continue;
        }
        int32_t fixed = -1;
        if (d.object_id >= 0)
        {
            const auto it = ix.idToSorted.find(d.object_id);
            fixed = it == ix.idToSorted.end() ? -1 : it->second;
        }
        const int32_t label = labels.find(d.label);
        if (fixed < 0 && label < 0)
        {
            continue;  // unknown to the map: a constant factor at every particle
        }
        sc.dets.push_back(makeDet(d.range_m, d.bearing_rad, label, fixed));
    }
    return s;
}

Sensor prepare(const mrpt::obs::CObservationBearingRange& obs,
               const CSemanticMap::TLikelihoodOptions& lo, const CSemanticMap::Index& ix,
               const LabelIndex&, Scratch& sc)
{
    const double R = lo.max_range_m > 0 ? lo.max_range_m : obs.maxSensorDistance;
    double fov =
        lo.fov_deg > 0 ? lo.fov_deg * M_PI / 180.0 : static_cast<double>(obs.fieldOfView_yaw);
    if (fov == 0)
    {
        fov = 2 * M_PI;  // MRPT leaves it 0 when the sensor has no FOV limit
    }
    const Sensor s = sensorOf(R, fov, obs.sensorLocationOnRobot);
    sc.dets.clear();
    if (!s.usable)
    {
        return s;
    }
    for (const auto& m : obs.sensedData)
    {
        const double r = m.range, b = m.yaw;
        if (!(r >= 0 && r <= R) || !(std::abs(b) <= 4 * M_PI) ||
            std::abs(wrapBearing(b)) > 0.5 * fov + 1e-9)
        {
            continue;
        }
        int32_t fixed = -1;
        if (m.landmarkID >= 0)
        {
            const auto it = ix.idToSorted.find(m.landmarkID);
            if (it == ix.idToSorted.end())
            {
                continue;  // an id the map does not have
            }
            fixed = it->second;
        }
        sc.dets.push_back(makeDet(r, b, -1, fixed));
    }
    return s;
}

}  // namespace

template <typename OBS>
void CSemanticMap::logLikelihoods(const OBS& obs, const TPose2D* poses, size_t n, double* out) const
{
    Scratch& sc = scratch();
    const Sensor s = prepare(obs, likelihoodOptions, *m_index, *m_labels, sc);
    const size_t nLabels = m_labels->size();
    const ModelConsts k =
        s.usable ? cachedModelConsts(likelihoodOptions, nLabels, s.R, s.fov, sc) : ModelConsts();
    // MRPT's per-particle path makes one call per particle with the same observation: the
    // plan is then the last call's (same detections, index build and constants).
    const std::array<double, 4> planKey = {static_cast<double>(m_index->stamp),
                                           static_cast<double>(nLabels), k.budget, k.ir};
    auto sameDet = [](const Det& a, const Det& b) {
        return a.r == b.r && a.uc == b.uc && a.us == b.us && a.label == b.label &&
               a.fixed == b.fixed;
    };
    if (!sc.planValid || planKey != sc.planKey || k.confusable != sc.planConfusable ||
        !std::equal(sc.dets.begin(), sc.dets.end(), sc.planDets.begin(), sc.planDets.end(),
                    sameDet))
    {
        planPairs(sc, *m_index, nLabels, k);
        sc.planKey = planKey;
        sc.planConfusable = k.confusable;
        sc.planDets = sc.dets;
        sc.planValid = true;
    }
    if (!s.usable)
    {
        std::fill(out, out + n, 0.0);  // nothing usable: uninformative, the same everywhere
        return;
    }
    // The sensor geometry of every particle of a block first (independent short chains the
    // CPU overlaps across particles), then the matching, which reads it.
    sc.vis = visTableFor(*m_index, s.R, s.fov, sc);
    constexpr size_t kBlock = 256;
    Geom geoms[kBlock];
    const GeomConsts gc = geomConsts(sc, s.ox, s.oy, s.oyaw, s.R, s.fov);
    for (size_t i0 = 0; i0 < n; i0 += kBlock)
    {
        const size_t m = std::min(kBlock, n - i0);
        // The headings' sin and cos two at a time (the same bits as one at a time).
        detail::forEachSinCos(
            m, [&](size_t i) { return poses[i0 + i].phi; },
            [&](size_t i, double sp, double cp)
            { geoms[i] = makeGeom(gc, poses[i0 + i], sp, cp); });
        if (likelihoodOptions.model == Model::Paper)
        {
            scorePaperBlock(*m_index, k, sc, geoms, poses + i0, m, out + i0);
            continue;
        }
        scoreProbabilisticBlock(*m_index, likelihoodOptions, k, sc, geoms, poses + i0, m, out + i0);
    }
}

double CSemanticMap::computeLogLikelihood(const CObservationSemantic& obs,
                                          const TPose2D& pose) const
{
    double ll = 0;
    logLikelihoods(obs, &pose, 1, &ll);
    return ll;
}

double CSemanticMap::computeLogLikelihood(const mrpt::obs::CObservationBearingRange& obs,
                                          const TPose2D& pose) const
{
    double ll = 0;
    logLikelihoods(obs, &pose, 1, &ll);
    return ll;
}

void CSemanticMap::computeLogLikelihoods(const CObservationSemantic& obs, const TPose2D* poses,
                                         size_t n, double* out) const
{
    logLikelihoods(obs, poses, n, out);
}

void CSemanticMap::computeLogLikelihoods(const mrpt::obs::CObservationBearingRange& obs,
                                         const TPose2D* poses, size_t n, double* out) const
{
    logLikelihoods(obs, poses, n, out);
}

CSemanticMap::TObservationCheck CSemanticMap::check(const CObservationSemantic& obs) const
{
    TObservationCheck c;
    for (const auto& d : obs.detections)
    {
        if (!isUsable(obs, d))
        {
            c.invalid++;
        }
        else if (m_labels->find(d.label) < 0 &&
                 (d.object_id < 0 || !m_index->idToSorted.count(d.object_id)))
        {
            c.unknown++;
        }
        else
        {
            c.used++;
        }
    }
    return c;
}

bool CSemanticMap::isUsable(const CObservationSemantic& obs, const TSemanticDetection& d) const
{
    const auto& lo = likelihoodOptions;
    const double R = lo.max_range_m > 0 ? lo.max_range_m : obs.maxRange_m;
    const double fov = lo.fov_deg > 0 ? lo.fov_deg * M_PI / 180.0 : obs.fov_rad;
    return CObservationSemantic::isValid(d, R, fov) && d.confidence >= lo.min_confidence;
}

std::vector<size_t> CSemanticMap::candidatesOf(const CObservationSemantic& obs,
                                               const TSemanticDetection& d) const
{
    std::vector<size_t> out;
    if (!isUsable(obs, d))
    {
        return out;
    }
    // As the likelihood associates: by id when the map knows it, else by label.
    if (d.object_id >= 0 && m_index->idToSorted.count(d.object_id))
    {
        for (size_t i = 0; i < m_objects.size(); i++)
        {
            if (m_objects[i].id == d.object_id)
            {
                out.push_back(i);
            }
        }
        return out;
    }
    for (size_t i = 0; i < m_objects.size(); i++)
    {
        if (m_objects[i].label == d.label)
        {
            out.push_back(i);
        }
    }
    return out;
}

bool CSemanticMap::internal_canComputeObservationLikelihood(
    const mrpt::obs::CObservation& obs) const
{
    return dynamic_cast<const CObservationSemantic*>(&obs) != nullptr ||
           dynamic_cast<const mrpt::obs::CObservationBearingRange*>(&obs) != nullptr;
}

double CSemanticMap::internal_computeObservationLikelihood(
    const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& takenFrom) const
{
    const TPose2D pose(takenFrom.x(), takenFrom.y(), takenFrom.yaw());
    if (const auto* o = dynamic_cast<const CObservationSemantic*>(&obs))
    {
        return computeLogLikelihood(*o, pose);
    }
    if (const auto* br = dynamic_cast<const mrpt::obs::CObservationBearingRange*>(&obs))
    {
        return computeLogLikelihood(*br, pose);
    }
    return 0;
}

// ------------------------------------------------------------------ insertion

bool CSemanticMap::internal_insertObservation(
    const mrpt::obs::CObservation& obs, const std::optional<const mrpt::poses::CPose3D>& robotPose)
{
    const mrpt::poses::CPose3D vehicle = robotPose ? *robotPose : mrpt::poses::CPose3D();
    struct NewDet
    {
        std::string label;
        int32_t id;
        double wx, wy;
    };
    std::vector<NewDet> news;
    auto toWorld = [&](const mrpt::poses::CPose3D& sensorOnVehicle, double r, double b)
    {
        const mrpt::poses::CPose3D s = vehicle + sensorOnVehicle;
        const double a = s.yaw() + b;
        return std::make_pair(s.x() + r * std::cos(a), s.y() + r * std::sin(a));
    };
    if (const auto* o = dynamic_cast<const CObservationSemantic*>(&obs))
    {
        for (const auto& d : o->detections)
        {
            if (!o->isValid(d) || d.confidence < likelihoodOptions.min_confidence)
            {
                continue;
            }
            const auto [wx, wy] = toWorld(o->sensorPose, d.range_m, d.bearing_rad);
            news.push_back({d.label, d.object_id, wx, wy});
        }
    }
    else if (const auto* br = dynamic_cast<const mrpt::obs::CObservationBearingRange*>(&obs))
    {
        for (const auto& m : br->sensedData)
        {
            if (!std::isfinite(m.range) || !std::isfinite(m.yaw) || m.range < 0)
            {
                continue;
            }
            const auto [wx, wy] = toWorld(br->sensorLocationOnRobot, m.range, m.yaw);
            news.push_back({insertionOptions.landmark_label, m.landmarkID, wx, wy});
        }
    }
    else
    {
        return false;
    }
    for (const auto& n : news)
    {
        // Merge into the object it names, else the nearest same-label object in reach.
        TObject* target = nullptr;
        if (n.id >= 0)
        {
            for (auto& ob : m_objects)
            {
                if (ob.id == n.id)
                {
                    target = &ob;
                }
            }
        }
        if (!target && n.id < 0)
        {
            double best = insertionOptions.merge_distance_m;
            for (auto& ob : m_objects)
            {
                const double dd = std::hypot(ob.x - n.wx, ob.y - n.wy);
                if (ob.label == n.label && dd <= best)
                {
                    best = dd;
                    target = &ob;
                }
            }
        }
        if (target)
        {
            // Running mean of the merged detections.
            const double k = 1.0 / (target->n_observations + 1.0);
            target->x += (n.wx - target->x) * k;
            target->y += (n.wy - target->y) * k;
            target->n_observations++;
        }
        else
        {
            TObject ob;
            ob.id = n.id > 0 ? n.id : nextFreeId();
            ob.label = n.label;
            ob.x = n.wx;
            ob.y = n.wy;
            ob.z = 0;
            m_objects.push_back(std::move(ob));
        }
    }
    rebuildIndex();
    return !news.empty();
}

// ------------------------------------------------------------------ I/O

uint8_t CSemanticMap::serializeGetVersion() const
{
    return 0;
}

void CSemanticMap::serializeTo(mrpt::serialization::CArchive& out) const
{
    // Nothing serializeFrom would refuse: checked before the first byte.
    for (const auto& o : m_objects)
    {
        if (const std::string p = labelLengthProblem(o.label); !p.empty())
        {
            THROW_EXCEPTION_FMT("CSemanticMap: cannot write object id %d: its %s", o.id, p.c_str());
        }
    }
    out << genericMapParams;
    out << m_hasBounds << m_bounds.x_min << m_bounds.x_max << m_bounds.y_min << m_bounds.y_max;
    out.WriteAs<uint32_t>(m_objects.size());
    for (const auto& o : m_objects)
    {
        out << o.id << o.label << o.x << o.y << o.z << o.extent_m << o.n_observations;
    }
}

void CSemanticMap::serializeFrom(mrpt::serialization::CArchive& in, uint8_t version)
{
    switch (version)
    {
        case 0:
        {
            // Read into locals: a throw leaves the map as it was, objects and index consistent.
            bool hasBounds = false;
            WorldBounds bounds;
            in >> genericMapParams;
            in >> hasBounds >> bounds.x_min >> bounds.x_max >> bounds.y_min >> bounds.y_max;
            const uint32_t n = detail::readCount(in, 1u << 24, "CSemanticMap objects");
            std::vector<TObject> objects;
            std::unordered_set<int32_t> ids;
            for (uint32_t i = 0; i < n; i++)
            {
                TObject o;
                in >> o.id;
                detail::readString(in, o.label, "CSemanticMap object label");
                in >> o.x >> o.y >> o.z >> o.extent_m >> o.n_observations;
                checkObject(o);
                if (!ids.insert(o.id).second)
                {
                    THROW_EXCEPTION_FMT("CSemanticMap: corrupted data: duplicate object id %d",
                                        o.id);
                }
                objects.push_back(std::move(o));
            }
            m_hasBounds = hasBounds;
            m_bounds = bounds;
            m_objects = std::move(objects);
            rebuildIndex();
            break;
        }
        default:
            MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
    }
}

void CSemanticMap::saveMetricMapRepresentationToFile(const std::string& prefix) const
{
    toWorld().saveToFile(prefix + "_semantic.yaml");
}

std::string CSemanticMap::asString() const
{
    return mrpt::format(
        "CSemanticMap: %u objects, %u labels, model '%s'", static_cast<unsigned>(m_objects.size()),
        static_cast<unsigned>(m_labels->size()), modelName(likelihoodOptions.model));
}

void CSemanticMap::getVisualizationInto(mrpt::opengl::CSetOfObjects& outObj) const
{
    if (!genericMapParams.enableSaveAs3DObject)
    {
        return;
    }
    for (const auto& o : m_objects)
    {
        // One stable colour per label.
        const int lab = m_labels->find(o.label);
        const float hue = static_cast<float>((lab * 0.618034) - std::floor(lab * 0.618034));
        const float r = std::max(0.2f, hue), g = std::max(0.2f, 1.0f - hue), b = 0.6f;
        const float rad = static_cast<float>(std::max(0.3, o.extent_m));
        auto cyl = mrpt::opengl::CCylinder::Create(rad, rad, 1.0f);
        cyl->setLocation(o.x, o.y, o.z);
        cyl->setColor(r, g, b);
        outObj.insert(cyl);
        auto txt = mrpt::opengl::CText::Create(o.label + " #" + std::to_string(o.id));
        txt->setLocation(o.x, o.y, o.z + 1.5);
        outObj.insert(txt);
    }
}

}  // namespace semloc
