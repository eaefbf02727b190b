/* semloc — point landmarks held compactly: what the importers read a landmark map into and
 * write the world of, a million landmarks in 40 MB. */
#pragma once

#include <semloc/world/World.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

namespace semloc
{
/** Point landmarks, 40 bytes each (a WorldObject takes 176): the landmark maps of
 *  semloc-import and semloc-import-landmarks as they are read, checked and written as a world
 *  file (World::saveToFile(path, objectList())) without ever standing as WorldObjects. */
class LandmarkSet
{
public:
    /** One landmark. */
    struct Landmark
    {
        /** Object id (positive in a world). */
        int32_t id = 0;
        /** Index of its label in labels(). */
        uint32_t label = 0;
        /** Position [m] and height (`z`) [m]. */
        double x = 0, y = 0, z = 0;
        /** Standard deviation of its position [m] (WorldObject::sigma_m). */
        double sigma_m = 0;
    };

    /** Adds a landmark labelled `label` (the labels are held once each). */
    void add(int32_t id, const std::string& label, double x, double y, double z = 0,
             double sigma_m = 0);
    /** Makes room for `n` landmarks (a file's rows counted first: no copies while it grows). */
    void reserve(size_t n) { m_landmarks.reserve(n); }

    size_t size() const { return m_landmarks.size(); }
    bool empty() const { return m_landmarks.empty(); }
    const Landmark& operator[](size_t i) const { return m_landmarks[i]; }
    /** The distinct labels, in the order of their first landmark. */
    const std::vector<std::string>& labels() const { return m_labels; }
    const std::string& labelOf(size_t i) const { return m_labels[m_landmarks[i].label]; }

    /** Landmark i as a world's point object (id, label, centre, z, sigma_m). */
    WorldObject object(size_t i) const;
    /** Every landmark as object(i), for World::saveToFile(path, list) (the set must outlive
     *  the list). */
    WorldObjectList objectList() const;

private:
    std::vector<Landmark> m_landmarks;
    std::vector<std::string> m_labels;
    std::unordered_map<std::string, uint32_t> m_labelIndex;
};
}  // namespace semloc
