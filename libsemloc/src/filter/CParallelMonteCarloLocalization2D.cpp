/* semloc — CParallelMonteCarloLocalization2D: MRPT's MCL step with per-particle work on a
 * thread pool, a never-empty particle set and augmented-MCL recovery. */
#include <mrpt/core/exceptions.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/random/RandomGenerators.h>
#include <semloc/filter/CParallelMonteCarloLocalization2D.h>
#include <semloc/filter/DetectionPoseSampler.h>
#include <semloc/filter/ParallelExecutor.h>
#include <semloc/maps/CSemanticMap.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <type_traits>

#include "filter/ExpFast.h"
#include "filter/FastMath.h"
#include "filter/Ziggurat.h"

namespace semloc
{
using mrpt::math::TPose2D;

namespace
{
constexpr double kNegInf = -std::numeric_limits<double>::infinity();
/** Smallest range a thread claims of a loop of a few nanoseconds per particle (max/min scans,
 *  weight shifts): the pool's threads poll between the calls of a step, so a call costs a
 *  microsecond or two, a few thousand particles' worth (the results are the same either
 *  way). */
constexpr size_t kCheapLoopGrain = 2048;
/** Loops that copy a particle or do a little more per particle (~10 ns). */
constexpr size_t kCopyLoopGrain = 1024;
/** Loops with a sin and a cos per particle (~25 ns): the estimate's. */
constexpr size_t kTrigLoopGrain = 512;
/** Loops with an exp() per particle (~20 ns) are worth splitting from this many on. */
constexpr size_t kExpLoopChunk = 4096;
/** Smallest range of the prediction + likelihood pass a thread claims (~1 us per particle):
 *  small enough for the threads to finish within a few tens of microseconds of each other. */
constexpr size_t kParticleGrain = 128;

using detail::Vec2;

/** mrpt::math::wrapToPi, bit for bit, without its fmod for angles within a turn of the
 *  range: fmod(t, 2 pi) is exactly t for 0 <= t < 2 pi, and exactly t - 2 pi for
 *  2 pi <= t < 4 pi (fmod is exact, and so is that subtraction: Sterbenz). The second case
 *  is MRPT's getCovarianceAndMean's, whose heading errors |phi - mean| are taken against a
 *  mean moved to [0, 2 pi). */
inline double wrapToPiExact(double a)
{
    const double t = a + M_PI;
    if (t >= 0 && t < 2 * M_PI)
    {
        return t - M_PI;
    }
    if (t >= 2 * M_PI && t < 4 * M_PI)
    {
        return (t - 2 * M_PI) - M_PI;
    }
    return mrpt::math::wrapToPi(a);
}

/** Standard normal draws of one particle: a splitmix64 sequence (Steele, Lea & Flood 2014)
 *  started from (step key, particle index), turned into normals by the ziggurat method. A
 *  particle's numbers depend on nothing else, so any thread may draw them: the same bits for
 *  any thread count, and no shared generator to serialize on. */
class ParticleNormals
{
public:
    ParticleNormals(uint64_t key, size_t particle)
        : m_state(key ^ (static_cast<uint64_t>(particle) * 0xD1B54A32D192ED03ull))
    {
    }

    /** One N(0, 1). */
    double operator()()
    {
        return detail::Ziggurat::draw([this] { return next(); });
    }

private:
    uint64_t next()
    {
        uint64_t z = (m_state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    uint64_t m_state;
};

/** Calls `run(first, i, n)` for the runs of particles [b, e) of `particles` (a std::deque)
 *  that lie contiguously in memory: first points at particle i, the run holds n. The loops
 *  over a run are plain pointer loops, without the deque iterator's end-of-node check (and
 *  its branch) per particle. libstdc++ exposes its node bounds; elsewhere runs of one. */
template <typename Particles, typename Run>
void forEachRun(Particles& particles, size_t b, size_t e, Run&& run)
{
    auto it = particles.begin() + static_cast<ptrdiff_t>(b);
    while (b < e)
    {
#if defined(__GLIBCXX__)
        const size_t n = std::min(e - b, static_cast<size_t>(it._M_last - it._M_cur));
#else
        const size_t n = 1;
#endif
        run(&*it, b, n);
        b += n;
        if (b < e)
        {
            it += static_cast<ptrdiff_t>(n);
        }
    }
}

/** Adds logW(k) for k in [0, n) to `even` (k even) or `odd` (k odd): two dependency chains
 *  of max and min instead of one, the same extremes. */
template <typename Range, typename LogW>
void addExtremes(size_t n, Range& even, Range& odd, LogW&& logW)
{
    size_t k = 0;
    for (; k + 1 < n; k += 2)
    {
        even.add(logW(k));
        odd.add(logW(k + 1));
    }
    if (k < n)
    {
        even.add(logW(k));
    }
}

/** Systematic resampling works on blocks of this many particles (any size gives the same
 *  indices; small blocks spread the copying evenly over the threads). */
constexpr size_t kResampleBlock = 256;
}  // namespace

/** Draws pose increments from a CPosePDFGaussian as MRPT's CPoseRandomSampler does
 *  (setPosePDF, do_sample_2D: mean + Z sqrt(D) n for the eigen-decomposition Z D Z^T of
 *  the covariance), with the normals n of ParticleNormals. */
class CParallelMonteCarloLocalization2D::GaussianIncrementDrawer
{
public:
    explicit GaussianIncrementDrawer(const mrpt::poses::CPosePDFGaussian& pdf)
        : m_meanXY{pdf.mean.x(), pdf.mean.y()}, m_meanPhi(pdf.mean.phi())
    {
        mrpt::math::CMatrixDouble33 Z;
        std::vector<double> eigVals;
        pdf.cov.eig_symmetric(Z, eigVals);
        mrpt::math::CMatrixDouble33 D;
        D.setDiagonal(eigVals);
        D = D.asEigen().array().sqrt().matrix();
        Z.matProductOf_AB(Z, D);
        for (int i = 0; i < 3; i++)
        {
            m_zxy[i] = Vec2{Z(0, i), Z(1, i)};
            m_zphi[i] = Z(2, i);
        }
    }

