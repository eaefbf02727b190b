/* semloc — DatasetImport: what real logs bring that the format's rules settle, counted for the
 * summary line and warned about: the ground truth at the steps (none inside a long gap), the
 * detections no landmark explains, and the summary's counts. */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <semloc/dataset/DatasetImport.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "io/Text.h"

namespace semloc
{
namespace
{
/** "1 step" or "3 steps". */
std::string counted(size_t n, const char* one, const char* many)
{
    return std::to_string(n) + " " + (n == 1 ? one : many);
}

/** The ids as ranges: "2-5, 9, 11-12", at most `most` ranges and then ", …". */
std::string idRanges(const std::set<int>& ids, size_t most = 4)
{
    std::string s;
    size_t ranges = 0;
    for (auto it = ids.begin(); it != ids.end();)
    {
        const int first = *it;
        int last = first;
        for (++it; it != ids.end() && *it == last + 1; ++it)
        {
            last = *it;
        }
        if (ranges++ == most)
        {
            return s + ", \u2026";
        }
        s += (s.empty() ? "" : ", ") + std::to_string(first) +
             (last > first ? "-" + std::to_string(last) : std::string());
    }
    return s;
}

/** Detections of one kind (no landmark, an id no landmark has...), by label. */
struct DetectionKind
{
    size_t count = 0;
    std::map<std::string, std::pair<size_t, std::set<int>>> byLabel;  // count, ids

    void add(const TSemanticDetection& d)
    {
        count++;
        auto& [n, ids] = byLabel[d.label];
        n++;
        if (d.object_id > 0)
        {
            ids.insert(d.object_id);
        }
    }

