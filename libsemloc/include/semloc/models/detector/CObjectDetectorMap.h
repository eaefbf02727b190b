/* semloc — the objects one of the vehicle's detectors sees, in the water column: the common part
 * of the side-scan, forward-looking sonar and bearing-only camera models (docs/design.md,
 * "The detector models"). */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/math/TPose2D.h>
#include <semloc/models/CSensorModelMap.h>
#include <semloc/observation/CObservationSemantic.h>
#include <semloc/world/World.h>

#include <cstdint>
#include <string>
#include <vector>

namespace semloc
{
/** A map of the world's objects as one detector of the vehicle sees them: labelled points in
 *  3D (each object's centre and its `z`), scored against that detector's scans
 *  (CObservationSemantic whose sensorLabel is the map's `sensor_label`).
 *
 *  The likelihood (every detector kind): objects in view are detected independently with
 *  P_D(r), linear in the range r from `p_detect_near` at 0 to `p_detect_far` at
 *  `max_range_m`; false alarms are Poisson with mean λ = `clutter_per_scan`, uniform over the
 *  kind's measurement space V and the map's K labels (density κ = λ / (V K)). Each detection
 *  j is explained either by clutter or by one object v in view of its label, with the
 *  kind's measurement density g_j(v):
 *
 *      log p(z | x) = -λ + Σ_v log(1 - P_D(r_v)) + Σ_j log(κ + Σ_{v: L_v = L_j} P_D(r_v) g_j(v) /
 * (1 - P_D(r_v)))
 *
 *  the association marginalized detection by detection (exact for one detection; for several
 *  it lets two detections share an object, which the look-alike fields of a seabed make
 *  harmless and which costs one pass over the objects in view). A detection of a label the
 *  map does not know is clutter. With nothing of the map in view the value is
 *  -λ + l log κ, the same at every pose (plan()).
 *
 *  Ranges are slant (`range_kind = slant`, the default: from the 3D offset of sensor and
 *  object, the sensor at the vehicle's height -depth plus its mount's z) or horizontal. The
 *  vehicle's depth is the last CObservationDepth the map saw: the filter hands a frame's
 *  observations to prepareObservation() in the frame's order before it evaluates any, and
 *  MRPT's per-pose call sees them in the same order, so a depth reading placed before the
 *  detections of its frame applies to them in both (0 before any reading). */
class CObjectDetectorMap : public CSensorModelMap
{
public:
    /** One object as the detector sees it. */
    struct TObject
    {
        double x = 0, y = 0, z = 0;
        /** Index of its label in labels(). */
        uint32_t label = 0;
        int32_t id = 0;
    };

    /** The options every detector kind reads from its `likelihoodOpts` section. */
    struct TDetectorParam
    {
        /** The scans the map scores: CObservationSemantic of this sensorLabel ("": every
         *  CObservationSemantic). */
        std::string sensor_label;
        /** Ranges from the 3D offset of sensor and object (true, `slant`) or in the
         *  horizontal plane (`horizontal`). */
        bool slant = true;
        /** The detector's range window [m]: objects nearer than min_range_m or beyond
         *  max_range_m are not seen. */
        double min_range_m = 0, max_range_m = 50;
        /** P_D at range 0 and at max_range_m (linear between), each in [0, 0.999]. */
        double p_detect_near = 0.9, p_detect_far = 0.5;
        /** The mean number of false alarms per scan (λ > 0). */
        double clutter_per_scan = 0.1;
        /** A detection's range noise [m] (kinds that measure a range). */
        double sigma_range_m = 0.5;
        /** The probability that a detection's range is misread: uniform over the range window
         *  instead of Gaussian (kinds that measure a range). */
        double p_range_outlier = 0;

        /** Reads the shared keys of `section` (strictly, with the kind's own `kindKeys`
         *  accepted too). */
        void load(const mrpt::config::CConfigFileBase& source, const std::string& section,
                  const std::vector<std::string>& kindKeys, bool measuresRange);
        /** Writes the shared keys, defaults included. */
        void save(mrpt::config::CConfigFileBase& target, const std::string& section,
                  bool measuresRange) const;
    };

    /** The kind's options (its TLikelihoodOptions' shared part). */
    virtual const TDetectorParam& detectorParam() const = 0;

    /** Replaces the objects with the world's (every object's centre and z). */
    void loadFromWorld(const World& world);
    const std::vector<TObject>& objects() const { return m_objects; }
    /** The objects' labels, each once; TObject::label indexes it. */
    const std::vector<std::string>& labels() const { return m_labels; }
    /** The vehicle's depth [m] the map's slant ranges use: the last CObservationDepth it saw. */
    double vehicleDepth() const { return m_depth_m; }

