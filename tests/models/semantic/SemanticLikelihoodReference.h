/* semloc tests — the semantic likelihoods written to be read: the reference of CSemanticMap's
 * fast path. */
#pragma once

#include <mrpt/math/TPose2D.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/observation/CObservationSemantic.h>

#include <cstddef>

/** @file
 *  Reference implementation of CSemanticMap's two likelihood models, `paper` (§III of
 *  Maurelli & Krupiński, "A semantic-aided particle filter approach for AUV localization")
 *  and `probabilistic`, written to be read rather than to be fast: one particle at a time,
 *  plain scalar C++ over the map's objects (no index, no visibility tables, no SIMD, libm's
 *  atan2/sin/cos/log instead of polynomial approximations), each model's equation at the top
 *  of its function.
 *
 *  CSemanticMap.cpp computes the same log-likelihoods through a grid index, per-step
 *  visibility tables, staged SSE2 blocks of particles and polynomial atan2/sin/cos; this file
 *  states what it computes, with the same semantics: which detections are used (validity,
 *  confidence, unknown labels and ids), which objects are predicted (range and field of view
 *  of the sensor, placed and yawed on the vehicle), the gates, the greedy one-to-one
 *  association from the best pair, missed detections and clutter, non-finite inputs and
 *  poses. tests/models/semantic/test_SemanticLikelihoodReference.cpp compares the two on random
 * scenes: equal to the bit where the fast path takes no approximation (non-finite poses, unusable
 *  sensors, paper scenes without a matched pair), else within the tolerance that the fast
 *  path's atan2 approximation (|error| < 1e-7 rad) explains. An object exactly on the edge of
 *  the sensor's coverage (SemanticTerms::onEdge) is in z^k or not by each one's rounding.
 *
 *  Not used by the filter: it is the specification the fast path is held to, and the place
 *  to read what a likelihood value means. */
namespace semloc::reference
{
/** What a reference evaluation counted, in the paper's notation (§III). */
struct SemanticTerms
{
    /** l: detections of the observation the likelihood uses. */
    size_t l = 0;
    /** q: map objects predicted inside the sensor's range and field of view. */
    size_t q = 0;
    /** m: matched (detection, object) pairs. */
    size_t m = 0;
    /** Map objects on the edge of the sensor's coverage: within a relative 1e-9 of the range
     *  limit or of the field of view's edge, or at the sensor's position. Whether they are in
     *  z^k is then a matter of rounding, which the fast path decides its own way. */
    size_t onEdge = 0;
};

/** The log-likelihood CSemanticMap::computeLogLikelihood(obs, pose) computes, by the model
 *  of map.likelihoodOptions; `terms` (optional) receives l, q and m. */
double semanticLogLikelihood(const CSemanticMap& map, const CObservationSemantic& obs,
                             const mrpt::math::TPose2D& pose, SemanticTerms* terms = nullptr);

/** The same for MRPT's landmark observation: a landmark with `landmarkID` >= 0 names the
 *  object with that id, one without an id may be any object (it carries no label). */
double semanticLogLikelihood(const CSemanticMap& map,
                             const mrpt::obs::CObservationBearingRange& obs,
                             const mrpt::math::TPose2D& pose, SemanticTerms* terms = nullptr);
}  // namespace semloc::reference
