/* semloc — CParallelMonteCarloLocalization2D's motion model and the particles' motion states
 * (the odometry's heading drift rates). */
#include <mrpt/core/exceptions.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/filter/CParallelMonteCarloLocalization2D.h>
#include <semloc/filter/ParticleMotionModel.h>

#include <cmath>

#include "filter/ParticleStore.h"
#include "filter/RecoveryPolicy.h"
#include "filter/Weights.h"

namespace semloc
{
void CParallelMonteCarloLocalization2D::setMotionModel(std::shared_ptr<ParticleMotionModel> model)
{
    ASSERTMSG_(model, "setMotionModel: no model");
    m_motion = std::move(model);
    resetMotionState();
}

void CParallelMonteCarloLocalization2D::setHeadingDrift(double priorStd, double walkStd)
{
    auto odometry = std::make_shared<OdometryMotionModel>();
    odometry->setHeadingDrift(priorStd, walkStd);
    setMotionModel(std::move(odometry));
}

void CParallelMonteCarloLocalization2D::resetMotionState()
{
    m_recovery->challengers().clear();  // another run's hypothesis, or another model's states
    m_motion->reset();
    m_store->assign(m_particles, *m_motion, mrpt::random::getRandomGenerator());
}

void CParallelMonteCarloLocalization2D::adoptParticles()
{
    m_store->adopt(m_particles, *m_motion, mrpt::random::getRandomGenerator());
}

std::vector<double> CParallelMonteCarloLocalization2D::motionStates() const
{
    const size_t n = m_store->particles.size() * m_store->dim();
    return n ? std::vector<double>(m_store->state(0), m_store->state(0) + n)
             : std::vector<double>();
}

std::vector<double> CParallelMonteCarloLocalization2D::meanMotionState() const
{
    const auto& particles = m_store->particles;
    const size_t dim = m_store->dim();
    if (dim == 0 || particles.empty())
    {
        return {};
    }
    const double maxW = detail::minMaxLogWeights(particles, *m_executor).max;
    std::vector<double> sum(dim, 0.0);
    double sumW = 0;
    for (size_t i = 0; i < particles.size(); i++)
    {
        const double w = std::exp(particles[i].log_w - maxW);
        for (size_t d = 0; d < dim; d++)
        {
            sum[d] += w * m_store->state(i)[d];
        }
        sumW += w;
    }
    for (double& v : sum)
    {
        v = sumW > 0 ? v / sumW : 0;
    }
    return sum;
}

double CParallelMonteCarloLocalization2D::headingDriftRate() const
{
    const auto* odometry = dynamic_cast<const OdometryMotionModel*>(m_motion.get());
    if (!odometry || !odometry->headingDrift())
    {
        return 0;
    }
    const auto mean = meanMotionState();
    return mean.empty() ? 0 : mean[0];
}

std::vector<double> CParallelMonteCarloLocalization2D::headingDriftRates() const
{
    const auto* odometry = dynamic_cast<const OdometryMotionModel*>(m_motion.get());
    return odometry && odometry->headingDrift() ? motionStates() : std::vector<double>();
}
}  // namespace semloc
