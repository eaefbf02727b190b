/* semloc — the structure model's map (models/structure/): the world's outlines and the sonar's
 * beam-model likelihood (Probabilistic Robotics §6.3, eqs. 6.4–6.12, in the class
 * documentation). */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/maps/CMetricMap.h>
#include <mrpt/math/TPose2D.h>
#include <mrpt/math/TSegment2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <semloc/models/BatchLikelihood.h>
#include <semloc/models/structure/RayCaster.h>
#include <semloc/world/World.h>

#include <string>
#include <vector>

namespace semloc
{
/** The structures' outlines as 2D segments and the likelihood of a sonar scan
 *  (mrpt::obs::CObservation2DRangeScan) from a vehicle pose: the paper's geometric
 *  baseline, usable by MRPT's particle filters.
 *
 *  Created in a CMultiMetricMap with `[MetricMap] structureMap_count=1`; options in
 *  `[MetricMap_structureMap_00_creationOpts]` (`world_file`, `cylinder_tolerance_m`,
 *  `raycast_cell_m`) and `..._likelihoodOpts` (TLikelihoodOptions). The map is static:
 *  inserting observations changes nothing.
 *
 *  ## Likelihood: the beam model of Probabilistic Robotics (Thrun, Burgard, Fox), §6.3
 *
 *  For each used beam k (every `decimation`-th, invalid ones skipped) the expected range
 *  z*_k is cast exactly from the sensor pose (vehicle pose ⊕ scan.sensorPose, in 2D) by
 *  RayCaster, and the measured range z_k scores
 *
 *      p(z_k | x) = z_hit p_hit + z_short p_short + z_max p_max + z_rand p_rand    (6.12)
 *
 *  - p_hit: N(z_k; z*_k, sigma_hit^2) normalized on [0, z_max]                    (6.4)
 *  - p_short: lambda e^{-lambda z_k} / (1 - e^{-lambda z*_k}) for z_k <= z*_k      (6.7)
 *  - p_max: 1 if z_k is a max-range reading (z_k >= z_max), else 0                 (6.10)
 *  - p_rand: 1 / z_max for z_k < z_max                                              (6.11)
 *
 *  z_max is `max_range_m` if > 0, else the scan's maxRange; readings beyond z_max are
 *  max-range readings. The four weights are normalized to sum 1. The result is
 *  log p(z | x) = sum_k log max(p(z_k | x), min_beam_likelihood): finite for any scan
 *  (0 when no beam is usable, the same for every particle).
 *
 *  computeLogLikelihood() allocates nothing, makes no virtual call per beam, and is safe
 *  to call from many threads at once. */
class CStructureMap : public mrpt::maps::CMetricMap, public BatchLikelihood
{
    DEFINE_SERIALIZABLE(CStructureMap, semloc)

public:
    /** Parameters of the beam model; defaults are the documented ones. */
    struct TLikelihoodOptions : public mrpt::config::CLoadableOptions
    {
        /** Std. dev. of a correct range reading, sigma_hit [m]. */
        double sigma_hit_m = 0.5;
        /** Weight of the Gaussian "hit" term. */
        double z_hit = 0.8;
        /** Weight of the "short" term (unexpected objects, e.g. fish). */
        double z_short = 0.05;
        /** Rate of the exponential "short" term, lambda_short [1/m]. */
        double lambda_short = 0.2;
        /** Weight of the max-range point mass (missed echoes). */
        double z_max = 0.05;
        /** Weight of the uniform "random" term. */
        double z_rand = 0.1;
        /** Use one beam out of this many (beams 0, d, 2d, ...). */
        int decimation = 1;
        /** Overrides the scan's maxRange when > 0 [m]. */
        double max_range_m = 0;
        /** Floor of each beam's probability, keeps the log finite. */
        double min_beam_likelihood = 1e-12;

        /** Reads the section strictly: an unknown key or a bad value is an error naming it. */
        void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                                const std::string& section) override;
        /** Writes every key of the section, defaults included, with a comment. */
        void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                              const std::string& section) const override;
    };

    CStructureMap();

    /** Likelihood parameters. */
    TLikelihoodOptions likelihoodOptions;

    /** @name Map contents
     *  @{ */
    /** Replaces the contents with the world's outlines (World::outlineSegments). */
    void loadFromWorld(const World& world, double cylinderTolerance_m = kDefaultCylinderTolerance_m,
                       double raycastCell_m = 0);
    /** Loads a world YAML file (see World::FromFile). */
    void loadFromWorldFile(const std::string& path,
                           double cylinderTolerance_m = kDefaultCylinderTolerance_m,
                           double raycastCell_m = 0);
    /** Replaces the contents with arbitrary segments; `raycastCell_m` <= 0 is automatic. */
    void setSegments(const std::vector<mrpt::math::TSegment2D>& segments, double raycastCell_m = 0);
    /** The outline segments. */
    const std::vector<mrpt::math::TSegment2D>& segments() const { return m_caster.segments(); }
    /** The ray caster over the segments (expected ranges). */
    const RayCaster& rayCaster() const { return m_caster; }
    /** @} */

    /** @name Likelihood (the fast path; the CMetricMap interface calls it)
     *  @{ */
    /** log p(scan | vehicle pose) by the beam model (class documentation). Finite. */
    double computeLogLikelihood(const mrpt::obs::CObservation2DRangeScan& scan,
                                const mrpt::math::TPose2D& pose) const;
    /** BatchLikelihood: 2D range scans. */
    bool uses(const mrpt::obs::CObservation& obs) const override;
    /** BatchLikelihood: computeLogLikelihood() at each pose. */
    void logLikelihoods(const mrpt::obs::CObservation& obs, const mrpt::math::TPose2D* poses,
                        size_t n, double* out) const override;
    /** @} */

    // CMetricMap interface
    /** True if the map has no outline segment. */
    bool isEmpty() const override { return m_caster.empty(); }
    /** Writes `<prefix>_outlines.txt`: one segment per line, `x1 y1 x2 y2` [m]. */
    void saveMetricMapRepresentationToFile(const std::string& filNamePrefix) const override;
    /** One-line summary: world name, segment count and ray-cast grid. */
    std::string asString() const override;
    /** The outlines as line segments (mrpt::opengl::CSetOfLines) at z = 0. */
    void getVisualizationInto(mrpt::opengl::CSetOfObjects& outObj) const override;

    MAP_DEFINITION_START(CStructureMap)
    /** [creationOpts] world YAML to load (empty: start empty). */
    std::string world_file;
    /** [creationOpts] chord tolerance of cylinder polygons [m]. */
    double cylinder_tolerance_m = kDefaultCylinderTolerance_m;
    /** [creationOpts] ray-casting grid cell [m]; 0 chooses it automatically; a smaller value
     *  than 0.01 is raised to it (the rays cast the same, only faster). */
    double raycast_cell_m = 0;
    /** [likelihoodOpts] */
    CStructureMap::TLikelihoodOptions likelihoodOpts;
    MAP_DEFINITION_END(CStructureMap)

private:
    void internal_clear() override;
    bool internal_insertObservation(
        const mrpt::obs::CObservation& obs,
        const std::optional<const mrpt::poses::CPose3D>& robotPose = std::nullopt) override;
    double internal_computeObservationLikelihood(
        const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& takenFrom) const override;
    bool internal_canComputeObservationLikelihood(
        const mrpt::obs::CObservation& obs) const override;

    RayCaster m_caster;
    /** World name (display). */
    std::string m_name;
    /** Cell requested at the last setSegments (0: automatic), kept for serialization. */
    double m_requestedCell_m = 0;
};

}  // namespace semloc
