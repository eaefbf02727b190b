/* semloc — LabelIndex implementation. */
#include "LabelIndex.h"

#include <algorithm>

namespace semloc
{
uint64_t LabelIndex::hash(std::string_view s) noexcept
{
    // FNV-1a, 64 bit: labels are short words, so a simple byte hash is cheapest.
    uint64_t h = 14695981039346656037ull;
    for (const char c : s)
    {
        h ^= static_cast<unsigned char>(c);
        h *= 1099511628211ull;
    }
    return h;
}

void LabelIndex::clear()
{
    m_names.clear();
    m_hashes.clear();
    m_slots.clear();
}

void LabelIndex::rehash(size_t slots)
{
    m_slots.assign(slots, -1);
    for (size_t i = 0; i < m_names.size(); i++)
    {
        size_t k = m_hashes[i] & (slots - 1);
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
    const uint64_t h = hash(label);
    const size_t mask = m_slots.size() - 1;
    for (size_t k = h & mask;; k = (k + 1) & mask)
    {
        const int32_t i = m_slots[k];
        if (i < 0)
        {
            return -1;
        }
        if (m_hashes[static_cast<size_t>(i)] == h && m_names[static_cast<size_t>(i)] == label)
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
    m_hashes.push_back(hash(label));
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
