// The analytic estimator's row: its pairs as a receiver first (analytic_receiver.cpp), then as the
// emitter, its terms for each receiver summed over the points of the pair's rule.
#include "preprocess/hemisphere/analytic_estimator.hpp"

#include <algorithm>

namespace hemirad {

void AnalyticEstimator::prepare(const Scene& scene, const RayScene& rays) {
    m_scene = &scene;
    m_rays = &rays;
    m_rules.build(scene, rays, m_options);
}

AnalyticEstimator::Workspace AnalyticEstimator::workspace(PairExchange& exchange) const {
    Workspace ws;
    const std::size_t n = m_scene->size();
    ws.exchange = &exchange;
    ws.status.assign(n, 0);
    ws.kept.sum.assign(n, -1.0);
    ws.ruled.assign(n, 0);
    ws.seen.unoccluded.assign(n, 0.0);
    ws.seen.least.assign(n, 2.0f);
    ws.seen.most.assign(n, -1.0f);
    ws.byOrder.resize(std::size_t(m_rules.orders().highest()) + 1);  // [0]: the far rule
    ws.reversed.published.assign(n, -1.0);
    return ws;
}

double AnalyticEstimator::addRow(PatchId i, RowAccumulator& row, Workspace& ws, RayCounts& counts) const {
    // Pairs whose other patch emits first: their terms come from that patch's points, and their
    // visibility is the neighbours' status for the silhouette test below.
    double direct = addReversedPairs(i, row, ws, counts);
    if (m_rules.coveredEmitters().covered(i)) ++counts.coveredRows;
    // Receivers by the order of their rule over i (0: the far rule); order 1 (the centroid) takes
    // the rest in one pass.
    for (auto& list : ws.byOrder) list.clear();
    ws.contacts.clear();
    for (PatchId j = 0; j < m_scene->size(); ++j) {
        if (j == i || !m_rules.emitsFor(i, j)) continue;
        if (m_rules.contactPair(i, j)) {  // computed as a whole below
            ws.contacts.push_back(j);
            ws.ruled[j] = 1;
            continue;
        }
        const int m = m_rules.pairOrder(i, j);
        if (m == 1) continue;
        ws.byOrder[m].push_back(j);
        ws.ruled[j] = 1;
    }
    // The far rule's shadow rays from the centroid; their terms are added by the centroid pass,
    // once it has the statuses of its own receivers for the silhouette test (the far rule exists
    // with one origin only, where the centroid pass does too).
    castFarRays(i, ws, counts);
    const double unit = m_rules.unit();
    const EmitterOrders& orders = m_rules.orders();
    if (orders.lowest() == 1) {
        ws.penumbra.clear();
        direct += addFrom(i, m_rules.geometry().shapes[i].centroid, 0, nullptr, unit, row, ws, counts);
        direct += replaceStraddlingPairs(i, ws.point.exact, row, ws, counts);
        direct += replacePenumbralPairs(i, row, ws, counts);
    }
    for (int m = std::max(2, orders.lowest()); m <= orders.highest(); ++m) {
        if (ws.byOrder[m].empty()) continue;
        m_rules.emitterRule(i, m, ws.rules);
        // addFrom leaves the scratch's rule alone.
        const std::vector<Vec3>& points = ws.rules.quadPoints;
        const std::vector<double>& weights = ws.rules.quadWeights;
        for (std::size_t q = 0; q < points.size(); ++q)
            direct += addFrom(i, points[q], std::uint32_t(q), &ws.byOrder[m], unit * weights[q], row, ws, counts);
        direct += replaceStraddlingPairs(i, ws.byOrder[m], row, ws, counts);
        for (const PatchId j : ws.byOrder[m]) ws.ruled[j] = 0;
    }
    for (const PatchId j : ws.contacts) {
        bool viewed = false;
        const double value = m_rules.contactValue(i, j, ws.rules, counts, viewed);
        ws.ruled[j] = 0;
        if (!viewed) continue;  // as the other row finds it: no term
        ws.kept.keep(j, value);
        if (!(value > 0.0)) continue;
        row.addWeight(j, value);
        direct += value;
    }
    for (const PatchId j : ws.byOrder[0]) ws.ruled[j] = ws.status[j] = 0;
    for (const PatchId j : ws.reversed.emitters) ws.status[j] = 0;
    ws.kept.outgoing.clear();
    for (const PatchId j : ws.kept.touched) {
        ws.kept.outgoing.push_back({j, m_rules.handedValue(ws.kept.sum[j], i, j)});
        ws.kept.sum[j] = -1.0;
    }
    ws.exchange->publish(i, ws.kept.outgoing);
    ws.kept.touched.clear();
    return direct / unit;
}

void AnalyticEstimator::castFarRays(PatchId i, Workspace& ws, RayCounts& counts) const {
    Workspace::Far& far = ws.far;
    far.patches.clear();  // the pairs with a shadow ray
    far.factors.clear();
    far.rays.clear();
    const PatchGeometry& geometry = m_rules.geometry();
    for (const PatchId j : ws.byOrder[0]) {
        double f = 0.0;
        const int m = m_rules.farPairOrder(i, j, f);
        if (m > 0) {  // too large for one shadow ray: the rule's points with exact visibility
            if (m == 1)
                ws.ruled[j] = 0;
            else
                ws.byOrder[std::size_t(m)].push_back(j);
            continue;
        }
        far.patches.push_back(j);
        far.factors.push_back(f);
        if (!m_rules.visibility()) continue;  // no shadow ray: no target
        float target[3];
        m_rules.rayTarget(i, j, geometry.polygon(j), geometry.shapes[j].count, 0, 0, target);
        far.rays.targets.insert(far.rays.targets.end(), target, target + 3);
    }
    far.rays.blocked.assign(far.patches.size(), 0);
    if (m_rules.visibility() && !far.patches.empty()) {
        float origin[3];
        m_rules.rayOrigin(i, geometry.shapes[i].centroid, origin);
        m_rays->occludedSegments(origin, far.rays.targets.data(), far.patches.size(), far.rays.blocked.data());
        counts.rays += far.patches.size();
    }
    for (std::size_t k = 0; k < far.patches.size(); ++k) ws.status[far.patches[k]] = far.rays.blocked[k] ? 2 : 1;
    probeReceiverCorners(i, geometry.shapes[i].centroid, far.patches, far.factors, far.rays.blocked, far.cornersDiffer,
                         ws, counts);
}

double AnalyticEstimator::addFarPairs(double weight, RowAccumulator& row, Workspace& ws) const {
    const Workspace::Far& far = ws.far;
    double sum = 0.0;
    for (std::size_t k = 0; k < far.patches.size(); ++k) {
        const PatchId j = far.patches[k];
        if (!(far.factors[k] > 0.0)) continue;  // facing away: nothing to split either
        if (!far.cornersDiffer[k])  // else its split value, kept by the centroid pass
            ws.kept.keep(j, far.rays.blocked[k] ? 0.0 : far.factors[k] * weight);
        if (m_rules.visibility() && m_rules.probesPenumbra(far.factors[k]))
            ws.penumbra.add(j, far.factors[k], &far.rays.targets[3 * k], far.rays.blocked[k]);
        // Split by the centroid pass, as its own receivers: on a silhouette, or its corners' rays disagreed.
        if (far.cornersDiffer[k] || m_rules.geometry().onSilhouette(j, ws.status)) {
            ws.point.split.push_back(j);
            ws.point.splitKept.push_back(far.cornersDiffer[k]);
            continue;
        }
        if (far.rays.blocked[k]) continue;
        row.addWeight(j, far.factors[k] * weight);
        sum += far.factors[k] * weight;
    }
    return sum;
}

double AnalyticEstimator::addFrom(PatchId i, const Vec3& x, std::uint32_t point, const std::vector<PatchId>* candidates,
                                  double weight, RowAccumulator& row, Workspace& ws, RayCounts& counts) const {
    Workspace::Point& p = ws.point;
    const bool visibility = m_rules.visibility();
    auto aimAt = [&](PatchId j, double f, const float target[3]) {
        p.candidates.push_back(j);
        p.factors.push_back(f);
        if (visibility) p.rays.targets.insert(p.rays.targets.end(), target, target + 3);  // no shadow ray: no target
    };
    float origin[3];
    m_rules.rayOrigin(i, x, origin);
    auto shoot = [&] {
        if (!visibility) {
            p.rays.blocked.assign(p.candidates.size(), 0);
            return;
        }
        p.rays.blocked.resize(p.candidates.size());
        m_rays->occludedSegments(origin, p.rays.targets.data(), p.candidates.size(), p.rays.blocked.data());
        counts.rays += p.candidates.size();
    };
    p.candidates.clear();
    p.factors.clear();
    p.rays.clear();
    p.exact.clear();
    p.exactVisible.clear();
    p.exactWhole.clear();
    const std::size_t count = candidates ? candidates->size() : m_scene->size();
    PairRules::PointTerm term;
    for (std::size_t c = 0; c < count; ++c) {
        const PatchId j = candidates ? (*candidates)[c] : PatchId(c);
        if (j == i || (!candidates && (ws.ruled[j] || !m_rules.emitsFor(i, j)))) continue;
        if (!m_rules.pointTerm(i, j, x, ws.rules, counts, term)) continue;
        if (term.exact) {
            p.exact.push_back(j);
            p.exactVisible.push_back(term.visible);
            p.exactWhole.push_back(term.factor);
            continue;
        }
        float target[3] = {};
        if (visibility) m_rules.rayTarget(i, j, term.polygon, term.corners, point, 0, target);
        aimAt(j, term.factor, target);
    }
    shoot();
    probeReceiverCorners(i, x, p.candidates, p.factors, p.rays.blocked, p.cornersDiffer, ws, counts);
    // Visibility of each patch from its shadow ray; a patch whose mesh neighbours disagree with it
    // sits on a silhouette and is split into pieces, each with its own factor and shadow ray, as is
    // one whose corners' rays disagree with its centre's (probeReceiverCorners).
    for (std::size_t k = 0; k < p.candidates.size(); ++k) ws.status[p.candidates[k]] = p.rays.blocked[k] ? 2 : 1;
    double sum = 0.0;
    for (std::size_t k = 0; k < p.exact.size(); ++k) {
        ws.seen.note(p.exact[k], p.exactVisible[k] / p.exactWhole[k], p.exactWhole[k] * weight);
        ws.status[p.exact[k]] = p.exactVisible[k] >= 0.5 * p.exactWhole[k] ? 1 : 2;  // as its centre's ray would say
        ws.kept.keep(p.exact[k], p.exactVisible[k] > 0.0 ? p.exactVisible[k] * weight : 0.0);
        if (!(p.exactVisible[k] > 0.0)) continue;
        row.addWeight(p.exact[k], p.exactVisible[k] * weight);
        sum += p.exactVisible[k] * weight;
    }
    p.split.clear();
    p.splitKept.clear();
    const PatchGeometry& geometry = m_rules.geometry();
    for (std::size_t k = 0; k < p.candidates.size(); ++k) {
        const PatchId j = p.candidates[k];
        if (!p.cornersDiffer[k]) ws.kept.keep(j, p.rays.blocked[k] ? 0.0 : p.factors[k] * weight);  // else its split value
        // The centre ray's verdict is the term's share, split or not (as the receiving row sees it).
        if (candidates)
            ws.seen.note(j, p.rays.blocked[k] ? 0.0 : 1.0, p.factors[k] * weight);
        else if (visibility && m_rules.probesPenumbra(p.factors[k]))
            ws.penumbra.add(j, p.factors[k], &p.rays.targets[3 * k], p.rays.blocked[k]);
        if (p.cornersDiffer[k] || geometry.onSilhouette(j, ws.status)) {
            p.split.push_back(j);
            p.splitKept.push_back(p.cornersDiffer[k]);
        } else if (!p.rays.blocked[k]) {
            row.addWeight(j, p.factors[k] * weight);
            sum += p.factors[k] * weight;
        }
    }
    if (!candidates) sum += addFarPairs(weight, row, ws);  // the centroid stands for the far rule's point too
    for (const PatchId j : p.candidates) ws.status[j] = 0;
    for (const PatchId j : p.exact) ws.status[j] = 0;
    // A receiver on a silhouette: the edge moves across it, so its centre's ray (all or nothing) is
    // not its term. Above PairRules' silhouette bound its exact visible part, below it in pieces
    // with a shadow ray each.
    // A term split because its corners' rays disagreed keeps its split value for the exchange (the
    // receiver's row splits it alike: splitDifferingTerms); one split on a silhouette alone keeps
    // its ray's verdict (the receiver's row decides its own silhouettes).
    p.candidates.clear();
    p.factors.clear();
    p.rays.clear();
    p.pieceOf.clear();
    p.splitValue.assign(p.split.size(), 0.0);
    for (std::size_t s = 0; s < p.split.size(); ++s) {
        const PatchId j = p.split[s];
        double visible = 0.0;
        if (m_rules.silhouetteTerm(i, j, x, ws.rules, counts, visible)) {
            if (!(visible > 0.0)) continue;
            p.splitValue[s] = visible * weight;
            row.addWeight(j, visible * weight);
            sum += visible * weight;
            continue;
        }
        m_rules.forEachPiece(i, j, x, point, ws.rules, [&](double f, const float target[3]) {
            aimAt(j, f, target);
            p.pieceOf.push_back(std::uint32_t(s));
        });
    }
    if (!p.candidates.empty()) {
        shoot();
        for (std::size_t k = 0; k < p.candidates.size(); ++k) {
            if (p.rays.blocked[k]) continue;
            row.addWeight(p.candidates[k], p.factors[k] * weight);
            sum += p.factors[k] * weight;
            p.splitValue[p.pieceOf[k]] += p.factors[k] * weight;  // in piece order, as the receiver's row sums them
        }
    }
    for (std::size_t s = 0; s < p.split.size(); ++s)
        if (p.splitKept[s]) ws.kept.keep(p.split[s], p.splitValue[s]);
    return sum;
}

void AnalyticEstimator::probeReceiverCorners(PatchId i, const Vec3& x, const std::vector<PatchId>& patches,
                                             const std::vector<double>& factors,
                                             const std::vector<std::uint8_t>& blocked, std::vector<std::uint8_t>& differ,
                                             Workspace& ws, RayCounts& counts) const {
    differ.assign(patches.size(), 0);
    if (!m_rules.visibility()) return;
    ws.cornerRays.clear();
    ws.cornerRayTerm.clear();
    for (std::size_t k = 0; k < patches.size(); ++k) {
        if (!(factors[k] > 0.0)) continue;  // no term
        const std::size_t added = m_rules.receiverCornerTargets(i, patches[k], x, ws.cornerRays.targets);
        ws.cornerRayTerm.insert(ws.cornerRayTerm.end(), added, std::uint32_t(k));
    }
    const std::size_t count = ws.cornerRayTerm.size();
    if (count == 0) return;
    float origin[3];
    m_rules.rayOrigin(i, x, origin);
    ws.cornerRays.blocked.resize(count);
    m_rays->occludedSegments(origin, ws.cornerRays.targets.data(), count, ws.cornerRays.blocked.data());
    counts.rays += count;
    for (std::size_t q = 0; q < count; ++q) {
        const std::uint32_t k = ws.cornerRayTerm[q];
        if ((ws.cornerRays.blocked[q] != 0) != (blocked[k] != 0)) differ[k] = 1;
    }
}

double AnalyticEstimator::replaceStraddlingPairs(PatchId i, const std::vector<PatchId>& receivers,
                                                 RowAccumulator& row, Workspace& ws, RayCounts& counts) const {
    Workspace::Seen& seen = ws.seen;
    double change = 0.0;
    for (const PatchId j : receivers) {
        const double unoccluded = seen.unoccluded[j], least = seen.least[j], most = seen.most[j];
        seen.reset(j);
        if (most < least) continue;  // no term
        const Straddle straddle = straddleOf(i, j, unoccluded, least, most, ws, counts);
        if (straddle == Straddle::None) continue;
        change += replaceEntry(j, replacementValue(straddle, i, j, ws, counts), row, ws);
    }
    return change;
}

double AnalyticEstimator::replacePenumbralPairs(PatchId i, RowAccumulator& row, Workspace& ws, RayCounts& counts) const {
    Workspace::Penumbra& pen = ws.penumbra;
    const std::size_t count = pen.patches.size();
    if (count == 0) return 0.0;
    // The corners' rays as cornersAgree casts them, one batch per corner (the same verdicts).
    // (A covered emitter has no centroid pass: no corner of this row is covered.)
    const PatchShape& emitter = m_rules.geometry().shapes[i];
    pen.agree.assign(count, 1);
    pen.verdicts.resize(count);
    for (std::uint32_t c = 0; c < emitter.count; ++c) {
        float origin[3];
        m_rules.rayOrigin(i, m_rules.cornerProbe(i, c), origin);
        m_rays->occludedSegments(origin, pen.targets.data(), count, pen.verdicts.data());
        counts.rays += count;
        for (std::size_t k = 0; k < count; ++k)
            if ((pen.verdicts[k] != 0) != (pen.blocked[k] != 0)) pen.agree[k] = 0;
    }
    // Where the corners agree, the bundle's rims (extremesAgree): with cornersAgree's verdicts,
    // PairRules::centroidVerdictHolds.
    double change = 0.0;
    for (std::size_t k = 0; k < count; ++k) {
        const PatchId j = pen.patches[k];
        if (pen.agree[k] && m_rules.extremesAgree(i, j, pen.factors[k], pen.blocked[k] != 0, ws.rules, counts)) continue;
        change += replaceEntry(j, replacementValue(Straddle::Penumbral, i, j, ws, counts), row, ws);
    }
    pen.clear();
    return change;
}

double AnalyticEstimator::replaceEntry(PatchId j, double value, RowAccumulator& row, Workspace& ws) {
    const double before = row.weight(j);
    row.addWeight(j, value - before);
    ws.kept.keep(j, 0.0);
    ws.kept.sum[j] = value;
    return value - before;
}

double AnalyticEstimator::replacementValue(Straddle straddle, PatchId e, PatchId r, Workspace& ws,
                                          RayCounts& counts) const {
    return straddle == Straddle::Whole ? m_rules.straddlingValue(e, r, ws.rules, counts)
                                       : m_rules.penumbralValue(e, r, ws.rules, counts);
}

AnalyticEstimator::Straddle AnalyticEstimator::straddleOf(PatchId e, PatchId r, double unoccluded, double least,
                                                          double most, Workspace& ws, RayCounts& counts) const {
    if (straddlesWhole(e, r, unoccluded, least, most, ws, counts)) return Straddle::Whole;  // may widen least..most
    if (m_rules.spreadsPenumbra(unoccluded, least, most)) return Straddle::Penumbral;
    if (!m_rules.probesPenumbra(unoccluded / m_rules.unit())) return Straddle::None;
    const bool allOrNothing = least == most && (least == 0.0 || least == 1.0);  // the points' shares
    // Below the straddle bound straddlesWhole did not ask the corners: their shares (and the edges'
    // midpoints'), as it would. A wall whose top edge alone sees over a roof had every point's
    // share small or 0: district1k's 740 -> 905 read 0 for 2.4e-4 (its top corners see 94 % of
    // the roof). With this probe the district's entries off by more than 1e-4 went from 19 to 16.
    if (!m_rules.straddles(unoccluded, 0.0, 1.0) &&
        cornersWiden(e, r, least, most, ws, counts, [&] { return m_rules.spreadsPenumbra(unoccluded, least, most); }))
        return Straddle::Penumbral;
    // Every point saw all of r, or none of it: the corners' rays to its centre or the rims may
    // still see otherwise, as the centroid pass asks them (replacePenumbralPairs).
    if (!allOrNothing) return Straddle::None;
    const PatchGeometry& geometry = m_rules.geometry();
    float target[3];
    m_rules.rayTarget(e, r, geometry.polygon(r), geometry.shapes[r].count, 0, 0, target);
    return m_rules.centroidVerdictHolds(e, r, unoccluded / m_rules.unit(), target, least == 0.0, ws.rules, counts)
               ? Straddle::None
               : Straddle::Penumbral;
}

bool AnalyticEstimator::straddlesWhole(PatchId e, PatchId r, double unoccluded, double& least, double& most,
                                       Workspace& ws, RayCounts& counts) const {
    if (m_rules.straddles(unoccluded, least, most)) return true;
    // Every term saw about as much: a shadow's edge may still cross the emitter between its points
    // and its rim, whatever share the points saw, all of r included (district1k's 207 -> 534 had
    // 0.00693 for 0.00599, now 0.00599). Its corners and edges' midpoints say, wherever a spread
    // of 1 would matter.
    if (!m_rules.straddles(unoccluded, 0.0, 1.0)) return false;
    return cornersWiden(e, r, least, most, ws, counts, [&] { return m_rules.straddles(unoccluded, least, most); });
}

template <class Enough>
bool AnalyticEstimator::cornersWiden(PatchId e, PatchId r, double& least, double& most, Workspace& ws,
                                     RayCounts& counts, Enough enough) const {
    const PatchShape& emitter = m_rules.geometry().shapes[e];
    const auto widen = [&](const Vec3& x) {
        const double share = m_rules.visibleShare(e, r, x, ws.rules, counts);
        if (share < 0.0) return false;
        least = std::min(least, double(float(share)));
        most = std::max(most, double(float(share)));
        return enough();
    };
    for (std::uint32_t k = 0; k < emitter.count; ++k)
        if (!m_rules.cornerCovered(e, k) && widen(m_rules.cornerProbe(e, k))) return true;  // a covered one sees nothing
    for (std::uint32_t k = 0; k < emitter.count; ++k) {
        const std::uint32_t next = k + 1 == emitter.count ? 0 : k + 1;
        if (m_rules.cornerCovered(e, k) || m_rules.cornerCovered(e, next)) continue;
        if (widen(0.5 * (m_rules.cornerProbe(e, k) + m_rules.cornerProbe(e, next)))) return true;
    }
    return false;
}

}  // namespace hemirad
