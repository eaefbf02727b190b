/* semloc — CSemanticMap: the map of labelled objects (its definition for CMultiMetricMap,
 * options, objects, serialization and display). The likelihoods are in
 * SemanticMapLikelihood.cpp and the fast kernels behind SemanticLikelihoodKernels.h;
 * inserting observations in SemanticMapInsertion.cpp. */
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/format.h>
#include <mrpt/opengl/CCylinder.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/opengl/CText.h>
#include <mrpt/serialization/CArchive.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/models/semantic/DetectionProbability.h>
#include <semloc/observation/Labels.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <unordered_set>

#include "io/BoundedRead.h"
#include "io/ExactConfigWrite.h"
#include "models/semantic/LabelIndex.h"
#include "models/semantic/SemanticIndex.h"

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
/** Largest |coefficient| of range_bias_m accepted [m]. */
constexpr double kMaxRangeBias_m = 1e3;

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
    if (!(std::isfinite(o.sigma_m) && o.sigma_m >= 0 && o.sigma_m <= kMaxWorldCoordinate_m))
    {
        THROW_EXCEPTION_FMT("CSemanticMap: object id %d: sigma_m must be finite and >= 0", o.id);
    }
    if (!(o.p_exist > 0 && o.p_exist <= 1))
    {
        THROW_EXCEPTION_FMT("CSemanticMap: object id %d: p_exist must be in (0, 1]", o.id);
    }
    if (!(std::isfinite(o.scatter_m2) && o.scatter_m2 >= 0 &&
          std::isfinite(o.expected_detections) && o.expected_detections >= 0))
    {
        THROW_EXCEPTION_FMT("CSemanticMap: object id %d: bad insertion counts", o.id);
    }
    if (const std::string problem = classesProblem(o.classes, o.label); !problem.empty())
    {
        THROW_EXCEPTION_FMT("CSemanticMap: object id %d: classes: %s", o.id, problem.c_str());
    }
}
}  // namespace

config::TValueRange CSemanticMap::TLikelihoodOptions::range(const std::string& key)
{
    static const std::vector<std::pair<std::string, config::TValueRange>> kRanges = {
        {"sigma_range_m", {1e-6, 1e6}},
        {"sigma_bearing_deg", {1e-6, 360}},
        {"p_range_outlier", {0, 0.999999}},
        {"unmatched_penalty", {1e-12, 0.999999}},
        {"missed_object_penalty", {0, 1}},
        {"p_detect_near", {1e-6, 0.999999}},
        {"p_detect_far", {1e-6, 0.999999}},
        {"p_detect_edge_ratio", {0, 1}},
        {"clutter_per_scan", {1e-9, 1e6}},
        {"p_confusion", {0, 0.999999}},
        {"min_confidence", {0, 1}},
        {"max_range_m", {0, 1e6}},
        {"fov_deg", {0, 360}},
        {"index_cell_m", {0.01, 1e6}},
        {"outage_every_s", {0, 1e9}},
        {"outage_mean_s", {1e-3, 1e9}},
        {"lookalike_persistence", {0, 1}},
        {"lookalike_speed_mps", {0, 1e3}},
        {"lookalike_window_s", {1e-3, 3600}}};
    for (const auto& [k, r] : kRanges)
    {
        if (k == key)
        {
            return r;
        }
    }
    THROW_EXCEPTION("CSemanticMap::TLikelihoodOptions: '" + key + "' is not a numeric key");
}

double CSemanticMap::TLikelihoodOptions::correctedRange(double rho, double theta, double R,
                                                        double fov) const
{
    return rangeLessBias(detector.range_bias_m, rho, theta, R, fov);
}

