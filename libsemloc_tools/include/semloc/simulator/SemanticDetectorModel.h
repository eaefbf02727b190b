/* semloc — simulated object detector: visible objects, missed detections, clutter, confusion. */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/math/TPoint2D.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/poses/CPose3D.h>
#include <semloc/models/structure/RayCaster.h>
#include <semloc/observation/CObservationSemantic.h>
#include <semloc/world/World.h>

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace mrpt::random
{
class CRandomGenerator;
}

namespace semloc
{
/** An object detector (e.g. on forward-looking sonar images) producing CObservationSemantic;
 *  its error model is the one CSemanticMap's `probabilistic` likelihood assumes.
 *
 *  **Visibility.** An object is visible when its centre lies within `max_range_m` and the
 *  field of view `fov_deg` of the sensor, and the line of sight from the sensor to the centre
 *  is not occluded: the first outline that line crosses (RayCaster over
 *  World::outlineSegments(), the sonar's segments) must be the object's own, or none. The
 *  own outline is recognized exactly, by casting the same ray against the object's outline
 *  alone and comparing the two distances (bit-equal when the nearest hit is on it); so an
 *  object is never hidden by itself, a box behind a pillar is, and a point object (a
 *  marker) is hidden by any outline in front of it.
 *
 *  **Detections** of a visible object at true range r, bearing b:
 *  - detected with P_D(r, b) = (p_detect_near + (p_detect_far - p_detect_near) r / max_range_m)
 *    (1 - (1 - p_detect_edge_ratio) min(|b| / (fov / 2), 1)) (the second factor 1 for a
 *    360-degree field of view): CSemanticMap's P_D;
 *  - range r + rangeBias(range_bias_m, b, fov) + N(0, range_noise_std_m^2) clamped to
 *    [0, max_range_m] (the bias CSemanticMap's range_bias_m takes off), bearing
 *    b + N(0, bearing_noise_std_deg^2) wrapped and clamped to the field of view (so every
 *    detection is valid for CObservationSemantic::isValid);
 *  - misread range: with probability p_range_outlier the range is instead uniform over
 *    [0, max_range_m] (a reflection, a partly hidden object), the bearing kept;
 *  - label: its own, or for an object with a class distribution (`classes` in the world
 *    file) one of those classes drawn with its probability; then with probability
 *    p_confusion one of the world's other labels (uniform); the world's `sigma_m` and
 *    `p_exist` describe a map, not the world, and are ignored here; object_id is the object's id
 * when report_ids (also when the label is confused: the id is the truth the detector could not
 * classify), else -1;
 *  - confidence 1.
 *  **Distractors**: objects that are not in the map but carry one of its labels (other
 *  vehicles, divers, moored buoys since moved), `distractors` of them, each moving in a
 *  straight line at `distractor_speed_mps`, reflected at the world's bounds (the Simulator
 *  moves them; TDistractor). One is visible as a point object is (range, field of view, no
 *  outline in front of it) and detected as a map object is (P_D, noise, confusion), with
 *  object_id -1.
 *  **False positives**: Poisson(false_positives_per_scan) per scan, each with a label
 *  uniform over the world's labels, range uniform in [0, max_range_m] and bearing uniform
 *  in the field of view (the density CSemanticMap assumes), object_id -1.
 *  Detections are listed in world-object order, then the distractors', false positives
 *  last. */
class SemanticDetectorModel
{
public:
    /** Section [SemanticDetector]. */
    struct TOptions : public mrpt::config::CLoadableOptions
    {
        /** False: the frames hold no CObservationSemantic of this detector (its noise is
         *  drawn all the same, so the other sensors' streams are those of a run with it): a
         *  vehicle that carries only the detectors of [SideScan], [ForwardSonar], [Camera]. */
        bool enabled = true;
        /** Maximum detection range [m]. */
        double max_range_m = 20.0;
        /** Horizontal field of view [deg], centred on the sensor's x axis, (0, 360]. */
        double fov_deg = 120.0;
        /** Std. dev. of the range noise [m]. */
        double range_noise_std_m = 0.5;
        /** Std. dev. of the bearing noise [deg]. */
        double bearing_noise_std_deg = 3.0;
        /** The range's bias by bearing [m]: up to 4 coefficients of rangeBias()
         *  (DetectionProbability.h); empty: none. */
        std::vector<double> range_bias_m;
        /** Detection probability of a visible object at zero range. */
        double p_detect_near = 0.95;
        /** Detection probability of a visible object at max range (linear in between). */
        double p_detect_far = 0.6;
        /** Detection probability at the edge of the field of view over that on its axis
         *  (linear in |bearing| between), [0, 1]; 1: the same across the field of view. */
        double p_detect_edge_ratio = 1.0;
        /** Mean number of false positives per scan (Poisson). */
        double false_positives_per_scan = 0.2;
        /** Probability that a detection carries another label of the world. */
        double p_confusion = 0.05;
        /** Probability that a detection's range is misread: uniform over [0, max_range_m]. */
        double p_range_outlier = 0.0;
        /** Report the map object id of each true detection (else -1: label only). */
        bool report_ids = false;
        /** @name Silences: stretches in which the detector reports nothing (empty scans)
         *  @{ */
        /** Mean time between the starts of two silences [s] (exponential); 0: none. */
        double gap_every_s = 0.0;
        /** Shortest and longest silence [s] (uniform in between). */
        double gap_min_s = 60.0;
        double gap_max_s = 120.0;
        /** @} */
        /** @name Distractors: unmapped moving objects under the world's labels
         *  @{ */
        /** How many (0: none). */
        int distractors = 0;
        /** Their speed [m/s]. */
        double distractor_speed_mps = 0.5;
        /** @} */
        /** @name Pose of the detector on the vehicle
         *  @{ */
        double sensor_x_m = 0.0;      //!< [m] forward
        double sensor_y_m = 0.0;      //!< [m] to the left
        double sensor_yaw_deg = 0.0;  //!< [deg] counter-clockwise
        /** @} */

