/* semloc — CSemanticMap's visibility candidate tables: their build and cache (see
 * VisibilityTable.h). */
#include "models/semantic/VisibilityTable.h"

#include <algorithm>
#include <atomic>
#include <cmath>

namespace semloc::detail
{
namespace
{
std::atomic<bool> g_visEnabled{true};
std::atomic<size_t> g_visLastBytes{0};

/** A table's size limit. A larger table, read at random places by particles spread over a
 *  large map, misses the cache and made the likelihood slower than the grid scan (5 000 and
 *  10 000 objects at the paper map's density: 209-270 ns per particle against 191-218 with
 *  8 MB tables of coarser cells), so large maps keep the grid scan. */
constexpr size_t kVisMaxBytes = size_t{1} << 20;
/** The most (cell, object) pairs a build looks at: its work, bounded. */
constexpr size_t kVisMaxPairs = size_t{64} << 20;

/** No table (degenerate extent, too large): the grid scan serves. */
std::shared_ptr<const VisTable> noTable()
{
    g_visLastBytes.store(0);
    return nullptr;
}

/** The bounding box of the index's objects and their largest |coordinate|. */
struct Extent
{
    double xmin, xmax, ymin, ymax, maxAbs;
};

Extent extentOf(const CSemanticMap::Index& ix)
{
    const size_t n = ix.objIdx.size();
    const double* X = ix.x.data();
    const double* Y = ix.y.data();
    Extent e{X[0], X[0], Y[0], Y[0], 0};
    for (size_t k = 0; k < n; k++)
    {
        e.xmin = std::min(e.xmin, X[k]);
        e.xmax = std::max(e.xmax, X[k]);
        e.ymin = std::min(e.ymin, Y[k]);
        e.ymax = std::max(e.ymax, Y[k]);
        e.maxAbs = std::max({e.maxAbs, std::abs(X[k]), std::abs(Y[k])});
    }
    return e;
}

/** The angle [rad] of the direction with "diamond angle" a in [-1, 3] (the table's bins):
 *  a = s / (|c| + |s|) for c >= 0, 2 - s / (|c| + |s|) for c < 0; monotonic in the angle,
 *  [-pi/2, 3 pi/2]. */
double diamondToAngle(double a)
{
    if (a <= 1)
    {
        return std::atan2(a, 1 - std::abs(a));
    }
    const double t = 2 - a;
    return M_PI - std::atan2(t, 1 - std::abs(t));
}

/** The heading bins of a table: bin b holds the headings of angles [edges[b], edges[b + 1]],
 *  increasing from -pi/2 to 3 pi/2; a set of bins is a bit mask. */
class HeadingBins
{
public:
    explicit HeadingBins(uint32_t bins) : m_bins(bins), m_edges(bins + 1)
    {
        for (uint32_t b = 0; b <= bins; b++)
        {
            m_edges[b] = diamondToAngle(4.0 * b / bins - 1);
        }
    }

    uint32_t count() const { return m_bins; }

    /** Every bin. */
    uint64_t all() const { return m_bins == 64 ? ~uint64_t{0} : (uint64_t{1} << m_bins) - 1; }

    /** The bins of the headings within `spread` (< pi) of direction phi in (-pi, pi]. */
    uint64_t around(double phi, double spread) const
    {
        double lo = phi - spread;  // (-2 pi, pi) -> [-pi/2, 3 pi/2)
        lo += lo < -0.5 * M_PI ? 2 * M_PI : 0;
        const double hi = lo + 2 * spread;
        const uint32_t b0 = binOf(lo);
        return hi < 1.5 * M_PI ? bitsOf(b0, binOf(hi))
                               : bitsOf(b0, m_bins - 1) | bitsOf(0, binOf(hi - 2 * M_PI));
    }

private:
    /** The bin of angle ang in [-pi/2, 3 pi/2). */
    uint32_t binOf(double ang) const
    {
        // Bins are within ~4 degrees of uniform in angle: guess, then step to the bin.
        auto b = static_cast<uint32_t>(
            std::min(m_bins - 1.0, std::max(0.0, (ang + 0.5 * M_PI) * (m_bins / (2 * M_PI)))));
        while (b > 0 && m_edges[b] > ang)
        {
            b--;
        }
        while (b + 1 < m_bins && m_edges[b + 1] <= ang)
        {
            b++;
        }
        return b;
    }

    /** Bins b0..b1, b0 <= b1 < 64. */
    static uint64_t bitsOf(uint32_t b0, uint32_t b1)
    {
        return (uint64_t{2} << b1) - (uint64_t{1} << b0);
    }

