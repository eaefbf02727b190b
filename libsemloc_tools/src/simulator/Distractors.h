/* semloc — the simulator's distractors: unmapped objects under the world's labels that move
 * (private). */
#pragma once

#include <semloc/simulator/SemanticDetectorModel.h>
#include <semloc/world/World.h>

#include <vector>

namespace mrpt::random
{
class CRandomGenerator;
}

namespace semloc::detail
{
/** [SemanticDetector] distractors: each starts at a pose uniform over the world's free space
 *  (its heading the direction it keeps), with a label uniform over the detector's labels,
 *  and moves at distractor_speed_mps in a straight line, reflected at the world's bounds.
 *  Only the start is random (its own stream): with no distractors nothing is drawn. */
class Distractors
{
public:
    Distractors(const World& world, const SemanticDetectorModel& detector,
                mrpt::random::CRandomGenerator& rng);

    /** Moves every distractor for dt seconds. */
    void step(double dt);

    /** Where they are now. */
    const std::vector<SemanticDetectorModel::TDistractor>& now() const { return m_now; }

private:
    WorldBounds m_bounds;
    double m_speed = 0;
    std::vector<SemanticDetectorModel::TDistractor> m_now;
    std::vector<double> m_heading;
};
}  // namespace semloc::detail