        /** Reads the section strictly: an unknown key or a bad value is an error naming it. */
        void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                                const std::string& section) override;
        /** Writes every key of the section, defaults included, with a comment. */
        void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                              const std::string& section) const override;

        /** The sensor pose on the vehicle. */
        mrpt::poses::CPose3D sensorPose() const;
    };

    /** A distractor where it is at one step: position [m] and its label's index in
     *  labels(). */
    struct TDistractor
    {
        double x = 0, y = 0;
        size_t label = 0;
    };

    /** An object the sensor sees (before detection noise and misses). */
    struct TVisibleObject
    {
        /** Index in World::objects. */
        size_t index = 0;
        /** Exact range of its centre [m]. */
        double range_m = 0;
        /** Exact bearing of its centre in the sensor frame [rad]. */
        double bearing_rad = 0;
    };

    /** A detector of the objects of `world` with the given options. */
    SemanticDetectorModel(const World& world, const TOptions& options);

    /** The objects visible from vehicle pose `vehicle` (class documentation), world order. */
    std::vector<TVisibleObject> visibleObjects(const mrpt::math::TPose2D& vehicle) const;

    /** One detector output from vehicle pose `vehicle` (label "SEMANTIC", timestamp unset),
     *  the `distractors` where they are now included. */
    CObservationSemantic::Ptr measure(const mrpt::math::TPose2D& vehicle,
                                      mrpt::random::CRandomGenerator& rng,
                                      const std::vector<TDistractor>& distractors = {}) const;

    /** True when the line of sight from `sensor` to the centre of the world's object
     *  `index` is clear: the first outline it crosses is the object's own, or none (the
     *  occlusion of visibleObjects(), without its range and field of view). */
    bool inLineOfSight(const mrpt::math::TPoint2D& sensor, size_t index) const;

    /** P_D(r, b): detection probability of a visible object at range `range_m` [m] and
     *  bearing `bearing_rad` in the sensor frame (see the class documentation). */
    double detectionProbability(double range_m, double bearing_rad) const;
    /** The world's distinct labels, sorted. */
    const std::vector<std::string>& labels() const { return m_labels; }
    /** The parameters. */
    const TOptions& options() const { return m_options; }

private:
    /** Appends the detection of a visible object or distractor of label `label` at `range`,
     *  `bearing` (or nothing, missed); an object with `classes` (label index, cumulative
     *  probability) is seen as one of them. */
    void detect(double range, double bearing, size_t label, int32_t id,
                mrpt::random::CRandomGenerator& rng, CObservationSemantic& obs,
                const std::vector<std::pair<size_t, double>>* classes = nullptr) const;
    /** Index of `label` in m_labels (which holds it). */
    size_t labelIndex(const std::string& label) const;
    /** The sensor's position in the world when the vehicle is at `vehicle`. */
    mrpt::math::TPoint2D sensorPosition(const mrpt::math::TPose2D& vehicle) const;
    /** True when the outlines hide object `index`, `range` away from (sx, sy) along `angle`. */
    bool occluded(double sx, double sy, double angle, double range, size_t index) const;
    /** Range and bearing [rad] of the distractor `d` seen from `vehicle`, if visible. */
    bool distractorVisible(const mrpt::math::TPose2D& vehicle, const TDistractor& d, double& range,
                           double& bearing) const;

    TOptions m_options;
    std::vector<WorldObject> m_objects;
    std::vector<size_t> m_labelOf;  // per object: index into m_labels
    /** Per object: its classes (index into m_labels, cumulative probability); empty: its
     *  label only. */
    std::vector<std::vector<std::pair<size_t, double>>> m_classesOf;
    std::vector<std::string> m_labels;  // distinct, sorted
    RayCaster m_all;                    // every outline
    std::vector<RayCaster> m_own;       // per object: its outline only (empty for points)
};

}  // namespace semloc