    TPose2D draw(ParticleNormals& rng) const
    {
        const double n0 = rng(), n1 = rng(), n2 = rng();
        // r = ((0 + Z(:,0) n0) + Z(:,1) n1) + Z(:,2) n2, x and y side by side (the same
        // operations, in the same order, as one coordinate at a time).
        const Vec2 rxy = ((Vec2{0, 0} + m_zxy[0] * n0) + m_zxy[1] * n1) + m_zxy[2] * n2;
        const double rphi = ((0 + m_zphi[0] * n0) + m_zphi[1] * n1) + m_zphi[2] * n2;
        const Vec2 xy = m_meanXY + rxy;
        return {xy[0], xy[1], wrapToPiExact(m_meanPhi + rphi)};
    }

private:
    Vec2 m_meanXY;
    double m_meanPhi;
    /** Columns of Z sqrt(D): rows x, y as pairs, row phi apart. */
    Vec2 m_zxy[3];
    double m_zphi[3];
};

namespace
{
/** Draws from the detections before falling back to a uniform pose: a detection near the
 *  map's border or an object leaves most of its circle in the free space. */
constexpr int kDetectionTries = 10;

/** The first CSemanticMap of `map` (itself, or in a CMultiMetricMap), else nullptr. */
const CSemanticMap* semanticMapOf(const mrpt::maps::CMetricMap* map)
{
    if (const auto* sem = dynamic_cast<const CSemanticMap*>(map))
    {
        return sem;
    }
    if (const auto* multi = dynamic_cast<const mrpt::maps::CMultiMetricMap*>(map))
    {
        return multi->mapByClass<CSemanticMap>().get();
    }
    return nullptr;
}

/** p (+) u for 2D poses, (s, c) = sin, cos of p.phi: (x + c ux - s uy, y + s ux + c uy), x
 *  and y side by side. */
inline TPose2D compose(const TPose2D& p, double s, double c, const TPose2D& u)
{
    // a - b is a + (-b) exactly: the same bits as the formula one coordinate at a time.
    const Vec2 xy = (Vec2{p.x, p.y} + Vec2{c, s} * u.x) + Vec2{-s, c} * u.y;
    return {xy[0], xy[1], wrapToPiExact(p.phi + u.phi)};
}

/** Moves the n particles p[0..n) (indices i0...) by their increments drawn from `drawer`
 *  with step key `key`, and copies the new poses to out. The headings' sin and cos two
 *  particles at a time (fastSinCos2: the same bits as one at a time). */
template <typename Drawer, typename Particle>
void movePoses(const Drawer& drawer, uint64_t key, Particle* p, size_t i0, size_t n, TPose2D* out)
{
    detail::forEachSinCos(
        n, [&](size_t k) { return p[k].d.phi; },
        [&](size_t k, double s, double c)
        {
            ParticleNormals normals(key, i0 + k);
            p[k].d = compose(p[k].d, s, c, drawer.draw(normals));
            out[k] = p[k].d;
        });
}
}  // namespace

CParallelMonteCarloLocalization2D::CParallelMonteCarloLocalization2D(size_t M)
    : CMonteCarloLocalization2D(M), m_executor(std::make_shared<ParallelExecutor>(1))
{
    setLoggerName("CParallelMonteCarloLocalization2D");
}

CParallelMonteCarloLocalization2D::~CParallelMonteCarloLocalization2D() = default;

void CParallelMonteCarloLocalization2D::setExecutor(std::shared_ptr<ParallelExecutor> executor)
{
    ASSERT_(executor);
    m_executor = std::move(executor);
}

void CParallelMonteCarloLocalization2D::setFreeSpaceSampler(
    std::shared_ptr<const FreeSpaceSampler> sampler)
{
    m_sampler = std::move(sampler);
}

void CParallelMonteCarloLocalization2D::setRecoveryOptions(const AugmentedMCL::TOptions& o)
{
    m_augmented = AugmentedMCL(o);
}

SensoryFrameLikelihood::TStats CParallelMonteCarloLocalization2D::likelihoodStats() const
{
    return m_likelihood ? m_likelihood->stats() : SensoryFrameLikelihood::TStats{};
}

void CParallelMonteCarloLocalization2D::prepareLikelihood()
{
    ASSERTMSG_(options.metricMap, "CParallelMonteCarloLocalization2D: no options.metricMap");
    if (!m_likelihood || m_likelihoodMap != options.metricMap.get())
    {
        m_likelihoodMap = options.metricMap.get();
        m_likelihood = std::make_unique<SensoryFrameLikelihood>(*m_likelihoodMap);
    }
    m_likelihood->prepare(*m_executor);
}

void CParallelMonteCarloLocalization2D::resetFromSampler(size_t particleCount)
{
    ASSERTMSG_(m_sampler, "resetFromSampler: no FreeSpaceSampler was set");
    ASSERT_(particleCount > 0);
    m_particles.resize(particleCount);
    auto& rng = mrpt::random::getRandomGenerator();
    for (auto& p : m_particles)
    {
        p.d = m_sampler->draw(rng);
        p.log_w = 0;
    }
}

void CParallelMonteCarloLocalization2D::prediction_and_update_pfStandardProposal(
    const mrpt::obs::CActionCollection* actions, const mrpt::obs::CSensoryFrame* sf,
    const mrpt::bayes::CParticleFilter::TParticleFilterOptions& PF_options)
{
    MRPT_START
    if (sf)
    {
        ASSERTMSG_(options.metricMap,
                   "CParallelMonteCarloLocalization2D needs options.metricMap (one map for "
                   "every particle)");
    }
    std::optional<GaussianIncrementDrawer> drawer;
    uint64_t key = 0;
    if (actions)
    {
        if (PF_options.adaptiveSampleSize)
        {
            // KLD sampling: MRPT's own implementation (prediction only, no frame).
            CMonteCarloLocalization2D::prediction_and_update_pfStandardProposal(actions, nullptr,
                                                                                PF_options);
        }
        else if (const auto gauss = gaussianMotion(*actions))
        {
            // One key per step from MRPT's generator (the seed decides it); each particle's
            // numbers from (key, index), drawn and applied on every thread.
            auto& rng = mrpt::random::getRandomGenerator();
            key = (static_cast<uint64_t>(rng.drawUniform32bit()) << 32) | rng.drawUniform32bit();
            drawer.emplace(*gauss);
        }
        else
        {
            predictOtherMotion(*actions);
        }
    }
    std::optional<MinMax> weightRange;
    if (drawer || sf)
    {
        weightRange = predictAndUpdate(drawer ? &*drawer : nullptr, key, sf, PF_options);
    }
    // CParticleFilter::executeOn's resampling test, done here where the weights are at hand:
    // executeOn then finds equal weights (its normalizeWeights() and ESS() are a max/min
    // pass) and does not resample again. Either branch takes the random numbers MRPT's
    // performResampling() would, at the same point of the sequence (the systematic one a
    // single uniform draw, as MRPT's).
    m_essBeforeResampling = weightsAndESS(weightRange ? *weightRange : minMaxLogWeights(), &m_linW);
    if (!PF_options.adaptiveSampleSize && m_essBeforeResampling < PF_options.BETA)
    {
        if (PF_options.resamplingMethod == mrpt::bayes::CParticleFilter::prSystematic)
        {
            systematicResampling();
        }
        else
        {
            std::vector<double> logW(m_particles.size());
            for (size_t i = 0; i < logW.size(); i++)
            {
                logW[i] = m_particles[i].log_w;
            }
            computeResampling(PF_options.resamplingMethod, logW, m_resampleIdx);
            performSubstitution(m_resampleIdx);
        }
    }
    MRPT_END
}

void CParallelMonteCarloLocalization2D::systematicResampling()
{
    // Systematic resampling (Kitagawa 1996): M equally spaced pointers t_i = (u + i) M / W,
    // u one uniform draw of MRPT's generator, into the cumulative weights; particle j takes
    // the pointers in [c_{j-1}, c_j), the last particle of positive weight those beyond.
    // The running sum c is one sequential chain of additions (its bits are the sequential
    // loop's); everything else runs per block of particles on the executor's threads: the
    // pointers of block [s, e) are those with c_{s-1} <= t_i < c_{e-1}, found from the
    // chain's values at the block borders. Same indices as the sequential walk, bit for bit.
    const std::vector<double>& w = m_linW;
    const size_t M = w.size();
    const size_t blocks = (M + kResampleBlock - 1) / kResampleBlock;
    m_blockCum.resize(blocks + 1);
    double total = 0;
    for (size_t blk = 0; blk < blocks; blk++)
    {
        m_blockCum[blk] = total;  // c_{s-1} of the block's first particle s (0 for s = 0)
        const size_t e = std::min(M, (blk + 1) * kResampleBlock);
        for (size_t i = blk * kResampleBlock; i < e; i++)
        {
            total += w[i];
        }
    }
    m_blockCum[blocks] = total;
    ASSERT_(total > 0);
    size_t last = M - 1;  // the last particle of positive weight: no pointer goes beyond it
    while (last > 0 && !(w[last] > 0))
    {
        last--;
    }
    const double u = mrpt::random::getRandomGenerator().drawUniform(0.0, 1.0);
    const double step = total / static_cast<double>(M);
    const auto pointer = [&](size_t i) { return (u + static_cast<double>(i)) * step; };
    // firstPointer[blk]: the first pointer of the block; the block of `last` takes every
    // pointer from its first on, the blocks after it none.
    const size_t lastBlock = last / kResampleBlock;
    m_blockFirstPointer.resize(blocks + 1);
    m_blockFirstPointer[0] = 0;
    for (size_t blk = 1; blk <= blocks; blk++)
    {
        if (blk > lastBlock)
        {
            m_blockFirstPointer[blk] = M;
            continue;
        }
        // The first i with t_i >= c (t_i is non-decreasing in i): a guess, then corrected.
        const double c = m_blockCum[blk];
        const double guess = std::ceil(c / step - u);
        size_t i = guess <= 0 ? 0 : std::min<size_t>(M, static_cast<size_t>(guess));
        while (i > 0 && pointer(i - 1) >= c)
        {
            i--;
        }
        while (i < M && pointer(i) < c)
        {
            i++;
        }
        m_blockFirstPointer[blk] = i;
    }

    m_resampled.resize(M);
    m_executor->forEachRange(
        blocks,
        [&](size_t b0, size_t b1, size_t)
        {
            for (size_t blk = b0; blk < b1; blk++)
            {
                const size_t i0 = m_blockFirstPointer[blk], i1 = m_blockFirstPointer[blk + 1];
                if (i0 >= i1)
                {
                    continue;
                }
                size_t j = blk * kResampleBlock;
                const size_t jEnd = std::min(last, std::min(M, (blk + 1) * kResampleBlock) - 1);
                double cum = m_blockCum[blk] + w[j];
                auto src = m_particles.cbegin() + static_cast<ptrdiff_t>(j);
                forEachRun(m_resampled, i0, i1,
                           [&](auto* dst, size_t d0, size_t n)
                           {
                               // pointer(i) with i counted as a double (exact below 2^53).
                               double di = static_cast<double>(d0);
                               for (size_t k = 0; k < n; k++, di += 1)
                               {
                                   const double t = (u + di) * step;
                                   while (t >= cum && j < jEnd)
                                   {
                                       cum += w[++j];
                                       ++src;
                                   }
                                   dst[k].d = src->d;
                                   dst[k].log_w = 0;  // equal weights after resampling
                               }
                           });
            }
        },
        1);
    m_particles.swap(m_resampled);
}

std::optional<mrpt::poses::CPosePDFGaussian> CParallelMonteCarloLocalization2D::gaussianMotion(
    const mrpt::obs::CActionCollection& actions)
{
    const auto mov2D = actions.getBestMovementEstimation();
    const auto* gauss =
        mov2D ? dynamic_cast<const mrpt::poses::CPosePDFGaussian*>(mov2D->poseChange.get())
              : nullptr;
    if (gauss)
    {
        return *gauss;
    }
    return std::nullopt;
}

void CParallelMonteCarloLocalization2D::predictOtherMotion(
    const mrpt::obs::CActionCollection& actions)
{
    // Any other motion model (MRPT's Thrun particles, 3D actions): MRPT's sampler and its
    // 3D composition, as PF_SLAM_implementation_pfStandardProposal.
    const size_t M = m_particles.size();
    const auto mov2D = actions.getBestMovementEstimation();
    if (mov2D)
    {
        ASSERT_(mov2D->poseChange);
        m_movementDrawer.setPosePDF(*mov2D->poseChange);
    }
    else if (const auto mov3D = actions.getActionByClass<mrpt::obs::CActionRobotMovement3D>())
    {
        m_movementDrawer.setPosePDF(mov3D->poseChange);
    }
    else
    {
        THROW_EXCEPTION(
            "Action list does not contain any CActionRobotMovement2D or CActionRobotMovement3D "
            "object!");
    }
    std::vector<mrpt::poses::CPose3D> incr(M);
    for (size_t i = 0; i < M; i++)
    {
        m_movementDrawer.drawSample(incr[i]);
    }
    m_executor->forEachChunk(
        M,
        [&](size_t b, size_t e)
        {
            for (size_t i = b; i < e; i++)
            {
                const mrpt::poses::CPose3D p(mrpt::math::TPose3D(m_particles[i].d));
                m_particles[i].d = TPose2D((p + incr[i]).asTPose());
            }
        });
}

double CParallelMonteCarloLocalization2D::logSumExpWeights() const
{
    double maxW = kNegInf;
    for (const auto& p : m_particles)
    {
        maxW = std::max(maxW, p.log_w);
    }
    if (!(maxW > kNegInf))
    {
        return maxW;
    }
    const double sum = m_executor->reduceBlocks(
        m_particles.size(),
        [&](size_t b, size_t e)
        {
            double s = 0;
            for (size_t i = b; i < e; i++)
            {
                s += std::exp(m_particles[i].log_w - maxW);
            }
            return s;
        },
        kExpLoopChunk / ParallelExecutor::kReduceBlock);
    return maxW + std::log(sum);
}

std::optional<CParallelMonteCarloLocalization2D::MinMax>
CParallelMonteCarloLocalization2D::predictAndUpdate(
    const GaussianIncrementDrawer* drawer, uint64_t key, const mrpt::obs::CSensoryFrame* sf,
    const mrpt::bayes::CParticleFilter::TParticleFilterOptions& PF_options)
{
    const size_t M = m_particles.size();
    ParallelExecutor& ex = *m_executor;
    bool chunkwise = true;
    double lsePrior = 0;
    const bool recovery = sf && m_augmented.options().enabled();
    if (sf)
    {
        ASSERTMSG_(M > 0, "the particle set is empty");
        prepareLikelihood();
        chunkwise = m_likelihood->plan(*sf, ex);
        lsePrior = recovery ? logSumExpWeights() : 0;
        m_logLik.resize(M);
    }
    m_poses.resize(M);

    // One pass per particle range: the prediction (or the poses' copy), the likelihood and
    // the weight update with the free-space prior, reducing the weights' extremes and the
    // counters per thread (exact whatever the ranges). A likelihood that needs every pose
    // first (generic MRPT maps) takes a pass of its own after the prediction.
    const bool prior = m_freeSpacePrior && m_sampler;
    const double pow = PF_options.powFactor;
    struct alignas(64) Partial
    {
        MinMax range;
        size_t outside = 0, nonfinite = 0;
    };
    std::vector<Partial> partial(ex.threads());
    const auto pass = [&](bool poses, bool likelihood)
    {
        ex.forEachRange(
            M,
            [&](size_t b, size_t e, size_t thread)
            {
                if (poses)
                {
                    forEachRun(m_particles, b, e,
                               [&](auto* p, size_t i0, size_t n)
                               {
                                   TPose2D* out = m_poses.data() + i0;
                                   if (drawer)
                                   {
                                       movePoses(*drawer, key, p, i0, n, out);
                                       return;
                                   }
                                   for (size_t k = 0; k < n; k++)
                                   {
                                       out[k] = p[k].d;
                                   }
                               });
                }
                if (!likelihood)
                {
                    return;
                }
                Partial& acc = partial[thread];
                acc.nonfinite += m_likelihood->evaluateChunk(m_poses.data(), b, e, m_logLik.data());
                if (prior)
                {
                    acc.outside +=
                        m_sampler->excludeOutside(m_poses.data() + b, e - b, m_logLik.data() + b);
                }
                // Even and odd particles' extremes apart: two dependency chains.
                MinMax even = acc.range, odd;
                forEachRun(m_particles, b, e,
                           [&](auto* p, size_t i0, size_t n)
                           {
                               const double* logLik = m_logLik.data() + i0;
                               addExtremes(n, even, odd,
                                           [&](size_t k) { return p[k].log_w += logLik[k] * pow; });
                           });
                even.add(odd);
                acc.range = even;
            },
            kParticleGrain);
    };
    if (!sf)
    {
        pass(true, false);
        return std::nullopt;
    }
    if (!chunkwise)
    {
        pass(true, false);
        m_likelihood->preEvaluate(m_poses.data(), M);
    }
    pass(chunkwise, true);

    MinMax range;
    size_t nonfinite = 0;
    for (const Partial& p : partial)
    {
        range.add(p.range);
        m_recoveryStats.outside_free_space += p.outside;
        nonfinite += p.nonfinite;
    }
    m_likelihood->addNonfinite(nonfinite);
    if (!std::isfinite(range.max))
    {
        // Every weight vanished: nothing left to normalize. Start over from the free space.
        m_recoveryStats.reinitializations++;
        MRPT_LOG_WARN_STREAM("every particle weight is zero after the update: re-initializing "
                             << M << " particles over the "
                             << (m_sampler ? m_sampler->description() : "same poses"));
        if (m_sampler)
        {
            // With recovery on, from the frame's detections too (the frame that killed
            // every particle is the best evidence of where the vehicle is).
            const auto detections = detectionSampler(*sf);
            for (auto& p : m_particles)
            {
                m_recoveryStats.reinitialized_from_detections +=
                    drawRecoveryPose(detections, p.d) ? 1 : 0;
                p.log_w = 0;
            }
        }
        else
        {
            for (auto& p : m_particles)
            {
                p.log_w = 0;
            }
        }
        m_augmented.reset();
        m_lastPInject = 0;
        return MinMax{0, 0};
    }

    m_lastPInject = 0;
    if (recovery)
    {
        // w_avg = sum_i w_prior_i p(z | x_i) / sum_i w_prior_i (§8.3.5, with weights).
        const double pInject = m_augmented.update(logSumExpWeights() - lsePrior);
        m_lastPInject = pInject;
        if (pInject > 0 && m_sampler)
        {
            injectRandomParticles(pInject, *sf, PF_options);
            return std::nullopt;  // resampled and partly replaced: scan the weights again
        }
    }
    return range;
}

std::optional<DetectionPoseSampler> CParallelMonteCarloLocalization2D::detectionSampler(
    const mrpt::obs::CSensoryFrame& sf) const
{
    std::optional<DetectionPoseSampler> out;
    if (m_augmented.options().enabled() && m_augmented.options().from_detections > 0)
    {
        const auto* semMap = semanticMapOf(options.metricMap.get());
        const auto obs = sf.getObservationByClass<CObservationSemantic>();
        if (semMap && obs)
        {
            out.emplace(*semMap, *obs);
            if (out->empty())
            {
                out.reset();
            }
        }
    }
    return out;
}

bool CParallelMonteCarloLocalization2D::drawRecoveryPose(
    const std::optional<DetectionPoseSampler>& detections, TPose2D& out) const
{
    auto& rng = mrpt::random::getRandomGenerator();
    if (detections && rng.drawUniform(0.0, 1.0) < m_augmented.options().from_detections)
    {
        for (int t = 0; t < kDetectionTries; t++)
        {
            const TPose2D q = detections->draw(rng);
            if (m_sampler->contains(q.x, q.y))
            {
                out = q;
                return true;
            }
        }
    }
    out = m_sampler->draw(rng);
    return false;
}

void CParallelMonteCarloLocalization2D::injectRandomParticles(
    double pInject, const mrpt::obs::CSensoryFrame& sf,
    const mrpt::bayes::CParticleFilter::TParticleFilterOptions& o)
{
    // Table 8.3: each particle of the resampled set is, with probability p_inject, a
    // random pose instead.
    normalizeWeights();
    performResampling(o);
    auto& rng = mrpt::random::getRandomGenerator();
    const auto detections = detectionSampler(sf);
    size_t injected = 0, fromDet = 0;
    for (auto& p : m_particles)
    {
        if (rng.drawUniform(0.0, 1.0) < pInject)
        {
            injected++;
            fromDet += drawRecoveryPose(detections, p.d) ? 1 : 0;
        }
    }
    if (injected > 0)
    {
        m_recoveryStats.injection_steps++;
        m_recoveryStats.injected_particles += injected;
        m_recoveryStats.injected_from_detections += fromDet;
    }
}

CParallelMonteCarloLocalization2D::MinMax CParallelMonteCarloLocalization2D::minMaxLogWeights()
    const
{
    std::vector<MinMax> partial(m_executor->threads());
    m_executor->forEachRange(
        m_particles.size(),
        [&](size_t b, size_t e, size_t thread)
        {
            // Even and odd particles apart: two dependency chains, the same extremes.
            MinMax even, odd;
            forEachRun(m_particles, b, e,
                       [&](const auto* p, size_t, size_t n)
                       { addExtremes(n, even, odd, [&](size_t k) { return p[k].log_w; }); });
            partial[thread].add(even);
            partial[thread].add(odd);
        },
        kCheapLoopGrain);
    MinMax r;
    for (const auto& p : partial)
    {
        r.add(p);
    }
    return r;
}

double CParallelMonteCarloLocalization2D::normalizeWeights(double* out_max_log_w)
{
    if (m_particles.empty())
    {
        return 0;
    }
    const MinMax r = minMaxLogWeights();
    // MRPT's loop starts from the first weight: a NaN there stays (std::max/min never pick
    // a NaN later on).
    const double first = m_particles[0].log_w;
    const double maxW = std::isnan(first) ? first : r.max;
    const double minW = std::isnan(first) ? first : r.min;
    if (maxW == 0)
    {
        // Already normalized (e.g. just resampled): subtracting 0 changes nothing.
        if (out_max_log_w)
        {
            *out_max_log_w = 0;
        }
        return std::exp(-minW);
    }
    m_executor->forEachRange(
        m_particles.size(),
        [&](size_t b, size_t e, size_t)
        {
            forEachRun(m_particles, b, e,
                       [&](auto* p, size_t, size_t n)
                       {
                           for (size_t k = 0; k < n; k++)
                           {
                               p[k].log_w -= maxW;
                           }
                       });
        },
        kCheapLoopGrain);
    if (out_max_log_w)
    {
        *out_max_log_w = maxW;
    }
    return std::exp(maxW - minW);
}

mrpt::poses::CPose2D CParallelMonteCarloLocalization2D::meanAndWeights(std::vector<double>& w,
                                                                       double& weightSum) const
{
    // MRPT 2.5.8's CPosePDFParticles::getMean: SE_average<2> over the particles in order,
    // weights exp(log_w). Here each particle's exp (only where log_w != 0: glibc's exp(+-0)
    // is 1 exactly) and cos and sin of its heading (glibc's) are computed on the executor's
    // threads first, then summed in particle order on this thread: the same values. The two
    // counts of SE_average and SO_average add the same weights in the same order: one here.
    const size_t n = m_particles.size();
    w.resize(n);
    weightSum = 0;
    if (n == 0)
    {
        return {};
    }
    thread_local std::vector<double> cosPhi, sinPhi;  // this thread's calls' buffers
    cosPhi.resize(n);
    sinPhi.resize(n);
    double* W = w.data();
    double* C = cosPhi.data();
    double* S = sinPhi.data();
    m_executor->forEachRange(
        n,
        [&](size_t b, size_t e, size_t)
        {
            forEachRun(m_particles, b, e,
                       [&](const auto* p, size_t i0, size_t len)
                       {
                           for (size_t k = 0; k < len; k++)
                           {
                               const double logW = p[k].log_w;
                               W[i0 + k] = logW == 0 ? 1.0 : std::exp(logW);
                               C[i0 + k] = std::cos(p[k].d.phi);
                               S[i0 + k] = std::sin(p[k].d.phi);
                           }
                       });
        },
        kTrigLoopGrain);
    double count = 0, sumX = 0, sumY = 0, sumCos = 0, sumSin = 0;
    forEachRun(m_particles, 0, n,
               [&](const auto* p, size_t i0, size_t len)
               {
                   for (size_t k = 0; k < len; k++)
                   {
                       const double wk = W[i0 + k];
                       count += wk;
                       sumX += wk * p[k].d.x;
                       sumY += wk * p[k].d.y;
                       sumCos += C[i0 + k] * wk;
                       sumSin += S[i0 + k] * wk;
                   }
               });
    weightSum = count;
    ASSERT_GT_(count, 0);
    mrpt::poses::CPose2D mean;
    mean.x(sumX / count);
    mean.y(sumY / count);
    // SO_average<2>::get_average (an undetermined angle is 0, MRPT's default).
    errno = 0;
    double ang = std::atan2(sumSin / count, sumCos / count);
    if (errno == EDOM)
    {
        ang = 0;
    }
    mean.phi(ang);
    return mean;
}

void CParallelMonteCarloLocalization2D::getMean(mrpt::poses::CPose2D& mean) const
{
    thread_local std::vector<double> w;
    double weightSum = 0;
    mean = meanAndWeights(w, weightSum);
}

std::tuple<CParallelMonteCarloLocalization2D::cov_mat_t,
           CParallelMonteCarloLocalization2D::type_value>
CParallelMonteCarloLocalization2D::getCovarianceAndMean() const
{
    // MRPT 2.5.8's CPosePDFParticles::getCovarianceAndMean, the same operations in the same
    // order. Its sum of exp(log_w) adds the same weights in the same order as getMean's
    // count: meanAndWeights' weightSum.
    thread_local std::vector<double> w;
    double linWSum = 0;
    const mrpt::poses::CPose2D mean = meanAndWeights(w, linWSum);
    const size_t n = m_particles.size();
    if (linWSum == 0)
    {
        linWSum = 1;
    }
    double meanPhi = mean.phi();
    if (meanPhi < 0)
    {
        meanPhi = M_2PI + meanPhi;
    }
    const double mx = mean.x(), my = mean.y();
    double varX = 0, varY = 0, varP = 0, varXY = 0, varXP = 0, varYP = 0;
    forEachRun(m_particles, 0, n,
               [&](const auto* p, size_t i0, size_t len)
               {
                   for (size_t k = 0; k < len; k++)
                   {
                       const double wk = w[i0 + k] / linWSum;
                       const double errX = p[k].d.x - mx;
                       const double errY = p[k].d.y - my;
                       const double errPhi = wrapToPiExact(std::abs(p[k].d.phi - meanPhi));
                       varX += (errX * errX) * wk;
                       varY += (errY * errY) * wk;
                       varP += (errPhi * errPhi) * wk;
                       varXY += (errX * errY) * wk;
                       varXP += (errX * errPhi) * wk;
                       varYP += (errY * errPhi) * wk;
                   }
               });
    cov_mat_t cov;
    cov.setZero();
    if (n >= 2)
    {
        cov(0, 0) = varX;
        cov(1, 1) = varY;
        cov(2, 2) = varP;
        cov(1, 0) = cov(0, 1) = varXY;
        cov(2, 0) = cov(0, 2) = varXP;
        cov(1, 2) = cov(2, 1) = varYP;
    }
    return {cov, mean};
}

double CParallelMonteCarloLocalization2D::ESS() const
{
    return weightsAndESS(minMaxLogWeights(), nullptr);
}

double CParallelMonteCarloLocalization2D::weightsAndESS(const MinMax& range,
                                                        std::vector<double>* linW) const
{
    // ESS = (sum w)^2 / (M sum w^2), shift-invariant: computed relative to the largest
    // log-weight, over fixed blocks (same bits for any thread count).
    const size_t M = m_particles.size();
    if (M == 0)
    {
        return 0;
    }
    const double maxW = range.max, minW = range.min;
    if (!(maxW > kNegInf) || std::isinf(maxW))
    {
        return 0;
    }
    if (linW)
    {
        linW->resize(M);
    }
    if (minW == maxW)
    {
        if (linW)
        {
            std::fill(linW->begin(), linW->end(), 1.0);
        }
        return 1;  // equal weights (e.g. just resampled): what the sums below give exactly
    }
    double* out = linW ? linW->data() : nullptr;
    const size_t blocks = (M + ParallelExecutor::kReduceBlock - 1) / ParallelExecutor::kReduceBlock;
    std::vector<double> sumW(blocks), sumW2(blocks);
    // The weights of block blk (written out if writeOut) and their sums.
    const auto blockSums = [&](size_t blk, auto writeOut)
    {
        double s = 0, s2 = 0;
        const size_t b = blk * ParallelExecutor::kReduceBlock;
        forEachRun(m_particles, b, std::min(M, b + ParallelExecutor::kReduceBlock),
                   [&](const auto* p, size_t i0, size_t n)
                   {
                       // Two at a time (expFast2), the sums in particle order.
                       size_t k = 0;
                       for (; k + 1 < n; k += 2)
                       {
                           double w0 = 0, w1 = 0;
                           detail::expFast2(p[k].log_w - maxW, p[k + 1].log_w - maxW, w0, w1);
                           if constexpr (decltype(writeOut)::value)
                           {
                               out[i0 + k] = w0;
                               out[i0 + k + 1] = w1;
                           }
                           s = (s + w0) + w1;
                           s2 = (s2 + w0 * w0) + w1 * w1;
                       }
                       if (k < n)
                       {
                           const double w = detail::expFast(p[k].log_w - maxW);
                           if constexpr (decltype(writeOut)::value)
                           {
                               out[i0 + k] = w;
                           }
                           s += w;
                           s2 += w * w;
                       }
                   });
        sumW[blk] = s;
        sumW2[blk] = s2;
    };
    m_executor->forEachChunk(
        blocks,
        [&](size_t b0, size_t b1)
        {
            for (size_t blk = b0; blk < b1; blk++)
            {
                if (out)
                {
                    blockSums(blk, std::true_type{});
                }
                else
                {
                    blockSums(blk, std::false_type{});
                }
            }
        },
        kExpLoopChunk / ParallelExecutor::kReduceBlock);
    double s = 0, s2 = 0;
    for (size_t blk = 0; blk < blocks; blk++)
    {
        s += sumW[blk];
        s2 += sumW2[blk];
    }
    return s2 > 0 ? s * s / (static_cast<double>(M) * s2) : 0;
}

void CParallelMonteCarloLocalization2D::performSubstitution(const std::vector<size_t>& indx)
{
    // MRPT sorts the indices first (the particle order after resampling); every resampling
    // method of computeResampling() already returns them sorted, so sort only if needed.
    std::vector<size_t> sorted;
    const std::vector<size_t>* idx = &indx;
    if (!std::is_sorted(indx.begin(), indx.end()))
    {
        sorted = indx;
        std::sort(sorted.begin(), sorted.end());
        idx = &sorted;
    }
    const size_t M = idx->size();
    m_resampled.resize(M);
    m_executor->forEachRange(
        M,
        [&](size_t b, size_t e, size_t)
        {
            auto dst = m_resampled.begin() + static_cast<ptrdiff_t>(b);
            for (size_t i = b; i < e; i++, ++dst)
            {
                dst->d = m_particles[(*idx)[i]].d;
                dst->log_w = 0;  // equal weights after resampling
            }
        },
        kCopyLoopGrain);
    m_particles.swap(m_resampled);
}

}  // namespace semloc
