/* semloc — the kinds of map a localizer's [MetricMap] may hold, by name: what semloc does with
 * each beside what MRPT does (docs/design.md, "Adding a sensor model"). */
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/maps/CMetricMap.h>
#include <mrpt/maps/TMetricMapInitializer.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/rtti/CObject.h>
#include <semloc/models/BatchLikelihood.h>
#include <semloc/world/World.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace semloc
{
/** One kind of map of `[MetricMap]`: MRPT's registry creates the map from `<name>_count` and
 *  reads its `[MetricMap_<name>_NN_*]` sections (MAP_DEFINITION_REGISTER); this kind says what
 *  semloc does with it beside that: fill it from the world, name it in a variant, write its
 *  effective options and reference, refuse observations it cannot score. Every hook but
 *  name() and mapClass() has a default that does nothing.
 *
 *  semloc's kinds (the semantic and structure models, MRPT's occupancy grid and beacon map)
 *  are registered when the registry is first used; a program (or a test) registers its own
 *  with SensorModelRegistry::add() before it loads an ini. */
class SensorModelKind
{
public:
    virtual ~SensorModelKind() = default;

    /** The map's name in `[MetricMap] <name>_count` (its MRPT registry name). */
    virtual std::string name() const = 0;
    /** The class of its maps (a map of a class derived from it is of this kind too). */
    virtual const mrpt::rtti::TRuntimeClassId* mapClass() const = 0;

    /** The map's name in a variant (docs/design.md): name() by default. */
    virtual std::string variant(const mrpt::maps::CMetricMap& map) const
    {
        (void)map;
        return name();
    }

    /** What fill() sees of one map of the [MetricMap] being loaded. */
    struct TFill
    {
        mrpt::maps::CMetricMap& map;
        const mrpt::maps::TMetricMapInitializer& definition;
        /** "MetricMap_semanticMap_00": its sections are prefix + "_creationOpts"... */
        std::string prefix;
        /** "ini [MetricMap] semanticMap_count: ", to start a message about the map. */
        std::string countKey;
        /** The map file ("" none) and whether it is a world YAML. */
        std::string mapFile;
        bool mapFileIsWorld = false;
        /** The world: the map file's, else the first world a map's own options named (a map
         *  that loads one sets it when it is empty). */
        std::optional<World>& world;
        /** Out: the world file the map was filled from ("" for none), for effectiveConfig. */
        std::string worldFile{};
    };
    /** A BatchLikelihood that evaluates `map` (one of this kind's maps that is not a
     *  BatchLikelihood itself: MRPT's) on blocks of poses with the same values as its
     *  generic call, or nullptr (the default: the filter makes the generic call). It must
     *  not outlive `map`; one per map and filter. */
    virtual std::unique_ptr<BatchLikelihood> batchOf(const mrpt::maps::CMetricMap& map) const
    {
        (void)map;
        return nullptr;
    }

    /** Which pass fills the map: 0 (the default) in definition order, then 1 (a map that
     *  takes its contents from the world another map's options may have named). */
    virtual int fillPass() const { return 0; }
    /** Fills the map from the world or its own files; an error names the ini key or the file
     *  (a map left empty is one). Nothing by default. */
    virtual void fill(TFill& f) const { (void)f; }

    /** Writes the effective options of `definition` (defaults included) into its sections
     *  under `prefix`, with `worldFile` (what fill() gave) where the kind has one. Nothing by
     *  default: the input's keys are then kept as they were given. */
    virtual void writeOptions(const mrpt::maps::TMetricMapInitializer& definition,
                              mrpt::config::CConfigFileBase& out, const std::string& prefix,
                              const std::string& worldFile) const
    {
        (void)definition, (void)out, (void)prefix, (void)worldFile;
    }
    /** Writes the default of every key of its sections under `prefix`, each with its comment
     *  (semloc-ini-reference). Nothing by default. */
    virtual void writeReference(mrpt::config::CConfigFileBase& out, const std::string& prefix) const
    {
        (void)out, (void)prefix;
    }
    /** Why `obs` cannot be scored, as a phrase ("its fov_rad nan is not..."), or "" when it
     *  can (or is none of this kind's concern). Asked of every kind for every observation,
     *  with the filter's `map` (a CMultiMetricMap or one map): a kind may refuse an
     *  observation only where `map` holds one of its maps. */
    virtual std::string invalidObservation(const mrpt::obs::CObservation& obs,
                                           const mrpt::maps::CMetricMap& map) const
    {
        (void)obs, (void)map;
        return {};
    }

protected:
    SensorModelKind() = default;
    SensorModelKind(const SensorModelKind&) = default;
    SensorModelKind& operator=(const SensorModelKind&) = default;
};

/** The kinds by name (not safe against add() from another thread). */
class SensorModelRegistry
{
public:
    /** Registers `kind` (replacing one of the same name): its maps, created by MRPT's
     *  registry from `<name>_count`, are filled, named and written by it. */
    static void add(std::shared_ptr<const SensorModelKind> kind);
    /** Every kind, semloc's first, then in registration order. */
    static const std::vector<std::shared_ptr<const SensorModelKind>>& kinds();
    /** The kind of `map` (the first whose mapClass() it derives from), or nullptr. */
    static const SensorModelKind* of(const mrpt::maps::CMetricMap& map);
    /** The kind of the maps `definition` creates, or nullptr. */
    static const SensorModelKind* of(const mrpt::maps::TMetricMapInitializer& definition);
};

}  // namespace semloc
