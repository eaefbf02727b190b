/* semloc — the fast semantic likelihood kernels: the interface CSemanticMap calls (private). */
#pragma once

#include <mrpt/math/TPose2D.h>
#include <semloc/models/semantic/CSemanticMap.h>

#include <cstddef>

#include "models/semantic/SemanticLikelihoodState.h"

/** @file
 *  The fast path of CSemanticMap's two likelihood models (the class documentation states
 *  them). Each kernel scores one block of particles in stages that each run over the whole
 *  block (docs/performance.md, "How the semantic likelihood is computed"): the visible
 *  objects z^k through the grid index or the visibility table (VisibleObjects.h), the
 *  gates and the greedy association (SemanticAssociation.h), the models' terms with
 *  polynomial atan2 in Vec2 lanes. PaperLikelihood.cpp and ProbabilisticLikelihood.cpp
 *  hold them.
 *
 *  tests/models/semantic/SemanticLikelihoodReference.h states the same models plainly, one particle
 * at a time; tests/models/semantic/test_SemanticLikelihoodReference.cpp holds these kernels to it.
 *
 *  Before a block: sc.dets holds the call's detections, planPairsOnce() their plan, sc.vis
 *  the visibility table (or null). A particle's value depends on its own arithmetic only, so
 *  not on the block (a single particle takes this path too). */
namespace semloc::semantic
{
/** The paper likelihood of the m particles of a block (sensor geometry geoms[i] of pose
 *  poses[i]) into out[0..m). */
void scorePaperBlock(const CSemanticMap::Index& ix, const ModelConsts& k, Scratch& sc,
                     const Geom* geoms, const mrpt::math::TPose2D* poses, size_t m, double* out);

/** The probabilistic likelihood of the m particles of a block into out[0..m). */
void scoreProbabilisticBlock(const CSemanticMap::Index& ix,
                             const CSemanticMap::TLikelihoodOptions& opt, const ModelConsts& k,
                             Scratch& sc, const Geom* geoms, const mrpt::math::TPose2D* poses,
                             size_t m, double* out);
}  // namespace semloc::semantic
