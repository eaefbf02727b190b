/* semloc — string -> small integer interning for object labels (private). */
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace semloc
{
/** Maps labels to dense ids 0..size()-1. `find` runs once per detection per particle,
 *  where a std::unordered_map<std::string, ...> lookup would dominate: labels are keyed
 *  by (length, first 8 bytes, last 8 bytes), which identifies any label of up to 16
 *  bytes without a byte loop or memcmp; longer labels are compared in full. */
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
    struct Key
    {
        uint64_t len, head, tail;
        bool operator==(const Key& o) const
        {
            return len == o.len && head == o.head && tail == o.tail;
        }
    };
    static Key keyOf(std::string_view s) noexcept;
    static uint64_t hashOf(const Key& k) noexcept;
    void rehash(size_t slots);

    std::vector<std::string> m_names;
    std::vector<Key> m_keys;
    std::vector<int32_t> m_slots;  // power-of-two open addressing, -1 = empty
};

}  // namespace semloc