void CSemanticMap::TLikelihoodOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                                          const std::string& s)
{
    config::rejectUnknownKeys(c, s, config::keysOf(*this));
    std::string m = modelName(model);
    config::readChoice(c, s, "model", m, {"paper", "probabilistic"});
    model = (m == "paper") ? Model::Paper : Model::Probabilistic;
    std::string a = probabilistic.association == Association::Marginal ? "marginal" : "greedy";
    config::readChoice(c, s, "association", a, {"greedy", "marginal"});
    probabilistic.association = (a == "marginal") ? Association::Marginal : Association::Greedy;
    if (probabilistic.association == Association::Marginal && model != Model::Probabilistic)
    {
        THROW_EXCEPTION(
            "ini [" + s +
            "] association: 'marginal' sums the probabilistic model over every "
            "association; set model = probabilistic (the paper model matches greedily)");
    }
    config::readDouble(c, s, "sigma_range_m", detector.sigma_range_m, range("sigma_range_m"));
    config::readDouble(c, s, "sigma_bearing_deg", detector.sigma_bearing_deg,
                       range("sigma_bearing_deg"));
    config::readDouble(c, s, "p_range_outlier", detector.p_range_outlier, range("p_range_outlier"));
    config::readDouble(c, s, "unmatched_penalty", paper.unmatched_penalty,
                       range("unmatched_penalty"));
    config::readDouble(c, s, "missed_object_penalty", paper.missed_object_penalty,
                       range("missed_object_penalty"));
    if (paper.missed_object_penalty > 0 && paper.missed_object_penalty < 1e-12)
    {
        THROW_EXCEPTION("ini [" + s +
                        "] missed_object_penalty: must be 0 (unmatched_penalty) or "
                        "at least 1e-12");
    }
    config::readDouble(c, s, "p_detect_near", probabilistic.p_detect_near, range("p_detect_near"));
    config::readDouble(c, s, "p_detect_far", probabilistic.p_detect_far, range("p_detect_far"));
    config::readDouble(c, s, "p_detect_edge_ratio", probabilistic.p_detect_edge_ratio,
                       range("p_detect_edge_ratio"));
    config::readDoubles(c, s, "range_bias_m", detector.range_bias_m, kRangeBiasTerms,
                        -kMaxRangeBias_m, kMaxRangeBias_m);
    if (std::all_of(detector.range_bias_m.begin(), detector.range_bias_m.end(),
                    [](double b) { return b == 0; }))
    {
        detector.range_bias_m.clear();  // none
    }
    config::readDouble(c, s, "clutter_per_scan", probabilistic.clutter_per_scan,
                       range("clutter_per_scan"));
    config::readDouble(c, s, "p_confusion", probabilistic.p_confusion, range("p_confusion"));
    config::readDouble(c, s, "min_confidence", detector.min_confidence, range("min_confidence"));
    config::readDouble(c, s, "max_range_m", detector.max_range_m, range("max_range_m"));
    config::readDouble(c, s, "fov_deg", detector.fov_deg, range("fov_deg"));
    config::readDouble(c, s, "index_cell_m", index_cell_m, range("index_cell_m"));
    config::readDouble(c, s, "outage_every_s", outage.outage_every_s, range("outage_every_s"));
    config::readDouble(c, s, "outage_mean_s", outage.outage_mean_s, range("outage_mean_s"));
    config::readDouble(c, s, "lookalike_persistence", lookalike.lookalike_persistence,
                       range("lookalike_persistence"));
    config::readDouble(c, s, "lookalike_speed_mps", lookalike.lookalike_speed_mps,
                       range("lookalike_speed_mps"));
    config::readDouble(c, s, "lookalike_window_s", lookalike.lookalike_window_s,
                       range("lookalike_window_s"));
    if (lookalike.lookalike_persistence > 0 && model != Model::Probabilistic)
    {
        THROW_EXCEPTION("ini [" + s +
                        "] lookalike_persistence: the look-alike model is part of the "
                        "probabilistic model; set model = probabilistic or "
                        "lookalike_persistence = 0");
    }
    if (outage.outage_every_s > 0 && model != Model::Probabilistic)
    {
        THROW_EXCEPTION("ini [" + s +
                        "] outage_every_s: the detector outage model is part of the "
                        "probabilistic model; set model = probabilistic or outage_every_s = 0");
    }
}