    uint32_t m_bins;
    std::vector<double> m_edges;
};

/** The build of one table: for each cell of sensor positions, the objects in range from
 *  somewhere in the cell, each in the lists of the heading bins that may see it. */
class TableBuild
{
public:
    TableBuild(const CSemanticMap::Index& ix, double R, double fov, double side, double maxAbs)
        : m_ix(ix),
          m_bins(fov >= 2 * M_PI ? 1 : 32),
          m_halfFov(std::min(0.5 * fov, M_PI)),
          // Margins, far above the rounding of the lookup and of the exact test.
          m_eps(1e-9 * (1 + maxAbs + R)),
          m_Rm(R * (1 + 1e-9) + m_eps),
          m_h(0.5 * side + m_eps),  // half side of a cell, widened
          m_rc(m_h * std::sqrt(2.0)),
          m_perBin(m_bins.count())
    {
    }

    uint32_t bins() const { return m_bins.count(); }
    bool tooLarge() const { return m_tooLarge; }
    void markTooLarge() { m_tooLarge = true; }

    /** Appends the lists of the cell centred at (mx, my), one per bin, to `cand`, and their
     *  ends to start[1..bins]. */
    void appendCell(double mx, double my, std::vector<uint32_t>& cand, uint32_t* start)
    {
        for (auto& l : m_perBin)
        {
            l.clear();
        }
        collect(mx, my);
        for (uint32_t b = 0; b < bins(); b++)
        {
            cand.insert(cand.end(), m_perBin[b].begin(), m_perBin[b].end());
            start[b + 1] = static_cast<uint32_t>(cand.size());
        }
    }

private:
    /** The objects of the index cells within h + Rm of (mx, my), each into its bins' lists
     *  (in increasing sorted index: the objects are visited in that order). */
    void collect(double mx, double my)
    {
        const CSemanticMap::Index& ix = m_ix;
        int ix0 = 0, ix1 = -1, iy0 = 0, iy1 = -1;
        cells(mx - m_h - m_Rm, mx + m_h + m_Rm, ix.x0, ix.inv_cell, ix.nx, ix0, ix1);
        cells(my - m_h - m_Rm, my + m_h + m_Rm, ix.y0, ix.inv_cell, ix.ny, iy0, iy1);
        for (int icy = iy0; icy <= iy1 && ix0 <= ix1; icy++)
        {
            const size_t row = static_cast<size_t>(icy) * static_cast<size_t>(ix.nx);
            for (uint32_t k = ix.cellStart[row + static_cast<size_t>(ix0)];
                 k < ix.cellStart[row + static_cast<size_t>(ix1) + 1]; k++)
            {
                m_tooLarge |= ++m_pairs > kVisMaxPairs;  // the build's work, bounded
                for (uint64_t mask = headings(ix.x[k] - mx, ix.y[k] - my); mask != 0;
                     mask &= mask - 1)  // k goes to its bins' lists
                {
                    m_perBin[static_cast<size_t>(__builtin_ctzll(mask))].push_back(k);
                }
            }
        }
    }

    /** The index cells [c0, c1] of one axis that hold coordinates in [lo, hi]. */
    static void cells(double lo, double hi, double o, double inv, int nc, int& c0, int& c1)
    {
        const double l = std::max(0.0, (lo - o) * inv);
        const double u = std::min(nc - 1.0, (hi - o) * inv);
        c0 = static_cast<int>(std::min(l, nc - 1.0));
        c1 = u < 0 ? -1 : static_cast<int>(u);
    }

    /** The bins of the headings that may see the object at (dx, dy) from the cell's centre
     *  from somewhere in the cell (0: out of range from the whole cell). */
    uint64_t headings(double dx, double dy) const
    {
        const double ex = std::max(std::abs(dx) - m_h, 0.0);
        const double ey = std::max(std::abs(dy) - m_h, 0.0);
        if (ex * ex + ey * ey > m_Rm * m_Rm)
        {
            return 0;  // out of range from the whole cell
        }
        const double d = std::sqrt(dx * dx + dy * dy);
        if (bins() == 1 || d <= m_rc * (1 + 1e-6))
        {
            return m_bins.all();  // any direction
        }
        // Directions from the cell: within asin(rc / d) of the centre's.
        const double phi = fastAtan2(dy, dx);  // |error| < 1e-7
        // Headings that see it: within spread of that direction.
        const double spread = std::asin(std::min(1.0, m_rc / d)) + m_halfFov + kAngMargin;
        return spread >= M_PI ? m_bins.all() : m_bins.around(phi, spread);
    }

