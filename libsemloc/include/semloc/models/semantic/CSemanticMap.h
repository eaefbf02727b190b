/* semloc — the semantic model's map (models/semantic/): labelled objects and the two semantic
 * likelihoods, the paper's (§III) and the probabilistic one, both stated in the class
 * documentation. */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/maps/CMetricMap.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/poses/CPose3D.h>
#include <semloc/io/ConfigHelpers.h>
#include <semloc/models/BatchLikelihood.h>
#include <semloc/observation/CObservationSemantic.h>
#include <semloc/world/World.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace semloc
{
class LabelIndex;

/** A map of labelled objects (the paper's semantic map) and the likelihood of a
 *  CObservationSemantic from a vehicle pose, usable by MRPT's particle filters.
 *
 *  Created in a CMultiMetricMap with `[MetricMap] semanticMap_count=1`; options in
 *  `[MetricMap_semanticMap_00_creationOpts]` (`world_file`), `..._likelihoodOpts`
 *  and `..._insertOpts`.
 *
 *  ## Likelihood models (`likelihoodOpts.model`)
 *
 *  Notation of §III: the real observation z^r has l detections (rho^r, theta^r);
 *  the predicted observation z^k from a particle pose holds the q map objects inside
 *  the detector's range and field of view, with (rho^k, theta^k); m pairs are matched.
 *
 *  **paper** (exactly §III):
 *
 *      log w = sum_{i=1..m} [ -1/2 ((rho^r_i - rho^k_i) / sigma_rho)^2
 *                             -1/2 ((theta^r_i - theta^k_i) / sigma_theta)^2 ]
 *              + d * log(p_u),          d = q + l - 2m
 *
 *  i.e. w = prod_i N0(d_rho_i) N0(d_theta_i) * p_u^d with zero-centred, peak-one
 *  Gaussians N0. Why this reading of "a mixture of two families of Gaussians ...
 *  then adjusted for the d objects present in one observation only":
 *  - the two families (range, bearing) are multiplied, not summed: a sum would let a
 *    particle with one good match and four bad ones score almost as well as the true
 *    pose, and the SIR weight of independent errors is their product;
 *  - peak-one Gaussians make a perfect match cost nothing, so the adjustment p_u in
 *    (0, 1] (`unmatched_penalty`) is the price of one unexplained object on the same
 *    scale, whichever of the two observations it is missing from;
 *  - matching: by object id when the detection carries one, otherwise by label; a pair
 *    is only matched if it costs less than leaving both unmatched (the gate
 *    N0 N0 > p_u^2), and same-label candidates are assigned one-to-one, greedily from
 *    the best pair (deterministic; optimal for the 1-2 candidates per label usual here).
 *    So w >= p_u^(q+l) > 0: always finite.
 *  - detections with a label the map does not know are skipped: they are unmatched at
 *    every particle, a constant factor that normalization removes.
 *  Occlusion is not modelled (that would need the ray casting the paper avoids); an
 *  occluded object costs one p_u at the particles that predict it.
 *
 *  **probabilistic** (the paper's future work, a probabilistic semantic map): each
 *  predicted object is detected with P_D(rho) (linear from `p_detect_near` at 0 to
 *  `p_detect_far` at max range), detections carry Gaussian range/bearing noise and are
 *  labelled correctly with 1 - p_c or as any other of the K map labels with
 *  p_c / (K - 1), and false positives are Poisson with mean lambda (`clutter_per_scan`),
 *  uniform over the field of view and the K labels (density kappa = lambda / (R fov K)).
 *  With a one-to-one association A chosen greedily, best pair first (the most likely one
 *  whenever no two pairs that gain compete for a detection or an object):
 *
 *      log p(z | x) = -lambda + sum_{(j,v) in A} [log P_D(rho_v) + log C(L_j | L_v)
 *                                 + log N(d_rho; sigma_rho) + log N(d_theta; sigma_theta)]
 *                   + sum_{v unmatched} log(1 - P_D(rho_v)) + sum_{j unmatched} log kappa
 *
 *  With `association = marginal` (probabilistic model only) the likelihood is instead the
 *  sum over every one-to-one association A of the detections to z^k (each detection an
 *  object or clutter, each object detected or missed), as in Atanasov, Zhu, Daniilidis &
 *  Pappas, "Localization from semantic observations via the matrix permanent" (IJRR 2016):
 *
 *      p(z | x) = e^-lambda kappa^l prod_v (1 - P_D(rho_v)) sum_A prod_{(j,v) in A} w_jv,
 *      w_jv = P_D(rho_v) C(L_j | L_v) N(d_rho) N(d_theta) / ((1 - P_D(rho_v)) kappa)
 *
 *  (the permanent of the detections x (objects + clutter) matrix). It is computed exactly
 *  per group of detections and objects linked by pairs (the sum factors over such groups),
 *  leaving out pairs with w_jv < kMarginalMinWeight (leaving out a pair of weight w makes the
 *  sum low by a factor of at most 1 + w). A group is summed detection by detection over the
 *  sets of objects its partial associations take: exact while there are at most
 *  kMarginalMaxStates such sets (always for up to 12 objects); beyond, only the heaviest
 *  kMarginalMaxStates sets are carried on (a beam: a lower bound of the sum, counted in
 *  associationsApproximated(), as is a group of more than 64 objects, whose lightest pairs
 *  are left out).
 *  Greedy's value is one term of the sum: the exact marginal is never below it.
 *
 *  **Objects with uncertainty** (probabilistic model; TObject::sigma_m, p_exist, classes,
 *  from the world file or insertObservation): at each particle a pair's range variance is
 *  sigma_rho^2 + sigma_m^2 and its bearing variance sigma_theta^2 + sigma_m^2 / max(rho^2,
 *  4 sigma_m^2); P_D(rho) becomes p_exist P_D(rho) (in the miss term too); the label term is
 *  C(L_j | v) = pi(L_j) (1 - p_c) + (1 - pi(L_j)) p_c / (K - 1) over the class distribution
 *  pi (a class it cannot be pairs only with a detection naming it). The paper model keeps
 *  positions and labels as given (docs/design.md, "The semantic models").
 *
 *  **Misread ranges** (`p_range_outlier` = eps > 0, both models): a detection of an object
 *  reports, with probability eps, a range uniform over [0, R] (R: the detector's max range)
 *  instead of a Gaussian one; its bearing stays Gaussian. The range factor of a matched pair
 *  becomes the mixture
 *
 *      probabilistic:  (1 - eps) N(d_rho; sigma_rho) + eps / R
 *      paper:          (1 - eps) N0(d_rho) + eps sqrt(2 pi) sigma_rho / R
 *
 *  (the paper's is the same over the Gaussian's peak). A detection at the object's bearing
 *  but far from its range is then a detection of the object with a misread range, not a
 *  missed object plus clutter, and no range error costs more than the uniform's share: one
 *  misread range cannot outweigh the other detections of the true pose. The gates follow
 *  (with a large enough eps any range passes; the bearing gate stays).
 *
 *  Both models are evaluated without allocation, through a uniform-grid index over the
 *  objects (cost independent of map size at fixed density), and are safe to call from
 *  many threads at once. */
class CSemanticMap : public mrpt::maps::CMetricMap, public BatchLikelihood
{
    DEFINE_SERIALIZABLE(CSemanticMap, semloc)

public:
    /** One labelled object of the map. */
    struct TObject
    {
        /** Unique positive id. */
        int32_t id = 0;
        /** Object class. */
        std::string label;
        /** Position [m]: x. */
        double x = 0;
        /** Position [m]: y. */
        double y = 0;
        /** Depth/height [m]. */
        double z = 0;
        /** Radius of the object's outline around (x, y) [m] (display, merging). */
        double extent_m = 0;
        /** How many detections were merged into it (1 for map-file objects). */
        uint32_t n_observations = 1;
        /** Standard deviation of its position, isotropic [m] (probabilistic model; 0: exact). */
        double sigma_m = 0;
        /** Probability that it is still there, in (0, 1] (probabilistic model). */
        double p_exist = 1;
        /** Its class distribution (label, probability), summing to 1 and holding `label`;
         *  empty: certainly of class `label` (probabilistic model). */
        std::vector<std::pair<std::string, double>> classes{};
        /** @name Bookkeeping of insertObservation (known poses): the detections merged into
         *  it, the sum of their squared distances to its mean [m^2], the insertions it was in
         *  view at and the detections P_D expected there.
         *  @{ */
        uint32_t n_detected = 0;
        double scatter_m2 = 0;
        uint32_t n_in_view = 0;
        double expected_detections = 0;
        /** @} */
    };

    /** Which likelihood (see the class documentation). */
    enum class Model
    {
        Paper,
        Probabilistic
    };

    /** How the probabilistic model associates detections with objects (see the class
     *  documentation). */
    enum class Association
    {
        /** One one-to-one association, greedily from the best pair. */
        Greedy,
        /** The sum over every one-to-one association. */
        Marginal
    };

    /** `association = marginal`: pairs of a smaller weight w_jv are left out of the sum. */
    static constexpr double kMarginalMinWeight = 1e-9;
    /** `association = marginal`: the most sets of taken objects the sum over one group of
     *  linked detections and objects keeps; beyond, the heaviest are kept. */
    static constexpr size_t kMarginalMaxStates = 4096;

    /** The detector's noise and coverage, read by both likelihoods. */
    struct TDetectorParam
    {
        /** Range noise of a detection, sigma_rho [m]. */
        double sigma_range_m = 0.5;
        /** Bearing noise of a detection, sigma_theta [deg]. */
        double sigma_bearing_deg = 3.0;
        /** Probability that a detection's range is misread (a reflection, a partly hidden
         *  object): uniform over [0, max range] instead of Gaussian around the object's, its
         *  bearing still Gaussian (see the class documentation); in [0, 1), 0: none. */
        double p_range_outlier = 0.0;
        /** The detector's range bias by bearing [m]: up to 4 coefficients of rangeBias()
         *  (DetectionProbability.h), c0 + c1 u + c2 u^2 + c3 u^3 with u the bearing over half
         *  the field of view; each detection's range is read less it (at least 0) by both
         *  models. Empty (default) or zeros: none. */
        std::vector<double> range_bias_m;
        /** Detections with lower confidence are ignored. */
        double min_confidence = 0.0;
        /** Overrides the observation's max range when > 0 [m]. */
        double max_range_m = 0.0;
        /** Overrides the observation's field of view when > 0 [deg]. */
        double fov_deg = 0.0;
    };

    /** The paper's likelihood (model = paper). */
    struct TPaperParam
    {
        /** Factor p_u in (0, 1] per object present in one observation only. */
        double unmatched_penalty = 0.2;
        /** The factor per predicted object no detection matched, in [0, 1]; 0: the same as
         *  unmatched_penalty (§III's single p_u). 1: a missed object costs nothing, so a pose
         *  that predicts objects the detector missed no longer loses to poses that predict
         *  fewer (a detector that misses objects; docs/design.md). */
        double missed_object_penalty = 0.0;
    };

    /** The probabilistic likelihood (model = probabilistic). */
    struct TProbabilisticParam
    {
        /** "greedy" or "marginal". */
        Association association = Association::Greedy;
        /** Detection probability of an object at zero range. */
        double p_detect_near = 0.95;
        /** Detection probability of an object at max range. */
        double p_detect_far = 0.6;
        /** P_D of an object at the edge of the field of view over P_D of one on its axis at
         *  the same range, linear in |bearing| between, in [0, 1]; 1: the same across the
         *  field of view (a camera that misses objects near its image's border). */
        double p_detect_edge_ratio = 1.0;
        /** Expected false positives per scan (Poisson mean). */
        double clutter_per_scan = 0.2;
        /** Probability a detection carries a wrong label. */
        double p_confusion = 0.05;
    };

    /** The detector's outages (probabilistic model). */
    struct TOutageParam
    {
        /** Mean time between detector outages [s] (spells in which the detector reports
         *  nothing at all, whatever is in view); 0: no outage model. The filter
         *  (CParallelMonteCarloLocalization2D) keeps the probability of an outage. */
        double outage_every_s = 0.0;
        /** Mean length of an outage [s] (with outage_every_s > 0). */
        double outage_mean_s = 60.0;
    };

    /** Look-alikes that persist (probabilistic model). */
    struct TLookAlikeParam
    {
        /** rho in [0, 1]: the expected detections, per scan, of an unmapped object (another
         *  vehicle, a diver) detected under a map label in an earlier scan of the last
         *  lookalike_window_s. A detection near such an earlier one (in the vehicle's odometry
         *  frame, same label) gets the clutter density kappa + rho N(its position; the earlier
         *  one's, the two detections' noise and lookalike_speed_mps dt) instead of kappa: a
         *  look-alike seen scan after scan costs the poses that cannot explain it once, not
         *  every scan. 0: clutter uniform and independent from scan to scan. Needs the
         *  filter's frame-to-frame state (CParallelMonteCarloLocalization2D); a generic
         *  computeObservationLikelihood() call leaves it out. */
        double lookalike_persistence = 0.0;
        /** How fast a look-alike may move [m/s]. */
        double lookalike_speed_mps = 0.3;
        /** How far back earlier detections are remembered [s]. */
        double lookalike_window_s = 1.0;
    };

    /** Parameters of the likelihood models, one `[..._likelihoodOpts]` section (its keys flat,
     *  as they always were); defaults are the documented ones. */
    struct TLikelihoodOptions : public mrpt::config::CLoadableOptions
    {
        /** "paper" or "probabilistic". */
        Model model = Model::Paper;
        /** Cell size of the object index [m]; a quarter of the detector range is about best. */
        double index_cell_m = 5.0;
        TDetectorParam detector;
        TPaperParam paper;
        TProbabilisticParam probabilistic;
        TOutageParam outage;
        TLookAlikeParam lookalike;

        /** The values loadFromConfigFile() accepts for the numeric key `key` (throws for a
         *  key that is not a number): what a tool writing the key must keep to. */
        static config::TValueRange range(const std::string& key);

        /** The detector's max range for `obs` [m]: max_range_m if > 0, else the
         *  observation's. */
        double maxRange(const CObservationSemantic& obs) const
        {
            return detector.max_range_m > 0 ? detector.max_range_m : obs.maxRange_m;
        }
        /** The detector's field of view for `obs` [rad]: fov_deg if > 0, else the
         *  observation's. */
        double fieldOfView(const CObservationSemantic& obs) const
        {
            return detector.fov_deg > 0 ? detector.fov_deg * M_PI / 180 : obs.fov_rad;
        }
        /** P_D(rho, theta) of the probabilistic model for a detector of max range `R` and
         *  field of view `fov` [rad], for an object at range `rho` [m] and bearing `theta`
         *  [rad] in the sensor frame: linear from p_detect_near at 0 to p_detect_far at R,
         *  times 1 - (1 - p_detect_edge_ratio) min(|theta| / (fov / 2), 1) when fov < 2 pi,
         *  clamped to [1e-6, 1]. */
        double detectionProbability(double rho, double R, double theta, double fov) const;
        /** A detection's range `rho` [m] at bearing `theta` [rad] less range_bias_m's bias
         *  for a field of view `fov` [rad], kept within the coverage [0, R] (a detection the
         *  models score is of an object within the max range `R`). */
        double correctedRange(double rho, double theta, double R, double fov) const;

        /** Reads `section` strictly (unknown keys and bad values are errors). */
        void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                                const std::string& section) override;
        /** Writes every key with a comment. */
        void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                              const std::string& section) const override;
    };

    /** How observations inserted with a known pose become objects. A detection is merged into
     *  the object it names, else the nearest of its label within merge_distance_m, else becomes
     *  a new object; each insertion of a CObservationSemantic also counts the objects inside
     *  the detector's coverage as in view with the detection P_D(rho) expected of them. An
     *  object the insertions touched gets sigma_m = its detections' spread per axis over
     *  sqrt(n) (from 3 on; sigma_range_m / sqrt(n) before) and p_exist = (detections + 1) /
     *  (expected detections + 1), at most 1 (docs/design.md, "The semantic models"). */
    struct TInsertionOptions : public mrpt::config::CLoadableOptions
    {
        /** A detection this close [m] to a known object of the same label is merged into it. */
        double merge_distance_m = 1.5;
        /** Label given to landmarks of a CObservationBearingRange. */
        std::string landmark_label = "landmark";

        /** Reads `section` strictly (unknown keys and bad values are errors). */
        void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                                const std::string& section) override;
        /** Writes every key with a comment. */
        void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                              const std::string& section) const override;
    };

    /** What a likelihood call could use of an observation. */
    struct TObservationCheck
    {
        /** Detections used by the likelihood. */
        size_t used = 0;
        /** NaN/inf/negative/out-of-range/out-of-FOV/low-confidence detections, skipped. */
        size_t invalid = 0;
        /** Valid detections whose label and id the map does not know, skipped. */
        size_t unknown = 0;
    };

    CSemanticMap();
    ~CSemanticMap() override;
    /** Copies the objects and options (the index is rebuilt). */
    CSemanticMap(const CSemanticMap& o);
    /** Copies the objects and options (the index is rebuilt). */
    CSemanticMap& operator=(const CSemanticMap& o);

    /** Likelihood parameters. */
    TLikelihoodOptions likelihoodOptions;
    /** Insertion parameters. */
    TInsertionOptions insertionOptions;

    /** @name Map contents
     *  @{ */
    /** Replaces the contents with the world's objects (every shape, at its centre). */
    void loadFromWorld(const World& world);
    /** Loads a world YAML file (see World::FromFile). */
    void loadFromWorldFile(const std::string& path);
    /** Adds one object; its id must be positive and unused. */
    void addObject(const TObject& o);
    /** The objects, in insertion order. */
    const std::vector<TObject>& objects() const { return m_objects; }
    /** Number of distinct labels. */
    size_t labelCount() const;
    /** The world this map was last saved or loaded with, as a World (points). */
    World toWorld() const;
    /** @} */

    /** @name Likelihood (the fast path; the CMetricMap interface calls these)
     *  @{ */
    /** Log-likelihood of a semantic observation taken from vehicle pose `pose`. Finite. */
    double computeLogLikelihood(const CObservationSemantic& obs,
                                const mrpt::math::TPose2D& pose) const;
    /** Log-likelihood of MRPT's landmark observation: `landmarkID` >= 0 is an object id,
     *  otherwise the landmark is associated by position with any object. Finite. */
    double computeLogLikelihood(const mrpt::obs::CObservationBearingRange& obs,
                                const mrpt::math::TPose2D& pose) const;
    /** Log-likelihoods of one observation from `n` vehicle poses, into `out[0..n)`: the
     *  filter's inner loop. The observation is prepared (validated, labels resolved) once,
     *  so each pose costs only its geometry. Equal to n calls of computeLogLikelihood. */
    void computeLogLikelihoods(const CObservationSemantic& obs, const mrpt::math::TPose2D* poses,
                               size_t n, double* out) const;
    /** Batch version for MRPT landmark observations. */
    void computeLogLikelihoods(const mrpt::obs::CObservationBearingRange& obs,
                               const mrpt::math::TPose2D* poses, size_t n, double* out) const;
    /** BatchLikelihood: semantic observations and MRPT's landmark observations. */
    bool uses(const mrpt::obs::CObservation& obs) const override;
    /** BatchLikelihood: computeLogLikelihoods() of either observation. */
    void logLikelihoods(const mrpt::obs::CObservation& obs, const mrpt::math::TPose2D* poses,
                        size_t n, double* out) const override;
    /** @name BatchLikelihood's hooks (SemanticFilterHooks.cpp): check()'s counts, the
     *  detector's outages (outage_every_s, probabilistic model), logLikelihoodWithoutObjects()
     *  as the likelihood with nothing of the map in view, the look-alike memory
     *  (lookalike_persistence, probabilistic model) and DetectionPoseSampler's proposals.
     *  @{ */
    TObservationPlan plan(const mrpt::obs::CObservation& obs) const override;
    std::unique_ptr<Memory> newMemory() const override;
    void logLikelihoodsRemembering(const mrpt::obs::CObservation& obs,
                                   const std::vector<double>& context,
                                   const mrpt::math::TPose2D* poses, size_t n,
                                   double* out) const override;
    bool proposes() const override { return true; }
    std::unique_ptr<PoseProposal> proposal(const mrpt::obs::CSensoryFrame& sf) const override;
    bool weighsWithoutMap() const override { return true; }
    std::string needsStandardProposal() const override;
    size_t approximations() const override;
    /** @} */
    /** computeLogLikelihoods() with detection k of obs.detections at the clutter density
     *  kappa e^clutterLogFactors[k] (>= 0; one per detection of `obs`) instead of kappa
     *  (probabilistic model; the paper model ignores them): the look-alike persistence
     *  the filter's state supplies (lookalike_persistence). */
    void computeLogLikelihoods(const CObservationSemantic& obs, const mrpt::math::TPose2D* poses,
                               size_t n, double* out, const double* clutterLogFactors) const;
    /** The uniform clutter density kappa of `obs`'s detections (probabilistic model: lambda
     *  over the view's range x field of view x labels) [1 / (m rad)]; 0 for an observation
     *  the likelihood cannot use. */
    double clutterDensity(const CObservationSemantic& obs) const;
    /** Log-likelihood of `obs` from a pose with no object of the map in view: every
     *  detection the likelihood uses is clutter (probabilistic model: -lambda + l log kappa;
     *  paper model: l log p_u), the same at every pose. log p(z | x) minus this is the
     *  frame's log Bayes factor of "the map's objects, seen from x" against "nothing of the
     *  map in view", dimensionless whatever the number of detections: the evidence recovery
     *  trigger compares particles with it. `used` (optional) gets l, the detections used;
     *  an observation the likelihood cannot use gives 0 and l = 0. */
    double logLikelihoodWithoutObjects(const CObservationSemantic& obs,
                                       size_t* used = nullptr) const;
    /** The same for MRPT's landmark observation. */
    double logLikelihoodWithoutObjects(const mrpt::obs::CObservationBearingRange& obs,
                                       size_t* used = nullptr) const;
    /** Counts what the likelihood will use of `obs` (call once per observation). */
    TObservationCheck check(const CObservationSemantic& obs) const;
    /** True if the likelihood uses `d` of `obs` as valid (range, bearing within the
     *  effective max range and field of view, confidence >= min_confidence). */
    bool isUsable(const CObservationSemantic& obs, const TSemanticDetection& d) const;
    /** Indices into objects() of the map objects detection `d` of `obs` may be, as the
     *  likelihood associates it: its object if it carries an id the map knows, else every
     *  object with its label; empty if the likelihood skips it (not usable, unknown). */
    std::vector<size_t> candidatesOf(const CObservationSemantic& obs,
                                     const TSemanticDetection& d) const;
    /** A map object inside a detector's coverage. */
    struct TObjectInView
    {
        /** Index into objects(). */
        size_t index = 0;
        /** Range [m] and bearing in the sensor frame [rad] of its position. */
        double range_m = 0, bearing_rad = 0;
    };
    /** The objects, in map order, inside the coverage of `obs` taken from vehicle pose
     *  `vehicle`: within its max range and field of view (TLikelihoodOptions::maxRange(),
     *  fieldOfView()) from the sensor at `vehicle` (+) obs.sensorPose; the objects a
     *  likelihood predicts there (no occlusion) and insertion counts as in view. Empty when
     *  the coverage is not a positive finite range and angle. */
    std::vector<TObjectInView> objectsInView(const CObservationSemantic& obs,
                                             const mrpt::poses::CPose3D& vehicle) const;
    /** @} */

    // CMetricMap interface
    /** True without objects. */
    bool isEmpty() const override { return m_objects.empty(); }
    /** Writes `<prefix>_semantic.yaml`, a world file of point objects that loads back. */
    void saveMetricMapRepresentationToFile(const std::string& filNamePrefix) const override;
    /** Particle evaluations with `association = marginal` whose association sum was
     *  approximated (a group beyond kMarginalMaxStates), since construction or
     *  resetAssociationCount(); the same for any thread count. */
    size_t associationsApproximated() const;
    /** Sets associationsApproximated() to 0. */
    void resetAssociationCount();

    /** One line: object and label counts, likelihood model. */
    std::string asString() const override;
    /** A cylinder and a "label #id" text per object (coloured by label). */
    void getVisualizationInto(mrpt::opengl::CSetOfObjects& outObj) const override;

    MAP_DEFINITION_START(CSemanticMap)
    /** [creationOpts] world YAML to load (empty: start empty). */
    std::string world_file;
    /** [likelihoodOpts] */
    CSemanticMap::TLikelihoodOptions likelihoodOpts;
    /** [insertOpts] */
    CSemanticMap::TInsertionOptions insertionOpts;
    MAP_DEFINITION_END(CSemanticMap)

private:
    void internal_clear() override;
    bool internal_insertObservation(
        const mrpt::obs::CObservation& obs,
        const std::optional<const mrpt::poses::CPose3D>& robotPose = std::nullopt) override;
    double internal_computeObservationLikelihood(
        const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& takenFrom) const override;
    bool internal_canComputeObservationLikelihood(
        const mrpt::obs::CObservation& obs) const override;

    template <typename OBS>
    void likelihoodsOf(const OBS& obs, const mrpt::math::TPose2D* poses, size_t n, double* out,
                       const double* clutterLogFactors = nullptr) const;
    template <typename OBS>
    double withoutObjects(const OBS& obs, size_t* used) const;
    /** Rebuilds the label table and the grid index after any change of m_objects. */
    void rebuildIndex();
    int nextFreeId() const;

    std::vector<TObject> m_objects;
    WorldBounds m_bounds;
    bool m_hasBounds = false;

public:
    /** Internal search structures (opaque; defined in the .cpp). */
    struct Index;

private:
    std::unique_ptr<LabelIndex> m_labels;
    std::unique_ptr<Index> m_index;
    mutable std::atomic<size_t> m_approximated{0};
};

}  // namespace semloc