    /** "label robot, ids 2-5: 407; label rock, no id: 12; and 2 more labels", by count. */
    std::string examples() const
    {
        std::vector<std::pair<size_t, std::string>> order;
        for (const auto& [label, v] : byLabel)
        {
            order.emplace_back(v.first, label);
        }
        std::sort(order.begin(), order.end(),
                  [](const auto& a, const auto& b)
                  { return a.first != b.first ? a.first > b.first : a.second < b.second; });
        std::string s;
        for (size_t k = 0; k < order.size() && k < 3; k++)
        {
            const auto& ids = byLabel.at(order[k].second).second;
            s += (k ? "; label " : "label ") + order[k].second + ", " +
                 (ids.empty() ? std::string("no id")
                              : (ids.size() == 1 ? "id " : "ids ") + idRanges(ids)) +
                 ": " + std::to_string(order[k].first);
        }
        return order.size() > 3
                   ? s + "; and " + counted(order.size() - 3, "more label", "more labels")
                   : s;
    }
};

/** The warnings of checkLandmarks(). */
void warnLandmarks(const DetectionKind& unknown, const DetectionKind& idNotLandmark,
                   const DetectionKind& otherLabel, TDatasetImportStats& stats)
{
    if (unknown.count > 0)
    {
        stats.warnings.push_back(
            counted(unknown.count, "detection is", "detections are") + " of no landmark (" +
            unknown.examples() +
            "): kept; semloc-localize counts them as detections_unknown: unknown to the map, "
            "they weigh every particle alike");
    }
    if (idNotLandmark.count > 0)
    {
        stats.warnings.push_back(
            counted(idNotLandmark.count, "detection has", "detections have") +
            " an id no landmark has (" + idNotLandmark.examples() +
            "): kept; semloc-localize associates them by their label, as detections without an "
            "id (a landmark of that label, or clutter)");
    }
    if (otherLabel.count > 0)
    {
        stats.warnings.push_back(counted(otherLabel.count, "detection has", "detections have") +
                                 " a landmark's id and another label (" + otherLabel.examples() +
                                 "): kept; semloc-localize associates them by their id");
    }
}
/** The warning of the ground truth's gaps, the longest from `from` to `to`. */
void warnGaps(const std::string& path, double from, double to, TDatasetImportStats& st)
{
    const bool one = st.groundTruthGaps == 1;
    st.warnings.push_back(mrpt::format(
        "ground truth '%s': %s longer than %s s (--gt-max-gap-s; %s%s s, from %s to %s) %s %s: "
        "they have no ground-truth row (semloc-localize gives them no error) rather than a pose "
        "interpolated across the gap",
        path.c_str(), counted(st.groundTruthGaps, "gap", "gaps").c_str(),
        detail::shortestText(st.groundTruthMaxGap_s).c_str(), one ? "" : "the longest ",
        detail::timeText(to - from).c_str(), detail::timeText(from).c_str(),
        detail::timeText(to).c_str(), one ? "holds" : "hold",
        counted(st.stepsInGroundTruthGaps, "step", "steps").c_str()));
}
}  // namespace

double DatasetImport::groundTruthMaxGap(const std::vector<GroundTruthRow>& gt, double option)
{
    if (option > 0)
    {
        return option;
    }
    std::vector<double> dt;
    for (size_t i = 1; i < gt.size(); i++)
    {
        dt.push_back(gt[i].t - gt[i - 1].t);
    }
    double median = 0;
    if (!dt.empty())
    {
        std::nth_element(dt.begin(), dt.begin() + static_cast<long>(dt.size() / 2), dt.end());
        median = dt[dt.size() / 2];
    }
    // To the microsecond, as times are (10 x 0.1 s apart is 1 s, not 1.0000000000000009).
    return std::max(kMinGroundTruthMaxGap_s,
                    std::round(kGroundTruthGapPeriods * median * 1e6) / 1e6);
}

std::vector<GroundTruthRow> DatasetImport::groundTruthAtSteps(const std::vector<GroundTruthRow>& gt,
                                                              const std::vector<ImportStep>& steps,
                                                              const std::string& path,
                                                              double maxGap_s,
                                                              TDatasetImportStats* stats)
{
    OdometryTrack track;  // the same interpolation as the odometry's
    for (const auto& r : gt)
    {
        track.t.push_back(r.t);
        track.pose.push_back({r.x, r.y, r.phi});
    }
    TDatasetImportStats local;
    TDatasetImportStats& st = stats != nullptr ? *stats : local;
    st.groundTruthMaxGap_s = groundTruthMaxGap(gt, maxGap_s);
    size_t gapEnd = 0, longest = 0;  // the row ending the current gap, the longest gap's
    std::vector<GroundTruthRow> out;
    for (const auto& s : steps)
    {
        if (s.t < track.t.front() || s.t > track.t.back())
        {
            st.stepsOutsideGroundTruth++;
            continue;
        }
        const auto i = static_cast<size_t>(std::upper_bound(track.t.begin(), track.t.end(), s.t) -
                                           track.t.begin());
        if (i < track.t.size() && track.t[i - 1] != s.t &&
            track.t[i] - track.t[i - 1] > st.groundTruthMaxGap_s)
        {
            st.stepsInGroundTruthGaps++;  // inside a gap: no row rather than a guess
            st.groundTruthGaps += i != gapEnd ? 1 : 0;
            gapEnd = i;
            const double gap = track.t[i] - track.t[i - 1];
            longest = longest == 0 || gap > track.t[longest] - track.t[longest - 1] ? i : longest;
            continue;
        }
        const auto p = track.at(s.t);
        out.push_back({s.t, p.x, p.y, p.phi});
    }
    if (longest > 0)
    {
        warnGaps(path, track.t[longest - 1], track.t[longest], st);
    }
    if (out.empty())
    {
        THROW_EXCEPTION(
            "ground truth '" + path + "' (times " + detail::timeText(gt.front().t) + " to " +
            detail::timeText(gt.back().t) + " s) covers no step (times " +
            detail::timeText(steps.front().t) + " to " + detail::timeText(steps.back().t) + " s" +
            (st.stepsInGroundTruthGaps > 0 ? "; " + std::to_string(st.stepsInGroundTruthGaps) +
                                                 " inside its gaps longer than " +
                                                 detail::shortestText(st.groundTruthMaxGap_s) + " s"
                                           : std::string()) +
            ")");
    }
    return out;
}

void DatasetImport::checkLandmarks(const std::vector<ImportStep>& steps,
                                   const std::vector<DetectionScan>& scans,
                                   const std::vector<ImportedLandmark>& landmarks,
                                   TDatasetImportStats& stats)
{
    LandmarkSet set;
    set.reserve(landmarks.size());
    for (const auto& l : landmarks)
    {
        set.add(l.object.id, l.object.label, l.object.center.x, l.object.center.y);
    }
    checkLandmarkSet(steps, scans, set, stats);
}

void DatasetImport::checkLandmarkSet(const std::vector<ImportStep>& steps,
                                     const std::vector<DetectionScan>& scans,
                                     const LandmarkSet& landmarks, TDatasetImportStats& stats)
{
    if (landmarks.empty())
    {
        return;
    }
    // The landmarks by id (the last of an id), 8 bytes each, and their labels.
    std::vector<std::pair<int32_t, uint32_t>> byId;
    byId.reserve(landmarks.size());
    for (size_t i = 0; i < landmarks.size(); i++)
    {
        byId.emplace_back(landmarks[i].id, static_cast<uint32_t>(i));
    }
    std::sort(byId.begin(), byId.end());
    const std::set<std::string> labels(landmarks.labels().begin(), landmarks.labels().end());
    auto labelOf = [&](int id) -> const std::string*
    {
        const auto it = std::upper_bound(byId.begin(), byId.end(),
                                         std::make_pair(id, std::numeric_limits<uint32_t>::max()));
        return it == byId.begin() || std::prev(it)->first != id
                   ? nullptr
                   : &landmarks.labelOf(std::prev(it)->second);
    };
    DetectionKind unknown, idNotLandmark, otherLabel;
    auto check = [&](const TSemanticDetection& d)
    {
        const std::string* label = d.object_id > 0 ? labelOf(d.object_id) : nullptr;
        if (label != nullptr)
        {
            if (*label != d.label)
            {
                otherLabel.add(d);
            }
        }
        else if (labels.count(d.label) == 0)
        {
            unknown.add(d);
        }
        else if (d.object_id > 0)
        {
            idNotLandmark.add(d);
        }
    };
    for (const auto& s : steps)
    {
        for (size_t k = 0; s.scan >= 0 && k < s.scanCount; k++)
        {
            for (const auto& d : scans[static_cast<size_t>(s.scan) + k].detections)
            {
                check(d);
            }
        }
    }
    stats.detectionsUnknown += unknown.count;
    stats.detectionsIdNotLandmark += idNotLandmark.count;
    stats.detectionsLabelNotLandmarks += otherLabel.count;
    warnLandmarks(unknown, idNotLandmark, otherLabel, stats);
}

namespace
{
/** The summary's parts of one reading file: "120 depth readings written (3 superseded, 1
 *  after the last step dropped), 2 repeated depth times (the later reading kept)". */
void addReadingCounts(std::vector<std::string>& parts, const TImportReadingCounts& c,
                      const char* one, const char* many, const char* what)
{
    if (c.written + c.superseded + c.dropped > 0)
    {
        std::string left;
        if (c.superseded > 0)
        {
            left = std::to_string(c.superseded) + " superseded";
        }
        if (c.dropped > 0)
        {
            left += (left.empty() ? "" : ", ") + std::to_string(c.dropped) +
                    " after the last step dropped";
        }
        parts.push_back(counted(c.written, one, many) + " written" +
                        (left.empty() ? std::string() : " (" + left + ")"));
    }
    if (c.repeatedTimes > 0)
    {
        parts.push_back(std::to_string(c.repeatedTimes) + " repeated " + what +
                        (c.repeatedTimes == 1 ? " time" : " times") + " (the later reading kept)");
    }
}

/** The summary's part of the scans by sensor, when any is not SEMANTIC: "scans by sensor:
 *  camera 420, sidescan 1388 (400 steps hold several)". */
void addSensorCounts(std::vector<std::string>& parts, const TDatasetImportStats& s)
{
    if (s.sensorScans.empty() ||
        (s.sensorScans.size() == 1 && s.sensorScans.begin()->first == kDefaultImportSensor))
    {
        return;
    }
    std::string text = "scans by sensor:";
    for (const auto& [label, n] : s.sensorScans)
    {
        text += (text.back() == ':' ? " " : ", ") + label + " " + std::to_string(n);
    }
    if (s.stepsOfSeveralScans > 0)
    {
        text += " (" + counted(s.stepsOfSeveralScans, "step holds", "steps hold") + " several)";
    }
    parts.push_back(text);
}
}  // namespace

std::string DatasetImport::summaryCounts(const TDatasetImportStats& s)
{
    std::vector<std::string> parts;
    auto add = [&](size_t n, const std::string& text)
    {
        if (n > 0)
        {
            parts.push_back(text);
        }
    };
    addSensorCounts(parts, s);
    add(s.detectionsWithoutRange, counted(s.detectionsWithoutRange, "detection", "detections") +
                                      " without a range (bearing-only)");
    addReadingCounts(parts, s.depth, "depth reading", "depth readings", "depth");
    addReadingCounts(parts, s.heading, "heading reading", "heading readings", "heading");
    addReadingCounts(parts, s.fixes, "fix", "fixes", "fix");
    add(s.odometryRepeatedTimes,
        counted(s.odometryRepeatedTimes, "repeated odometry time", "repeated odometry times") +
            " (the later reading kept)");
    add(s.detectionsGrouped, counted(s.detectionsGrouped, "detection", "detections") +
                                 " grouped into scans within " +
                                 detail::shortestText(s.scanWindow_s) + " s");
    add(s.groundTruthRepeatedTimes,
        counted(s.groundTruthRepeatedTimes, "repeated ground-truth time",
                "repeated ground-truth times") +
            " (the later pose kept)");
    add(s.detectionsUnknown, counted(s.detectionsUnknown, "detection", "detections") +
                                 " of no landmark (unknown to the map)");
    add(s.detectionsIdNotLandmark, counted(s.detectionsIdNotLandmark, "detection", "detections") +
                                       " of an id no landmark has (associated by label)");
    add(s.detectionsLabelNotLandmarks,
        counted(s.detectionsLabelNotLandmarks, "detection", "detections") +
            " labelled unlike their landmark (associated by id)");
    add(s.stepsInGroundTruthGaps, counted(s.stepsInGroundTruthGaps, "step", "steps") +
                                      " without ground truth in " +
                                      counted(s.groundTruthGaps, "gap", "gaps") + " over " +
                                      detail::shortestText(s.groundTruthMaxGap_s) + " s");
    add(s.stepsOutsideGroundTruth, counted(s.stepsOutsideGroundTruth, "step", "steps") +
                                       " outside the ground truth's time span");
    std::string text;
    for (const auto& p : parts)
    {
        text += (text.empty() ? "" : ", ") + p;
    }
    return text;
}

}  // namespace semloc
