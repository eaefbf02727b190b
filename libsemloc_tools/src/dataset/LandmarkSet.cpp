/* semloc — LandmarkSet: point landmarks held compactly. */
#include <mrpt/core/exceptions.h>
#include <semloc/dataset/LandmarkSet.h>

namespace semloc
{
void LandmarkSet::add(int32_t id, const std::string& label, double x, double y, double z,
                      double sigma_m)
{
    auto it = m_labelIndex.find(label);
    if (it == m_labelIndex.end())
    {
        ASSERT_LT_(m_labels.size(), size_t{UINT32_MAX});
        it = m_labelIndex.emplace(label, static_cast<uint32_t>(m_labels.size())).first;
        m_labels.push_back(label);
    }
    Landmark l;
    l.id = id;
    l.label = it->second;
    l.x = x;
    l.y = y;
    l.z = z;
    l.sigma_m = sigma_m;
    m_landmarks.push_back(l);
}

WorldObject LandmarkSet::object(size_t i) const
{
    const Landmark& l = m_landmarks.at(i);
    WorldObject o;
    o.id = l.id;
    o.label = m_labels[l.label];
    o.shape = ShapeType::Point;
    o.center = {l.x, l.y};
    o.z = l.z;
    o.sigma_m = l.sigma_m;
    return o;
}

WorldObjectList LandmarkSet::objectList() const
{
    WorldObjectList list;
    list.count = size();
    list.at = [this](size_t i) { return object(i); };
    return list;
}
}  // namespace semloc
