/* semloc — the motion model of a DVL's body-frame velocities (surge, sway, yaw rate). */
#pragma once

#include <semloc/filter/ParticleMotionModel.h>

#include <cstdint>

namespace semloc
{
/** A DVL's dead reckoning as the prediction (`[MotionModel] kind = dvl`): each step's
 *  increment (du, dv, dpsi) in the vehicle's frame, surge and sway over the ground times the
 *  step's time and the heading's change (the rawlog's CActionRobotMovement2D raw increment:
 *  semloc-import integrates `vx, vy, w` into it), is moved by independent Gaussian noise in
 *  each body axis whose standard deviation is a share of the distance travelled:
 *
 *      sigma_uv  = max(a1 d, minStdXY)                  (both axes: an AUV crabs in a current)
 *      sigma_psi = max(a3 d + a4 |dpsi|, minStdPHI)     d = hypot(du, dv)
 *
 *  the `[MotionModel]` keys a1 [m/m], a3 [deg/m], a4 [deg/deg], minStdXY [m], minStdPHI [deg]
 *  (MRPT's rotation-translation model instead charges the noise along and across the
 *  direction of travel, and needs a robot that does not slip sideways). Each particle's
 *  numbers come from its own stream keyed by one draw of MRPT's generator per step: the same
 *  bits for any thread count. */
class DvlMotionModel : public ParticleMotionModel
{
public:
    struct TNoise
    {
        double a1 = 0.01, a3_deg = 1, a4 = 0.05, minStdXY = 0.01, minStdPHI_deg = 0.2;
    };
    explicit DvlMotionModel(const TNoise& noise) : m_noise(noise) {}

    void prepare(const TMotionStep& step, mrpt::random::CRandomGenerator& rng) override;
    void move(size_t i0, size_t n, mrpt::math::TPose2D* poses, double* states) const override;

    /** The step's increment and its noise (what prepare() found). */
    mrpt::math::TPose2D increment() const { return m_increment; }
    double sigmaXY() const { return m_sigmaXY; }
    double sigmaPhi() const { return m_sigmaPhi; }

private:
    TNoise m_noise;
    mrpt::math::TPose2D m_increment{0, 0, 0};
    double m_sigmaXY = 0, m_sigmaPhi = 0;
    uint64_t m_key = 0;
    bool m_prepared = false;
};

}  // namespace semloc
