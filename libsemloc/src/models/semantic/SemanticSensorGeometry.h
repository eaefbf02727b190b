/* semloc — the semantic likelihood's sensor geometry per particle (private). */
#pragma once

#include <mrpt/math/TPose2D.h>

#include <cmath>
#include <limits>

namespace semloc::semantic
{
/** Lazily recomputed value of f(key): the per-step angles and options are the same
 *  for every particle of a step, so their trig/log is computed once per change. */
struct Memo
{
    double key = std::numeric_limits<double>::quiet_NaN(), val = 0;
    template <typename F>
    double get(double k, F&& f)
    {
        if (k != key)
        {
            key = k;
            val = f(k);
        }
        return val;
    }
};

/** The trig of the sensor's mounting and field of view, kept across calls (per thread). */
struct SensorTrig
{
    Memo cosHalf, sinHalf, cosYaw, sinYaw;
};

/** Sensor geometry for one particle. */
struct Geom
{
    double sx, sy, c, s;  // sensor position and heading cos/sin in the world
    double R, fov, cosHalf, sinHalf;
};

/** What makeGeom needs that is the same for every particle of a call: the sensor's place
 *  on the vehicle, cos/sin of its yaw there, and range, FOV and cos/sin of the half FOV. */
struct GeomConsts
{
    double ox = 0, oy = 0, cosYaw = 1, sinYaw = 0;
    bool yawed = false;
    double R = 0, fov = 0, cosHalf = -1, sinHalf = 0;
};

inline GeomConsts geomConsts(SensorTrig& trig, double ox, double oy, double oyaw, double R,
                             double fov)
{
    GeomConsts gc;
    gc.ox = ox;
    gc.oy = oy;
    gc.yawed = oyaw != 0;
    if (gc.yawed)
    {
        gc.cosYaw = trig.cosYaw.get(oyaw, [](double a) { return std::cos(a); });
        gc.sinYaw = trig.sinYaw.get(oyaw, [](double a) { return std::sin(a); });
    }
    gc.R = R;
    gc.fov = fov;
    if (fov < 2 * M_PI)
    {
        gc.cosHalf = trig.cosHalf.get(0.5 * fov, [](double a) { return std::cos(a); });
        gc.sinHalf = trig.sinHalf.get(0.5 * fov, [](double a) { return std::sin(a); });
    }
    return gc;
}

/** The geometry of `pose`, sp and cp the sin and cos of its heading. */
inline Geom makeGeom(const GeomConsts& gc, const mrpt::math::TPose2D& pose, double sp, double cp)
{
    Geom g;
    g.sx = pose.x + cp * gc.ox - sp * gc.oy;
    g.sy = pose.y + sp * gc.ox + cp * gc.oy;
    if (gc.yawed)
    {
        g.c = cp * gc.cosYaw - sp * gc.sinYaw;
        g.s = sp * gc.cosYaw + cp * gc.sinYaw;
    }
    else
    {
        g.c = cp;
        g.s = sp;
    }
    g.R = gc.R;
    g.fov = gc.fov;
    g.cosHalf = gc.cosHalf;
    g.sinHalf = gc.sinHalf;
    return g;
}
}  // namespace semloc::semantic
