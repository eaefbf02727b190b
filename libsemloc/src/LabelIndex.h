/* semloc — string -> small integer interning for object labels (private). */
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace semloc
{
/** Maps labels to dense ids 0..size()-1. `find` is allocation-free and costs one
 *  hash of the label plus one probe on average: it runs once per detection per
 *  particle, where a std::unordered_map<std::string, ...> lookup would dominate. */
class LabelIndex
{
public:
    /** Id of `label`, adding it if new. */
    int intern(const std::string& label);
    /** Id of `label`, or -1 if unknown. */
    int find(std::string_view label) const noexcept;
    /** Number of distinct labels. */
    size_t size() const { return m_names.size(); }
    /** Label of an id. */
    const std::string& name(int id) const { return m_names[static_cast<size_t>(id)]; }
    void clear();

private:
    static uint64_t hash(std::string_view s) noexcept;
    void rehash(size_t slots);

    std::vector<std::string> m_names;
    std::vector<uint64_t> m_hashes;
    std::vector<int32_t> m_slots;  // power-of-two open addressing, -1 = empty
};

}  // namespace semloc
