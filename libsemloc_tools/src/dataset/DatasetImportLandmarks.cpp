/* semloc — DatasetImport's landmarks: semloc-import's landmarks CSV file read into landmarks or
 * a LandmarkSet, and the world around them (docs/tools.md, "semloc-import"). */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <semloc/dataset/DatasetImport.h>
#include <semloc/dataset/GroundTruthFile.h>
#include <semloc/dataset/LandmarkImport.h>
#include <semloc/io/ErrorMessage.h>
#include <semloc/observation/Labels.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <istream>
#include <limits>
#include <utility>
#include <vector>

#include "dataset/CsvTable.h"
#include "dataset/ImportCells.h"

namespace semloc
{
using detail::CsvTable;

namespace
{
constexpr long kMaxId = std::numeric_limits<int32_t>::max();

/** The id of row `r` if its cell is one (integerCell's rule, without throwing). */
bool validId(const CsvTable& t, size_t r, long& id)
{
    const std::string text = t.text(r, "id");
    if (text.empty() || text.size() > 10 ||
        !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; }))
    {
        return false;
    }
    id = std::stol(text);
    return id >= 1 && id <= kMaxId;
}

/** The first row whose id an earlier row has (SIZE_MAX if none) and that earlier row: found
 *  from the ids alone before the rows are checked in order (16 bytes a row, where a map of
 *  the ids seen took 48), so the error is the one a row-by-row check meets first. */
std::pair<size_t, size_t> firstRepeatedId(const CsvTable& t)
{
    std::vector<std::pair<long, size_t>> ids;
    ids.reserve(t.rows());
    for (size_t r = 0; r < t.rows(); r++)
    {
        if (long id = 0; validId(t, r, id))
        {
            ids.emplace_back(id, r);
        }
    }
    std::sort(ids.begin(), ids.end());
    std::pair<size_t, size_t> first = {std::numeric_limits<size_t>::max(), 0};
    for (size_t k = 1, group = 0; k < ids.size(); k++)
    {
        group = ids[k].first == ids[k - 1].first ? group : k;
        if (ids[k].first == ids[group].first && k > group && ids[k].second < first.first)
        {
            first = {ids[k].second, ids[group].second};
        }
    }
    return first;
}

/** Every row of the landmarks table, checked in file order: `take(landmark)` with
 *  object.sigma_m set. */
void forEachLandmark(const CsvTable& t, const std::function<void(const ImportedLandmark&)>& take)
{
    const auto [repeated, firstOfId] = firstRepeatedId(t);
    for (size_t r = 0; r < t.rows(); r++)
    {
        ImportedLandmark l;
        const long id = detail::integerCell(t, r, "id", 1, kMaxId);
        if (r == repeated)
        {
            t.fail(r, "id",
                   mrpt::format("duplicate id %ld (first on line %zu)", id, t.line(firstOfId)));
        }
        l.object.id = static_cast<int>(id);
        l.object.label = t.text(r, "label");
        if (const std::string p = labelProblem(l.object.label); !p.empty())
        {
            t.fail(r, "label", p);
        }
        l.object.shape = ShapeType::Point;
        l.object.center = {detail::positionCell(t, r, "x"), detail::positionCell(t, r, "y")};
        // Metres up from the surface (docs/design.md, "The water column"): 0 when not given.
        l.object.z = t.empty(r, "z") ? 0.0 : detail::positionCell(t, r, "z");
        for (auto [col, sigma] :
             {std::pair{"sigma_x_m", &l.sigma_x_m}, {"sigma_y_m", &l.sigma_y_m}})
        {
            *sigma = t.numberOr(r, col, std::numeric_limits<double>::quiet_NaN());
            if (*sigma < 0 || *sigma > kMaxWorldCoordinate_m)
            {
                t.fail(r, col, "a standard deviation must be in [0, 1e7] [m]");
            }
        }
        const bool hasX = !std::isnan(l.sigma_x_m), hasY = !std::isnan(l.sigma_y_m);
        if (hasX != hasY)
        {
            t.fail(r, hasX ? "sigma_x_m" : "sigma_y_m",
                   std::string("given without ") + (hasX ? "sigma_y_m" : "sigma_x_m") +
                       ": give both standard deviations or neither");
        }
        // The world's position uncertainty is isotropic: the one of the same total variance.
        l.object.sigma_m =
            hasX ? std::sqrt(0.5 * (l.sigma_x_m * l.sigma_x_m + l.sigma_y_m * l.sigma_y_m)) : 0.0;
        take(l);
    }
    if (t.rows() == 0)
    {
        THROW_EXCEPTION("'" + t.name() + "' holds no landmarks");
    }
}

const std::vector<std::string> kRequired = {"id", "label", "x", "y"};
const std::vector<std::string> kOptional = {"sigma_x_m", "sigma_y_m", "z"};

std::vector<ImportedLandmark> landmarksOf(std::istream* in, const std::string& path)
{
    const auto t = detail::openTable(in, path, kRequired, kOptional);
    std::vector<ImportedLandmark> out;
    out.reserve(t.rows());
    forEachLandmark(t, [&](const ImportedLandmark& l) { out.push_back(l); });
    return out;
}
}  // namespace

std::vector<ImportedLandmark> DatasetImport::readLandmarks(const std::string& path)
{
    return landmarksOf(nullptr, path);
}

std::vector<ImportedLandmark> DatasetImport::readLandmarks(std::istream& in,
                                                           const std::string& name)
{
    return landmarksOf(&in, name);
}

LandmarkSet DatasetImport::readLandmarkSet(const std::string& path)
{
    const auto t = detail::openTable(nullptr, path, kRequired, kOptional);
    LandmarkSet out;
    out.reserve(t.rows());
    forEachLandmark(t,
                    [&](const ImportedLandmark& l)
                    {
                        const auto& o = l.object;
                        out.add(o.id, o.label, o.center.x, o.center.y, o.z, o.sigma_m);
                    });
    return out;
}

World DatasetImport::makeWorldFrame(const LandmarkSet& landmarks,
                                    const std::vector<GroundTruthRow>& groundTruth, double margin_m,
                                    const std::string& name)
{
    return LandmarkImport::makeWorldFrame(landmarks, posesOf(groundTruth), margin_m, name);
}

}  // namespace semloc