    /** A scan as its evaluations read it (what every pose shares). */
    struct TScan
    {
        struct TDetection
        {
            /** Label index (labels().size(): a label the map does not know). */
            uint32_t label;
            double range_m, bearing_rad;
        };
        /** The valid detections, sorted by label; the ones of label k are
         *  [labelBegin[k], labelBegin[k + 1]). */
        std::vector<TDetection> detections;
        std::vector<uint32_t> labelBegin;
        /** The sensor on the vehicle (x, y, yaw) and its height in the world [m]. */
        double mountX = 0, mountY = 0, mountYaw = 0, sensorZ = 0;
        /** log κ and -λ. */
        double logKappa = 0, minusLambda = 0;
        /** Detections refused (invalid for the kind) and of labels the map does not know. */
        size_t invalid = 0, unknown = 0;
    };
    /** `obs` as its evaluations read it, the sensor at the current vehicleDepth(). */
    TScan scan(const CObservationSemantic& obs) const;

    // BatchLikelihood
    bool uses(const mrpt::obs::CObservation& obs) const override;
    TObservationPlan plan(const mrpt::obs::CObservation& obs) const override;
    std::unique_ptr<Prepared> prepareObservation(const mrpt::obs::CObservation& obs) const override;
    bool weighsWithoutMap() const override { return true; }
    void logLikelihoods(const mrpt::obs::CObservation& obs, const mrpt::math::TPose2D* poses,
                        size_t n, double* out) const override;

    /** out[i] = log p(scan | poses[i]) (the kind's geometry over the objects near each pose). */
    virtual void scoreScan(const TScan& scan, const mrpt::math::TPose2D* poses, size_t n,
                           double* out) const = 0;

    /** An object in view, as the kind's geometry predicts its detections. */
    struct TInView
    {
        /** Index in objects(). */
        uint32_t object = 0;
        /** The range the kind measures [m] and the bearing in the sensor's frame [rad]. */
        double range_m = 0, bearing_rad = 0;
        /** The side-scan's side: +1 port, -1 starboard (0: the other kinds). */
        int side = 0;
    };
    /** The objects in view of `scan`'s sensor with the vehicle at `pose`, by the geometry
     *  scoreScan() scores with (semloc-calibrate matches the detections against it). */
    virtual std::vector<TInView> inView(const TScan& scan,
                                        const mrpt::math::TPose2D& pose) const = 0;
    /** Whether the kind's detections carry a range (all but the camera) and a bearing (all
     *  but the side-scan, whose bearing's sign is its side). */
    virtual bool measuresRange() const = 0;
    virtual bool measuresBearing() const = 0;

    // CMetricMap
    bool isEmpty() const override { return m_objects.empty(); }
    std::string asString() const override;

    /** The objects whose horizontal distance to (x, y) may be within r: a superset, in
     *  index order, as [begin, end) ranges of cellObjects() through visit(begin, end). */
    template <typename Visit>
    void forEachCellNear(double x, double y, double r, const Visit& visit) const;
    /** Object indices by grid cell (forEachCellNear's ranges index it). */
    const std::vector<uint32_t>& cellObjects() const { return m_cellObjects; }

protected:
    CObjectDetectorMap() = default;
    /** True when `d` is a detection this kind can score (its range and bearing for the
     *  kind's coverage). */
    virtual bool validDetection(const TSemanticDetection& d) const = 0;
    /** The kind's measurement space V (clutter density λ / (V K)). */
    virtual double measurementVolume() const = 0;

    void internal_clear() override;
    double internal_computeObservationLikelihood(
        const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& takenFrom) const override;

    /** Writes and reads the objects (the kinds' serialization). */
    void writeObjects(mrpt::serialization::CArchive& out) const;
    void readObjects(mrpt::serialization::CArchive& in);

private:
    void buildIndex();
    /** Takes a depth reading (a frame's or MRPT's per-pose call). */
    void takeDepth(const mrpt::obs::CObservation& obs) const;

    std::vector<TObject> m_objects;
    std::vector<std::string> m_labels;
    /** The grid: cells of m_cell metres from (m_x0, m_y0), m_nx by m_ny, CSR over m_cellObjects. */
    double m_cell = 1, m_x0 = 0, m_y0 = 0;
    int m_nx = 0, m_ny = 0;
    std::vector<uint32_t> m_cellBegin, m_cellObjects;
    /** The last depth reading [m] (changed only where a frame is prepared, on one thread). */
    mutable double m_depth_m = 0;
};

template <typename Visit>
void CObjectDetectorMap::forEachCellNear(double x, double y, double r, const Visit& visit) const
{
    if (m_nx == 0)
    {
        return;
    }
    const auto cellOf = [this](double v, double v0, int n)
    {
        const double c = std::floor((v - v0) / m_cell);
        return c < 0 ? 0 : (c >= n ? n - 1 : static_cast<int>(c));
    };
    const int cx0 = cellOf(x - r, m_x0, m_nx), cx1 = cellOf(x + r, m_x0, m_nx);
    const int cy0 = cellOf(y - r, m_y0, m_ny), cy1 = cellOf(y + r, m_y0, m_ny);
    for (int cy = cy0; cy <= cy1; cy++)
    {
        const size_t row = static_cast<size_t>(cy) * static_cast<size_t>(m_nx);
        visit(m_cellBegin[row + static_cast<size_t>(cx0)],
              m_cellBegin[row + static_cast<size_t>(cx1) + 1]);
    }
}

}  // namespace semloc
