/* semloc — standard normal draws by the ziggurat method (private).
 *
 * Marsaglia & Tsang, "The Ziggurat Method for Generating Random Variables", J. Statistical
 * Software 5(8), 2000: 128 layers of equal area V under f(x) = exp(-x^2 / 2), the base one
 * holding the tail beyond r. One 64-bit random number gives the layer (7 bits), the sign
 * (1 bit) and a 53-bit uniform: distinct bits, so the layer and the value are independent
 * (Doornik 2005 showed the correlation of the original's shared bits). About 99 % of the
 * draws are accepted at once, at the cost of a multiplication and a comparison; the rest
 * take the wedge test or Marsaglia's tail algorithm. */
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace semloc::detail
{
class Ziggurat
{
public:
    /** One N(0, 1) draw; `next` returns uniformly distributed 64-bit words. Inline: the
     *  ~99 % of draws inside their layer's rectangle; the others out of line. */
    template <typename Next>
    static double draw(Next&& next)
    {
        const uint64_t z = next();
        double v = 0;
        return inRectangle(tables(), z, v) ? v : outsideRectangle(next, z);
    }

private:
    /** Bit 7 of z as a sign bit. */
    static uint64_t signOf(uint64_t z) { return (z & 128u) << 56; }
    /** The 53-bit uniform in [0, 1) of z's top bits. */
    static double uniformOf(uint64_t z) { return static_cast<double>(z >> 11) * 0x1p-53; }

    /** draw() from a word z whose value fell outside its layer's rectangle: the tail or the
     *  wedge test, then new words until one is accepted. */
    template <typename Next>
    [[gnu::noinline]] static double outsideRectangle(Next& next, uint64_t z)
    {
        const Tables& t = tables();
        for (;;)
        {
            const auto i = static_cast<unsigned>(z & 127u);
            const uint64_t sign = signOf(z);
            const double x = uniformOf(z) * t.x[i];
            if (i == 0)
            {
                return withSign(tail(next), sign);
            }
            // The wedge between the rectangle and the curve.
            const double y = t.f[i] + uniform(next()) * (t.f[i + 1] - t.f[i]);
            if (y < std::exp(-0.5 * x * x))
            {
                return withSign(x, sign);
            }
            z = next();
            double v = 0;
            if (inRectangle(t, z, v))
            {
                return v;
            }
        }
    }
    static constexpr int kLayers = 128;
    static constexpr double kR = 3.442619855899;       // start of the tail
    static constexpr double kV = 9.91256303526217e-3;  // area of each layer

    struct Tables
    {
        // x[i]: right edge of layer i (x[0] = V / f(r), the base strip as a rectangle;
        // x[1] = r; x[128] = 0); f[i] = f(x[i]); ratio[i] = x[i + 1] / x[i].
        std::array<double, kLayers + 1> x{}, f{};
        std::array<double, kLayers> ratio{};
    };

    static const Tables& tables()
    {
        static const Tables t = []
        {
            Tables s;
            const auto f = [](double v) { return std::exp(-0.5 * v * v); };
            s.x[0] = kV / f(kR);
            s.x[1] = kR;
            for (int i = 1; i < kLayers - 1; i++)
            {
                s.x[i + 1] = std::sqrt(-2 * std::log(kV / s.x[i] + f(s.x[i])));
            }
            s.x[kLayers] = 0;
            for (int i = 0; i <= kLayers; i++)
            {
                s.f[i] = f(s.x[i]);
            }
            for (int i = 0; i < kLayers; i++)
            {
                s.ratio[i] = s.x[i + 1] / s.x[i];
            }
            return s;
        }();
        return t;
    }

    /** v (>= 0) with its sign bit flipped if `sign` has it: -v or v as (+-1) * v gives them,
     *  without the branch on a random bit that was mispredicted every other draw. */
    static double withSign(double v, uint64_t sign)
    {
        uint64_t b;
        std::memcpy(&b, &v, sizeof b);
        b ^= sign;
        std::memcpy(&v, &b, sizeof v);
        return v;
    }

    /** True if word z's value lies inside its layer's rectangle, under f (~99 % of words):
     *  then it is the draw, v. */
    static bool inRectangle(const Tables& t, uint64_t z, double& v)
    {
        const auto i = static_cast<unsigned>(z & 127u);
        const double u = uniformOf(z);
        v = withSign(u * t.x[i], signOf(z));
        return u < t.ratio[i];
    }

    /** Uniform in (0, 1]: its log is finite. */
    static double uniform(uint64_t z) { return static_cast<double>((z >> 11) + 1) * 0x1p-53; }

    /** |x| beyond r (Marsaglia 1964). */
    template <typename Next>
    static double tail(Next& next)
    {
        for (;;)
        {
            const double x = -std::log(uniform(next())) / kR;
            const double y = -std::log(uniform(next()));
            if (2 * y >= x * x)
            {
                return kR + x;
            }
        }
    }
};

}  // namespace semloc::detail
