/* semloc — the semantic detector's silences in a simulation (private). */
#pragma once

#include <mrpt/random/RandomGenerators.h>
#include <semloc/simulator/SemanticDetectorModel.h>

#include <cmath>

#include "simulator/SimRandom.h"

namespace semloc::detail
{
/** The detector's silences ([SemanticDetector] gap_every_s, gap_min_s, gap_max_s): starts
 *  an exponential time apart (from the end of the previous one), lengths uniform. */
class Silences
{
public:
    Silences(const SemanticDetectorModel::TOptions& o, double t0,
             mrpt::random::CRandomGenerator& rng)
        : m_o(o), m_rng(rng)
    {
        m_start = m_end = t0;
        next();
    }
    /** True if the detector is silent at time t (times must not decrease). */
    bool silent(double t)
    {
        while (m_o.gap_every_s > 0 && t >= m_end)
        {
            next();
        }
        return m_o.gap_every_s > 0 && t >= m_start && t < m_end;
    }

private:
    void next()
    {
        if (m_o.gap_every_s <= 0)
        {
            return;
        }
        const double wait = -m_o.gap_every_s * std::log(1.0 - detail::uniform01(m_rng));
        m_start = m_end + wait;
        m_end =
            m_start + m_o.gap_min_s + (m_o.gap_max_s - m_o.gap_min_s) * detail::uniform01(m_rng);
    }
    const SemanticDetectorModel::TOptions& m_o;
    mrpt::random::CRandomGenerator& m_rng;
    double m_start = 0, m_end = 0;
};
}  // namespace semloc::detail
