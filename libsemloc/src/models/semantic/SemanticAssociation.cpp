/* semloc — the detection plan of a likelihood call: which detections may pair with which
 * label, and in which range bins (see SemanticAssociation.h). */
#include "models/semantic/SemanticAssociation.h"

#include <algorithm>
#include <cmath>

namespace semloc::semantic
{
namespace
{
/** Calls add(l) for each label l whose objects detection d may pair with. */
template <typename Add>
void labelsOf(const Det& d, const CSemanticMap::Index& ix, size_t nLabels, bool anyLabel, Add&& add)
{
    if (d.fixed >= 0)
    {
        add(static_cast<size_t>(ix.label[static_cast<size_t>(d.fixed)]));
    }
    else if (anyLabel || d.label < 0)
    {
        for (size_t l = 0; l < nLabels; l++)
        {
            add(l);
        }
    }
    else
    {
        add(static_cast<size_t>(d.label));
    }
}

/** detByLabel and detStart (planPairs). */
void listByLabel(Scratch& sc, const CSemanticMap::Index& ix, size_t nLabels, bool anyLabel)
{
    const auto nd = static_cast<uint32_t>(sc.dets.size());
    sc.detStart.assign(nLabels + 1, 0);
    for (uint32_t j = 0; j < nd; j++)
    {
        labelsOf(sc.dets[j], ix, nLabels, anyLabel, [&](size_t l) { sc.detStart[l + 1]++; });
    }
    for (size_t l = 0; l < nLabels; l++)
    {
        sc.detStart[l + 1] += sc.detStart[l];
    }
    sc.detByLabel.resize(sc.detStart[nLabels]);
    auto& fill = sc.detFill;
    fill.assign(sc.detStart.begin(), sc.detStart.end() - 1);
    for (uint32_t j = 0; j < nd; j++)
    {
        labelsOf(sc.dets[j], ix, nLabels, anyLabel,
                 [&](size_t l) { sc.detByLabel[fill[l]++] = j; });
    }
}

/** The slots of each label: its detections, padded to the largest count with a detection
 *  whose infinite range fails the range gate. */
void fillSlots(Scratch& sc, size_t nLabels)
{
    size_t slotCount = 0;
    for (size_t l = 0; l < nLabels; l++)
    {
        slotCount = std::max<size_t>(slotCount, sc.detStart[l + 1] - sc.detStart[l]);
    }
    const Slot none{{kInf, 0, 0, -1, -1, 0}, 0};
    sc.slotCount = slotCount;
    sc.slots.assign(nLabels * slotCount, none);
    for (size_t l = 0; l < nLabels; l++)
    {
        for (uint32_t i = sc.detStart[l]; i < sc.detStart[l + 1]; i++)
        {
            const uint32_t j = sc.detByLabel[i];
            sc.slots[l * slotCount + (i - sc.detStart[l])] = {sc.dets[j], j};
        }
    }
}

/** gateLo2, gateHi2: the squared range hull of each label's detections, widened by reach. */
void rangeHulls(Scratch& sc, size_t nLabels, double reach)
{
    sc.gateLo2.assign(nLabels, kInf);
    sc.gateHi2.assign(nLabels, -kInf);
    for (size_t l = 0; l < nLabels; l++)
    {
        for (uint32_t i = sc.detStart[l]; i < sc.detStart[l + 1]; i++)
        {
            const double r = sc.dets[sc.detByLabel[i]].r;
            const double lo = std::max(0.0, (r - reach) * (1 - 1e-9) - 1e-9);
            const double hi = (r + reach) * (1 + 1e-9) + 1e-9;
            sc.gateLo2[l] = std::min(sc.gateLo2[l], lo * lo * (1 - 1e-9));
            sc.gateHi2[l] = std::max(sc.gateHi2[l], hi * hi * (1 + 1e-9));
        }
    }
}

/** Sorts each label's slots by increasing range; returns the largest range. */
double sortSlotsByRange(Scratch& sc, size_t nLabels)
{
    double maxR = 0;
    for (size_t l = 0; l < nLabels; l++)
    {
        Slot* sl = sc.slots.data() + l * sc.slotCount;
        const size_t cnt = sc.detStart[l + 1] - sc.detStart[l];
        std::sort(sl, sl + cnt,
                  [](const Slot& a, const Slot& b)
                  { return a.d.r != b.d.r ? a.d.r < b.d.r : a.j < b.j; });
        maxR = cnt > 0 ? std::max(maxR, sl[cnt - 1].d.r) : maxR;
    }
    return maxR;
}

/** The range bins of planPairs(): each label's slots by increasing range, and for an object
 *  of label l in range bin b (width binW, the last bin open-ended) the slots
 *  [binSpan[2 (l nb + b)], binSpan[2 (l nb + b) + 1]) whose range may be within `reach` of
 *  its range (bounds widened by a relative 1e-9 for rounding: a superset of the pairs that
 *  pass the range gate). So an object meets ~2 reach of detections, not all of its label's. */
void planRangeBins(Scratch& sc, size_t nLabels, double reach)
{
    const size_t ns = sc.slotCount;
    const double maxR = sortSlotsByRange(sc, nLabels);
    // Bins of half the window, at most 1024 of them; one bin (no filtering) if the window
    // is not finite.
    sc.binCount = 1;
    sc.binInv = 0;
    double w = kInf;
    if (std::isfinite(reach) && std::isfinite(maxR))
    {
        w = std::max(reach / 2, (maxR + reach) / 1022);
        if (w > 0)
        {
            sc.binCount = static_cast<size_t>((maxR + reach) / w) + 2;
            sc.binInv = 1 / w;
        }
    }
    const size_t nb = sc.binCount;
    sc.binSpan.resize(2 * nLabels * nb);
    sc.maxSpan = 0;
    for (size_t l = 0; l < nLabels; l++)
    {
        const Slot* sl = sc.slots.data() + l * ns;
        const Slot* end = sl + (sc.detStart[l + 1] - sc.detStart[l]);
        for (size_t b = 0; b < nb; b++)
        {
            const double lo = nb == 1 ? -kInf : static_cast<double>(b) * w - reach;
            const double hi = b + 1 == nb ? kInf : static_cast<double>(b + 1) * w + reach;
            const double margin = 1e-9 * (static_cast<double>(b + 1) * w + reach) + 1e-9;
            const Slot* first = std::lower_bound(sl, end, lo - margin,
                                                 [](const Slot& a, double r) { return a.d.r < r; });
            const Slot* last = std::upper_bound(first, end, hi + margin,
                                                [](double r, const Slot& a) { return r < a.d.r; });
            sc.binSpan[2 * (l * nb + b)] = static_cast<uint32_t>(first - sc.slots.data());
            sc.binSpan[2 * (l * nb + b) + 1] = static_cast<uint32_t>(last - sc.slots.data());
            sc.maxSpan = std::max(sc.maxSpan, static_cast<size_t>(last - first));
        }
    }
}
}  // namespace

void planPairs(Scratch& sc, const CSemanticMap::Index& ix, size_t nLabels, const ModelConsts& k)
{
    listByLabel(sc, ix, nLabels, k.planAll);
    fillSlots(sc, nLabels);
    const double reach = k.gateIr > 0 ? std::sqrt(std::max(0.0, k.rangeBudget)) / k.gateIr : kInf;
    rangeHulls(sc, nLabels, reach);
    planRangeBins(sc, nLabels, reach);
}

void planPairsOnce(Scratch& sc, const CSemanticMap::Index& ix, size_t nLabels, const ModelConsts& k)
{
    const std::array<double, 4> planKey = {static_cast<double>(ix.stamp),
                                           static_cast<double>(nLabels), k.rangeBudget, k.gateIr};
    auto sameDet = [](const Det& a, const Det& b) {
        return a.r == b.r && a.uc == b.uc && a.us == b.us && a.label == b.label &&
               a.fixed == b.fixed;
    };
    if (!sc.planValid || planKey != sc.planKey || k.planAll != sc.planConfusable ||
        !std::equal(sc.dets.begin(), sc.dets.end(), sc.planDets.begin(), sc.planDets.end(),
                    sameDet))
    {
        planPairs(sc, ix, nLabels, k);
        sc.planKey = planKey;
        sc.planConfusable = k.planAll;
        sc.planDets = sc.dets;
        sc.planValid = true;
    }
}
}  // namespace semloc::semantic
