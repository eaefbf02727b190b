/* semloc — LabelIndex implementation. */
#include "models/semantic/LabelIndex.h"

#include <algorithm>
#include <cstring>

namespace semloc
{
LabelIndex::Key LabelIndex::keyOf(std::string_view s) noexcept
{
    Key k{s.size(), 0, 0};
    const size_t n = std::min<size_t>(8, s.size());
    std::memcpy(&k.head, s.data(), n);
    std::memcpy(&k.tail, s.data() + s.size() - n, n);
    return k;
}

uint64_t LabelIndex::hashOf(const Key& k) noexcept
{
    uint64_t h = k.head * 0x9E3779B97F4A7C15ull ^ (k.tail + k.len) * 0xC2B2AE3D27D4EB4Full;
    return h ^ (h >> 29);
}

void LabelIndex::clear()
{
    m_names.clear();
    m_keys.clear();
    m_slots.clear();
}

void LabelIndex::rehash(size_t slots)
{
    m_slots.assign(slots, -1);
    for (size_t i = 0; i < m_names.size(); i++)
    {
        size_t k = hashOf(m_keys[i]) & (slots - 1);
        while (m_slots[k] >= 0)
        {
            k = (k + 1) & (slots - 1);
        }
        m_slots[k] = static_cast<int32_t>(i);
    }
}

int LabelIndex::find(std::string_view label) const noexcept
{
    if (m_slots.empty())
    {
        return -1;
    }
    const Key key = keyOf(label);
    const size_t mask = m_slots.size() - 1;
    for (size_t k = hashOf(key) & mask;; k = (k + 1) & mask)
    {
        const int32_t i = m_slots[k];
        if (i < 0)
        {
            return -1;
        }
        if (m_keys[static_cast<size_t>(i)] == key &&
            (key.len <= 16 || m_names[static_cast<size_t>(i)] == label))
        {
            return i;
        }
    }
}

int LabelIndex::intern(const std::string& label)
{
    if (const int i = find(label); i >= 0)
    {
        return i;
    }
    m_names.push_back(label);
    m_keys.push_back(keyOf(label));
    // Keep the table at most 1/4 full so probes stay short.
    size_t slots = 16;
    while (slots < 4 * m_names.size())
    {
        slots *= 2;
    }
    rehash(slots);
    return static_cast<int>(m_names.size() - 1);
}

}  // namespace semloc