void CSemanticMap::TLikelihoodOptions::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                                        const std::string& s) const
{
    c.write(s, "model", std::string(modelName(model)), 24, 24, "paper | probabilistic");
    c.write(s, "association",
            std::string(probabilistic.association == Association::Marginal ? "marginal" : "greedy"),
            24, 24, "probabilistic: greedy (best association) | marginal (sum over all)");
    detail::writeExact(c, s, "sigma_range_m", detector.sigma_range_m, "range noise sigma_rho [m]");
    detail::writeExact(c, s, "sigma_bearing_deg", detector.sigma_bearing_deg,
                       "bearing noise sigma_theta [deg]");
    detail::writeExact(c, s, "p_range_outlier", detector.p_range_outlier,
                       "P(range misread: uniform over [0, max range]), [0,1)");
    detail::writeExact(c, s, "unmatched_penalty", paper.unmatched_penalty,
                       "paper: factor per object in one observation only, (0,1)");
    detail::writeExact(c, s, "missed_object_penalty", paper.missed_object_penalty,
                       "paper: factor per predicted object not detected; 0: unmatched_penalty");
    detail::writeExact(c, s, "p_detect_near", probabilistic.p_detect_near,
                       "probabilistic: P_D at range 0");
    detail::writeExact(c, s, "p_detect_far", probabilistic.p_detect_far,
                       "probabilistic: P_D at max range");
    detail::writeExact(c, s, "p_detect_edge_ratio", probabilistic.p_detect_edge_ratio,
                       "probabilistic: P_D at the edge of the view / on its axis");
    detail::writeExactList(c, s, "range_bias_m", detector.range_bias_m,
                           "range bias c0, c1, c2, c3 [m] in bearing / half the view");
    detail::writeExact(c, s, "clutter_per_scan", probabilistic.clutter_per_scan,
                       "probabilistic: mean false positives per scan");
    detail::writeExact(c, s, "p_confusion", probabilistic.p_confusion,
                       "probabilistic: P(wrong label)");
    detail::writeExact(c, s, "min_confidence", detector.min_confidence,
                       "ignore detections below this");
    detail::writeExact(c, s, "max_range_m", detector.max_range_m,
                       ">0 overrides the observation's max range");
    detail::writeExact(c, s, "fov_deg", detector.fov_deg,
                       ">0 overrides the observation's field of view");
    detail::writeExact(c, s, "index_cell_m", index_cell_m, "cell of the object index [m]");
    detail::writeExact(c, s, "outage_every_s", outage.outage_every_s,
                       "probabilistic: mean time between detector outages [s], 0 = none");
    detail::writeExact(c, s, "outage_mean_s", outage.outage_mean_s,
                       "probabilistic: mean length of an outage [s]");
    detail::writeExact(c, s, "lookalike_persistence", lookalike.lookalike_persistence,
                       "probabilistic: look-alikes' detections per scan after one, 0 = none");
    detail::writeExact(c, s, "lookalike_speed_mps", lookalike.lookalike_speed_mps,
                       "probabilistic: look-alikes' largest speed [m/s]");
    detail::writeExact(c, s, "lookalike_window_s", lookalike.lookalike_window_s,
                       "probabilistic: look-alikes' earlier detections kept [s]");
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

// ------------------------------------------------------------------ objects

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

size_t CSemanticMap::associationsApproximated() const
{
    return m_approximated.load();
}

void CSemanticMap::resetAssociationCount()
{
    m_approximated = 0;
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
        o.sigma_m = wo.sigma_m;
        o.p_exist = wo.p_exist;
        o.classes = wo.classes;
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
        wo.sigma_m = o.sigma_m;
        wo.p_exist = o.p_exist;
        wo.classes = o.classes;
        w.objects.push_back(std::move(wo));
    }
    return w;
}

// ------------------------------------------------------------------ I/O

uint8_t CSemanticMap::serializeGetVersion() const
{
    return 1;
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
        for (const auto& c : o.classes)
        {
            if (const std::string p = labelLengthProblem(c.first); !p.empty())
            {
                THROW_EXCEPTION_FMT("CSemanticMap: cannot write object id %d: a class's %s", o.id,
                                    p.c_str());
            }
        }
    }
    out << genericMapParams;
    out << m_hasBounds << m_bounds.x_min << m_bounds.x_max << m_bounds.y_min << m_bounds.y_max;
    out.WriteAs<uint32_t>(m_objects.size());
    for (const auto& o : m_objects)
    {
        out << o.id << o.label << o.x << o.y << o.z << o.extent_m << o.n_observations;
        // Version 1: how sure the map is of it, and the insertion's bookkeeping.
        out << o.sigma_m << o.p_exist << o.n_detected << o.scatter_m2 << o.n_in_view
            << o.expected_detections;
        out.WriteAs<uint32_t>(o.classes.size());
        for (const auto& [label, p] : o.classes)
        {
            out << label << p;
        }
    }
}

void CSemanticMap::serializeFrom(mrpt::serialization::CArchive& in, uint8_t version)
{
    switch (version)
    {
        case 0:
        case 1:
        {
            // Read into locals: a throw leaves the map as it was, objects and index consistent.
            WorldBounds bounds;
            const auto params = detail::readGenericMapParams(in, "CSemanticMap");
            const bool hasBounds = detail::readBool(in, "CSemanticMap bounds flag");
            in >> bounds.x_min >> bounds.x_max >> bounds.y_min >> bounds.y_max;
            const uint32_t n = detail::readCount(in, 1u << 24, "CSemanticMap objects");
            std::vector<TObject> objects;
            std::unordered_set<int32_t> ids;
            for (uint32_t i = 0; i < n; i++)
            {
                TObject o;
                in >> o.id;
                detail::readString(in, o.label, "CSemanticMap object label");
                in >> o.x >> o.y >> o.z >> o.extent_m >> o.n_observations;
                if (version >= 1)
                {
                    in >> o.sigma_m >> o.p_exist >> o.n_detected >> o.scatter_m2 >> o.n_in_view >>
                        o.expected_detections;
                    const uint32_t nc = detail::readCount(in, 1u << 16, "CSemanticMap classes");
                    for (uint32_t c = 0; c < nc; c++)
                    {
                        std::pair<std::string, double> cl;
                        detail::readString(in, cl.first, "CSemanticMap class label");
                        in >> cl.second;
                        o.classes.push_back(std::move(cl));
                    }
                }
                checkObject(o);
                if (!ids.insert(o.id).second)
                {
                    THROW_EXCEPTION_FMT("CSemanticMap: corrupted data: duplicate object id %d",
                                        o.id);
                }
                objects.push_back(std::move(o));
            }
            genericMapParams = params;
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