// The analytic estimator's row as a receiver: the entries of the pairs that other rows emit for it,
// handed over by the exchange when the emitting row finished first, else recomputed here from the
// emitter's points with the same rules (pair_rules.hpp), equal bit for bit.
#include "preprocess/hemisphere/analytic_estimator.hpp"

namespace hemirad {

double AnalyticEstimator::addReversedPairs(PatchId i, RowAccumulator& row, Workspace& ws, RayCounts& counts) const {
    // For every j that emits for i, the terms row j sums for i (addFrom with j's rule, in j's
    // order, the same shadow rays), so that A_i F_ij = A_j F_ji to rounding wherever the two rows
    // agree about a silhouette (row j splits i where i's neighbours disagree, seen from j; this row
    // splits where j's neighbours disagree, seen from i). Row j hands them over through the
    // exchange when it finished first; the rest are recomputed here.
    Workspace::Reversed& rev = ws.reversed;
    const std::uint64_t ticket = ws.exchange->open(i, rev.taken);
    for (const PairExchange::Entry& entry : rev.taken) rev.published[entry.patch] = entry.value;
    rev.clear();
    for (PatchId j = 0; j < m_scene->size(); ++j) {
        if (j == i || !m_rules.emitsFor(j, i)) continue;
        const std::uint32_t begin = std::uint32_t(rev.factors.size());
        double contact = 0.0;  // a close pair's value, computed here (no terms)
        if (rev.published[j] >= 0.0) {
            rev.handed.push_back(rev.published[j]);
        } else if (ws.exchange->finished(j, ticket)) {
            continue;  // row j had no term for i
        } else if (m_rules.contactPair(j, i)) {
            bool viewed = false;
            contact = m_rules.contactValue(j, i, ws.rules, counts, viewed);
            if (!viewed) continue;  // no term (as row j publishes none)
            rev.handed.push_back(m_rules.handedValue(contact, j, i));
        } else if (!reversedTerms(j, i, true, ws, counts)) {
            continue;  // no point of j has a term for i
        } else {
            rev.handed.push_back(-1.0);  // from the terms below
        }
        rev.sum.push_back(contact);
        rev.whole.push_back(0);
        rev.emitters.push_back(j);
        rev.termBegin.push_back(begin);
        rev.termEnd.push_back(std::uint32_t(rev.factors.size()));
    }
    for (const PairExchange::Entry& entry : rev.taken) rev.published[entry.patch] = -1.0;
    const std::size_t rays = rev.rays.segments();
    rev.rays.blocked.assign(rays, 0);
    if (m_rules.visibility() && rays > 0) {
        m_rays->occludedSegmentPairs(rev.rays.origins.data(), rev.rays.targets.data(), rays, rev.rays.blocked.data());
        counts.rays += rays;
    }
    splitDifferingTerms(i, ws, counts);
    for (std::size_t p = 0; p < rev.emitters.size(); ++p) {
        if (rev.handed[p] < 0.0) {
            for (std::uint32_t t = rev.termBegin[p]; t < rev.termEnd[p]; ++t) {  // row j's sum for i, in row j's order
                if (rev.differs[t]) {  // split, as row j keeps it
                    if (rev.splitValue[t] > 0.0) rev.sum[p] += rev.splitValue[t];
                    continue;
                }
                if (rev.rayOf[t] == rev.kNoRay ? !(rev.factors[t] > 0.0) : rev.rays.blocked[rev.rayOf[t]] != 0) continue;
                rev.sum[p] += rev.factors[t] * rev.weights[t];
            }
            const Straddle straddle = reversedStraddles(i, p, ws, counts);  // as row j replaces its terms
            if (straddle != Straddle::None) {
                rev.sum[p] = replacementValue(straddle, rev.emitters[p], i, ws, counts);
                rev.whole[p] = 1;
            }
            rev.handed[p] = m_rules.handedValue(rev.sum[p], rev.emitters[p], i);
        }
        ws.status[rev.emitters[p]] = rev.handed[p] > 0.0 ? 1 : 2;
    }
    if (m_rules.visibility()) splitReversedSilhouettes(i, ws, counts);
    double sum = 0.0;
    const double Ai = m_scene->patches[i].area;
    const double unit = m_rules.unit();
    for (std::size_t p = 0; p < rev.emitters.size(); ++p) {
        const PatchId j = rev.emitters[p];
        // The handed-over entry in ray units, or the terms of a pair split here.
        const double value = rev.handed[p] >= 0.0 ? rev.handed[p] * unit : rev.sum[p] * (m_scene->patches[j].area / Ai);
        if (!(value > 0.0)) continue;
        row.addWeight(j, value);
        sum += value;
    }
    return sum;
}

bool AnalyticEstimator::reversedTerms(PatchId j, PatchId i, bool rays, Workspace& ws, RayCounts& counts) const {
    const PatchGeometry& geometry = m_rules.geometry();
    const PatchShape& receiver = geometry.shapes[i];
    const PatchShape& emitter = geometry.shapes[j];
    if (m_rules.contactPair(j, i)) return false;  // a close pair is computed whole, without terms
    // No point of j has a term when all of i lies below j's plane or all of j behind i's (with a
    // margin of j's radius for the points off its centroid's plane).
    if (emitter.normal.dot(receiver.centroid - emitter.centroid) <= -receiver.radius - emitter.radius ||
        receiver.normal.dot(emitter.centroid - receiver.centroid) + emitter.radius <= 0.0)
        return false;
    Workspace::Reversed& rev = ws.reversed;
    // A term of row j for i at j's point x (index q); `polygon`: the part of i its shadow ray aims
    // at, null for an exact term (shadow polygons: no ray).
    auto addTerm = [&](const Vec3& x, std::uint32_t q, double f, double whole, double weight, const Vec3* polygon,
                       std::size_t corners) {
        rev.differs.push_back(0);
        rev.factors.push_back(f);
        rev.wholes.push_back(whole);
        rev.weights.push_back(weight);
        rev.points.push_back(x);
        rev.pointIndex.push_back(q);
        if (!polygon) {
            rev.rayOf.push_back(rev.kNoRay);
            return;
        }
        rev.rayOf.push_back(std::uint32_t(rev.rays.segments()));
        if (!rays) return;  // the split replaces the ray terms: their verdicts are not needed
        float origin[3], target[3];
        m_rules.rayOrigin(j, x, origin);
        m_rules.rayTarget(j, i, polygon, corners, q, 0, target);
        rev.rays.addSegment(origin, target);
        if (!m_rules.visibility()) return;
        // Its rays to i's corners, as row j probes them (probeReceiverCorners).
        const std::size_t added = m_rules.receiverCornerTargets(j, i, x, rev.cornerRays.targets);
        for (std::size_t k = 0; k < added; ++k)
            rev.cornerRays.origins.insert(rev.cornerRays.origins.end(), origin, origin + 3);
        rev.cornerRayTerm.insert(rev.cornerRayTerm.end(), added, std::uint32_t(rev.factors.size() - 1));
    };
    const double unit = m_rules.unit();
    double far = 0.0;
    int m = m_rules.pairOrder(j, i);
    if (m == 0) m = m_rules.farPairOrder(j, i, far);  // as castFarRays
    if (m == 0) {  // the far rule: one term, one shadow ray from j's centroid (as addFarPairs)
        if (!(far > 0.0)) return false;
        addTerm(emitter.centroid, 0, far, far, unit, geometry.polygon(i), receiver.count);
        return true;
    }
    m_rules.emitterRule(j, m, ws.rules);
    const std::size_t before = rev.factors.size();
    PairRules::PointTerm term;
    for (std::size_t q = 0; q < ws.rules.quadPoints.size(); ++q) {
        const Vec3& x = ws.rules.quadPoints[q];
        if (!m_rules.pointTerm(j, i, x, ws.rules, counts, term)) continue;
        const double weight = unit * ws.rules.quadWeights[q];  // as row j weighs it (the centroid's weight is 1)
        if (term.exact)  // as addFrom: the visible part from shadow polygons
            addTerm(x, std::uint32_t(q), term.visible, term.factor, weight, nullptr, 0);
        else
            addTerm(x, std::uint32_t(q), term.factor, term.factor, weight, term.polygon, term.corners);
    }
    return rev.factors.size() > before;
}

AnalyticEstimator::Straddle AnalyticEstimator::reversedStraddles(PatchId i, std::size_t p, Workspace& ws,
                                                                 RayCounts& counts) const {
    const Workspace::Reversed& rev = ws.reversed;
    const PatchId j = rev.emitters[p];
    // Which terms row j notes (replaceStraddlingPairs): all of a rule pass's (order 2 and up), the
    // exact term of the centroid pass; its ray term and the far rule's are probed from j's corners
    // and the rims of its view of i (replacePenumbralPairs, PairRules::centroidVerdictHolds).
    double far = 0.0;
    int m = m_rules.pairOrder(j, i);
    if (m == 0) m = m_rules.farPairOrder(j, i, far);
    if (m <= 1) {  // one term, from j's centroid
        const std::uint32_t t = rev.termBegin[p];
        if (rev.termEnd[p] != t + 1 || rev.rayOf[t] == rev.kNoRay) {
            if (m == 0) return Straddle::None;
        } else {
            if (!m_rules.visibility() || !m_rules.probesPenumbra(rev.factors[t])) return Straddle::None;
            const std::uint32_t ray = rev.rayOf[t];
            return m_rules.centroidVerdictHolds(j, i, rev.factors[t], &rev.rays.targets[3 * ray],
                                                rev.rays.blocked[ray] != 0, ws.rules, counts)
                       ? Straddle::None
                       : Straddle::Penumbral;
        }
    }
    double unoccluded = 0.0;
    float least = 2.0f, most = -1.0f;
    for (std::uint32_t t = rev.termBegin[p]; t < rev.termEnd[p]; ++t) {
        const bool exact = rev.rayOf[t] == rev.kNoRay;
        if (m == 1 && !exact) continue;
        const double share = exact ? rev.factors[t] / rev.wholes[t] : rev.rays.blocked[rev.rayOf[t]] ? 0.0 : 1.0;
        unoccluded += rev.wholes[t] * rev.weights[t];
        least = std::min(least, float(share));
        most = std::max(most, float(share));
    }
    return most >= least ? straddleOf(j, i, unoccluded, least, most, ws, counts) : Straddle::None;
}

template <class Piece>
void AnalyticEstimator::splitTerm(PatchId j, PatchId i, std::uint32_t t, Workspace& ws, RayCounts& counts,
                                  double& exact, Piece piece) const {
    const Workspace::Reversed& rev = ws.reversed;
    double visible = 0.0;
    if (m_rules.silhouetteTerm(j, i, rev.points[t], ws.rules, counts, visible)) {  // as row j decides
        if (visible > 0.0) exact = visible * rev.weights[t];
        return;
    }
    float origin[3];
    m_rules.rayOrigin(j, rev.points[t], origin);
    m_rules.forEachPiece(j, i, rev.points[t], rev.pointIndex[t], ws.rules,
                         [&](double f, const float target[3]) { piece(origin, target, f * rev.weights[t]); });
}

void AnalyticEstimator::splitDifferingTerms(PatchId i, Workspace& ws, RayCounts& counts) const {
    // Row j's probe of this patch's corners from each ray term's point (probeReceiverCorners): the
    // same rays, so the same terms disagree, and each such term split as row j splits it, into
    // splitValue (row j keeps that value for the pair, not its ray's verdict).
    Workspace::Reversed& rev = ws.reversed;
    const std::size_t cornerRays = rev.cornerRayTerm.size();
    if (cornerRays == 0) return;
    rev.cornerRays.blocked.resize(cornerRays);
    m_rays->occludedSegmentPairs(rev.cornerRays.origins.data(), rev.cornerRays.targets.data(), cornerRays,
                                 rev.cornerRays.blocked.data());
    counts.rays += cornerRays;
    for (std::size_t q = 0; q < cornerRays; ++q) {
        const std::uint32_t t = rev.cornerRayTerm[q];
        if ((rev.cornerRays.blocked[q] != 0) != (rev.rays.blocked[rev.rayOf[t]] != 0)) rev.differs[t] = 1;
    }
    rev.splitValue.assign(rev.factors.size(), 0.0);
    rev.pieces.clear();
    rev.pieceTerm.clear();
    rev.pieceTermValue.clear();
    for (std::size_t p = 0; p < rev.emitters.size(); ++p) {
        const PatchId j = rev.emitters[p];
        for (std::uint32_t t = rev.termBegin[p]; t < rev.termEnd[p]; ++t) {
            if (!rev.differs[t]) continue;
            const auto piece = [&](const float origin[3], const float target[3], double value) {
                rev.pieces.addSegment(origin, target);
                rev.pieceTerm.push_back(t);
                rev.pieceTermValue.push_back(value);
            };
            splitTerm(j, i, t, ws, counts, rev.splitValue[t], piece);
        }
    }
    if (rev.pieceTerm.empty()) return;
    rev.pieces.blocked.assign(rev.pieceTerm.size(), 0);
    m_rays->occludedSegmentPairs(rev.pieces.origins.data(), rev.pieces.targets.data(), rev.pieceTerm.size(),
                                 rev.pieces.blocked.data());
    counts.rays += rev.pieceTerm.size();
    for (std::size_t k = 0; k < rev.pieceTerm.size(); ++k)  // in piece order, as row j sums them
        if (!rev.pieces.blocked[k]) rev.splitValue[rev.pieceTerm[k]] += rev.pieceTermValue[k];
}

void AnalyticEstimator::splitReversedSilhouettes(PatchId i, Workspace& ws, RayCounts& counts) const {
    // An emitter j whose mesh neighbours disagree with it about i sees i past a silhouette, which
    // moves across i as the point on j moves: each of its ray terms takes i's exact visible part
    // (above PairRules' silhouette bound) or i in pieces, each with its own factor and shadow ray,
    // as row j does where it finds i on a silhouette (the same terms, pieces, aims and rays: equal
    // values where both rows split). Exact terms stay as they are.
    Workspace::Reversed& rev = ws.reversed;
    rev.silhouette.clear();
    for (std::size_t p = 0; p < rev.emitters.size(); ++p) {
        if (rev.whole[p] || !m_rules.geometry().onSilhouette(rev.emitters[p], ws.status)) continue;
        if (rev.termBegin[p] == rev.termEnd[p] && rev.sum[p] == 0.0) {
            // Handed over by row j as a sum: its terms again, with their shadow rays, to tell
            // whether row j computed the pair whole (a straddling pair keeps the handed value).
            const std::size_t first = rev.rays.segments();
            rev.termBegin[p] = std::uint32_t(rev.factors.size());
            reversedTerms(rev.emitters[p], i, true, ws, counts);
            rev.termEnd[p] = std::uint32_t(rev.factors.size());
            const std::size_t added = rev.rays.segments() - first;
            rev.rays.blocked.resize(first + added, 0);
            if (added > 0) {
                m_rays->occludedSegmentPairs(rev.rays.origins.data() + 3 * first, rev.rays.targets.data() + 3 * first,
                                             added, rev.rays.blocked.data() + first);
                counts.rays += added;
            }
            if (reversedStraddles(i, p, ws, counts) != Straddle::None) {
                rev.whole[p] = 1;
                continue;
            }
        }
        rev.silhouette.push_back(std::uint32_t(p));
    }
    rev.rays.clear();
    rev.pieceOf.clear();
    rev.pieceValue.clear();
    for (const std::uint32_t p : rev.silhouette) {
        const PatchId j = rev.emitters[p];
        bool split = false;
        for (std::uint32_t t = rev.termBegin[p]; t < rev.termEnd[p]; ++t) {
            if (rev.rayOf[t] == rev.kNoRay) continue;
            if (!split) {  // the exact terms are kept; the ray terms are replaced by their pieces
                rev.handed[p] = -1.0;
                rev.sum[p] = 0.0;
                for (std::uint32_t u = rev.termBegin[p]; u < rev.termEnd[p]; ++u)
                    if (rev.rayOf[u] == rev.kNoRay && rev.factors[u] > 0.0) rev.sum[p] += rev.factors[u] * rev.weights[u];
                split = true;
            }
            double exact = 0.0;
            splitTerm(j, i, t, ws, counts, exact, [&](const float origin[3], const float target[3], double value) {
                rev.rays.addSegment(origin, target);
                rev.pieceOf.push_back(p);
                rev.pieceValue.push_back(value);
            });
            if (exact > 0.0) rev.sum[p] += exact;
        }
    }
    if (rev.pieceOf.empty()) return;
    rev.rays.blocked.assign(rev.pieceOf.size(), 0);
    m_rays->occludedSegmentPairs(rev.rays.origins.data(), rev.rays.targets.data(), rev.pieceOf.size(),
                                 rev.rays.blocked.data());
    counts.rays += rev.pieceOf.size();
    for (std::size_t k = 0; k < rev.pieceOf.size(); ++k)
        if (!rev.rays.blocked[k]) rev.sum[rev.pieceOf[k]] += rev.pieceValue[k];
}

}  // namespace hemirad
