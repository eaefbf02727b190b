/* semloc — the odometry's heading drift as a state of every particle. */
#include "filter/HeadingDrift.h"

#include <mrpt/core/exceptions.h>
#include <mrpt/system/datetime.h>

namespace semloc::detail
{
void HeadingDrift::reset(size_t count, mrpt::random::CRandomGenerator& rng)
{
    m_rate.resize(count);
    for (size_t i = 0; i < count; i++)
    {
        redraw(i, rng);
    }
}

void HeadingDrift::match(size_t count, mrpt::random::CRandomGenerator& rng)
{
    if (m_rate.size() != count)
    {
        reset(count, rng);
    }
}

double HeadingDrift::elapsed(mrpt::Clock::time_point t)
{
    if (t == INVALID_TIMESTAMP)
    {
        THROW_EXCEPTION(
            "[MotionModel] heading_drift_*: the heading drift model needs timestamped "
            "observations (every frame's first observation, or its odometry action, carries "
            "its time)");
    }
    double dt = 0;
    if (m_last && t > *m_last)
    {
        dt = mrpt::system::timeDifference(*m_last, t);
    }
    if (!m_last || t > *m_last)
    {
        m_last = t;
    }
    return dt;
}
}  // namespace semloc::detail
