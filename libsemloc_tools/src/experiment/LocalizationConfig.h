/* semloc — a localization run's configuration written back: config.ini (private). */
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <semloc/experiment/LocalizationExperiment.h>
#include <semloc/maps/LocalizationMap.h>

#include <string>
#include <utility>
#include <vector>

namespace semloc::detail
{
/** Throws "ini [SECTION]: unknown section (semloc-localize reads ...)" unless semloc-localize
 *  reads `section` (its own sections and [MetricMap_...], whose names LocalizationMap checks). */
void checkLocalizeSection(const std::string& section);

/** config.ini: the effective configuration of a run configured by `o` (every key of our
 *  sections, defaults included), the pf-localization keys it only carried over (`carried`)
 *  and the map sections of `ini` (LocalizationMap::effectiveConfig). */
std::string effectiveConfigText(const LocalizationExperiment::TOptions& o,
                                const std::vector<std::pair<std::string, std::string>>& carried,
                                const LocalizationMap& maps,
                                const mrpt::config::CConfigFileBase& ini);

}  // namespace semloc::detail