    static constexpr double kAngMargin = 1e-5;
    const CSemanticMap::Index& m_ix;
    HeadingBins m_bins;
    double m_halfFov, m_eps, m_Rm, m_h, m_rc;
    std::vector<std::vector<uint32_t>> m_perBin;
    size_t m_pairs = 0;
    bool m_tooLarge = false;
};

/** A table's grid over the objects' extent widened by R and a cell (cells of `side`), its
 *  lists' offsets zeroed; null if the offsets alone would take half the byte cap. */
std::shared_ptr<VisTable> emptyTable(const Extent& e, double R, double side, uint32_t bins)
{
    const double nxD = std::floor((e.xmax - e.xmin + 2 * R) / side) + 3;
    const double nyD = std::floor((e.ymax - e.ymin + 2 * R) / side) + 3;
    const double lists = nxD * nyD * bins;
    if (!(lists * 4 <= 0.5 * static_cast<double>(kVisMaxBytes)))
    {
        return nullptr;
    }
    auto t = std::make_shared<VisTable>();
    t->x0 = e.xmin - R - side;
    t->y0 = e.ymin - R - side;
    t->inv = 1 / side;
    t->ox = t->x0 - side;
    t->oy = t->y0 - side;
    t->nx = static_cast<uint32_t>(nxD);
    t->ny = static_cast<uint32_t>(nyD);
    t->bins = bins;
    t->binScale = bins > 1 ? bins / 4.0 : 0.0;
    t->lastBin = bins - 1.0;
    t->start.assign(static_cast<size_t>(lists) + 1, 0);
    return t;
}

/** Fills t's lists, cell by cell, into `cand`; false when the table would take more than
 *  `maxEntries` candidates or the build too much work. */
bool fillLists(VisTable& t, TableBuild& build, double side, size_t maxEntries,
               std::vector<uint32_t>& cand)
{
    for (size_t cy = 0; cy < t.ny && !build.tooLarge(); cy++)
    {
        for (size_t cx = 0; cx < t.nx && !build.tooLarge(); cx++)
        {
            const double mx = t.x0 + (static_cast<double>(cx) + 0.5) * side;
            const double my = t.y0 + (static_cast<double>(cy) + 0.5) * side;
            const size_t list0 = (cy * t.nx + cx) * t.bins;  // < 2^31: the byte cap
            build.appendCell(mx, my, cand, t.start.data() + list0);
            if (cand.size() > maxEntries)
            {
                build.markTooLarge();
            }
        }
    }
    return !build.tooLarge();
}
}  // namespace

void setVisibilityTableEnabled(bool enabled)
{
    g_visEnabled.store(enabled);
}

bool visibilityTableEnabled()
{
    return g_visEnabled.load();
}

size_t lastVisibilityTableBytes()
{
    return g_visLastBytes.load();
}

std::shared_ptr<const VisTable> buildVisTable(const CSemanticMap::Index& ix, double R, double fov)
{
    if (ix.objIdx.empty() || !(R > 0) || !std::isfinite(R))
    {
        return nullptr;
    }
    const Extent e = extentOf(ix);
    const double side = R / 10;
    if (!(side < 1e300))
    {
        return noTable();  // a degenerate extent
    }
    TableBuild build(ix, R, fov, side, e.maxAbs);
    std::shared_ptr<VisTable> t = emptyTable(e, R, side, build.bins());
    if (!t)
    {
        return noTable();  // the list offsets alone too large
    }
    const bool small = ix.objIdx.size() < 65536;
    const size_t maxEntries = (kVisMaxBytes - 4 * t->start.size()) / (small ? 2 : 4);
    std::vector<uint32_t> cand;
    if (!fillLists(*t, build, side, maxEntries, cand))
    {
        return noTable();
    }
    cand.push_back(0);  // padding: the scan reads candidates in pairs
    if (small)
    {
        t->c16.assign(cand.begin(), cand.end());
    }
    else
    {
        t->c32 = std::move(cand);
    }
    t->bytes = 4 * t->start.size() + 2 * t->c16.size() + 4 * t->c32.size();
    g_visLastBytes.store(t->bytes);
    return t;
}

const VisTable* visTableFor(const CSemanticMap::Index& ix, double R, double fov,
                            VisTableHandle& handle)
{
    if (!ix.vis || !visibilityTableEnabled())
    {
        return nullptr;
    }
    if (handle.stamp != ix.stamp || handle.R != R || handle.fov != fov)
    {
        std::shared_ptr<const VisTable> t;
        {
            std::lock_guard<std::mutex> lock(ix.vis->mu);
            auto& es = ix.vis->entries;
            const auto it =
                std::find_if(es.begin(), es.end(),
                             [&](const VisCache::Entry& en) { return en.R == R && en.fov == fov; });
            if (it != es.end())
            {
                t = it->table;
            }
            else
            {
                t = buildVisTable(ix, R, fov);
                if (es.size() >= 4)
                {
                    es.erase(es.begin());  // a few (R, FOV) at most: the oldest goes
                }
                es.push_back({R, fov, t});
            }
        }
        handle.hold = std::move(t);
        handle.stamp = ix.stamp;
        handle.R = R;
        handle.fov = fov;
    }
    return handle.hold.get();
}
}  // namespace semloc::detail
