// The arcs of the layout inside the pieces: the two rings of each T-shirt and the two arcs of each
// handle (design.md §2).

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "detail/curves.h"
#include "detail/patches.h"
#include "detail/stages.h"
#include "detail/surface.h"
#include "quadcage/core/errors.h"

namespace quadcage::layout::detail {

std::optional<std::vector<int>> route_ring(Builder& b, const std::vector<int>& s_ids,
                                           const std::array<Hole, 4>& holes, const std::array<int, 4>& x,
                                           bool face_right, double* length, int max_vertices) {
    std::vector<int> arcs;
    std::vector<int> label;
    std::vector<char> outside;
    int piece = -1, labelled_at = -1;  // labelled_at: b.splits_ when `label` was made
    std::function<double(int)> last_cost;  // the last search's path cost, its blocked vertices,
    std::vector<char> last_block;          // and b.splits_ when it was made
    int cost_at = -1;
    std::vector<char> reached;
    bool opened = false;  // the last failed search had its route opened (Builder::open_route)
    for (int j = 0, attempt = 0; j < 4; ++attempt) {
        // Room on demand: only the chords a failed search's route must cross are split (splitting
        // all chords before every search lets each new curve hug the last: the mesh grows
        // several-fold); the walls round the search only if no route crosses chords alone.
        if (attempt > kRoomAttempts) return std::nullopt;
        if (attempt > 0 && !opened && b.open_room(reached, attempt) == 0) return std::nullopt;
        if (b.s_.num_vertices() > max_vertices) return std::nullopt;  // worse than a ring already found
        // The pieces change only with the surface (an arc added is no S-cycle): after an arc that
        // needed no split, the last labels still hold.
        if (b.splits_ != labelled_at) {
            label_pieces(b, s_ids, &label);
            piece = label[triangle_beside(b.s_, b.curves_[holes[0].curve], holes[0].side)];
            outside = outside_piece(b.s_, label, piece);
            labelled_at = b.splits_;
        }
        const std::vector<char> block = b.blocked();
        // After an arc that needed no split, only the arc is new: the last cost's field is lowered
        // from it instead of searched again.
        const std::function<double(int)> cost =
            b.splits_ == cost_at ? b.grown_cost_near(last_cost, last_block, block, &outside)
                                 : b.cost_near(block, &outside, kAdjacency);
        last_cost = cost;
        last_block = block;
        cost_at = b.splits_;
        const int jn = (j + 1) % 4;
        const std::vector<int> here = side_toward(b.s_, b.curves_[holes[j].curve], x[j], label, piece);
        const std::vector<int> there = side_toward(b.s_, b.curves_[holes[jn].curve], x[jn], label, piece);
        std::vector<int> leave = here, arrive = there;
        if (j > 0) {  // the arc arriving at x[j] fixes on which side of it this one may leave
            const Cycle& in = b.curves_[arcs.back()];
            const int i = index_in(here, in[in.size() - 2]);
            QC_CHECK(i >= 0, "route_ring: arriving arc not in the piece's sector");
            leave = face_right ? slice(here, i + 1, static_cast<int>(here.size())) : slice(here, 0, i);
        }
        if (jn == 0) {  // closing at x[0]: arrive on the right side of the first arc's start
            const int i = index_in(there, b.curves_[arcs.front()][1]);
            QC_CHECK(i >= 0, "route_ring: first arc not in the piece's sector");
            arrive = face_right ? slice(there, 0, i) : slice(there, i + 1, static_cast<int>(there.size()));
        }
        double cost_total = 0;
        const std::vector<int> interior =
            b.sector_path(x[j], leave, x[jn], arrive, block, cost, &cost_total, &reached);
        if (interior.empty()) {
            opened = b.open_route(x[j], leave, x[jn], arrive, block, cost) > 0;
            continue;
        }
        Cycle arc{x[j]};
        arc.insert(arc.end(), interior.begin(), interior.end());
        arc.push_back(x[jn]);
        *length += path_length(b.s_.mesh(), arc);
        arcs.push_back(b.add_curve(arc, false));
        ++j;
        attempt = -1;
    }
    return arcs;
}

namespace {

// Distances inside `piece` from the vertices of closed curve `from_curve`, crossing no S-cycle.
std::vector<double> hole_distances(const Builder& b, const std::vector<int>& label, int piece, int from_curve,
                                   const std::vector<char>& on_s) {
    std::vector<char> block = outside_piece(b.s_, label, piece);
    for (size_t v = 0; v < block.size(); ++v) block[v] = block[v] || on_s[v];
    return distances_from(b.s_, block, b.curves_[from_curve]);
}

using HoleReach = std::array<std::array<std::vector<double>, 4>, 4>;

// reach[k][m][i]: distance inside `piece` from vertex i of hole k, leaving through the piece's side,
// to hole m (distance fields `field`); +inf for m = k.
HoleReach hole_reach(const Builder& b, const std::vector<Hole>& holes, const std::array<std::vector<double>, 4>& field,
                     const std::vector<int>& label, int piece) {
    HoleReach reach;
    for (int k = 0; k < 4; ++k) {
        const Cycle& c = b.curves_[holes[k].curve];
        for (auto& r : reach[k]) r.assign(c.size(), kInf);
        for (size_t i = 0; i < c.size(); ++i)
            for (int w : side_toward(b.s_, c, c[i], label, piece)) {
                const double step = norm(b.s_.point(w) - b.s_.point(c[i]));
                for (int m = 0; m < 4; ++m)
                    if (m != k && field[m][w] < kInf) reach[k][m][i] = std::min(reach[k][m][i], field[m][w] + step);
            }
    }
    return reach;
}

// The T-shirt (paper, Fig. 7; design.md §2): 2 corners on each of its 4 holes, a bottom ring and
// a top ring through them in one cyclic order of the holes. Tries the 3 cyclic orders in both
// directions and keeps the shortest pair of rings. Adds the rings to b and returns, per hole, its
// (bottom, top) corners.
std::vector<std::pair<Hole, std::array<int, 2>>> route_tshirt(Builder& b, const std::vector<int>& s_ids,
                                                              const std::vector<Hole>& holes,
                                                              std::vector<int>* arcs) {
    std::vector<int> label;
    label_pieces(b, s_ids, &label);
    const int piece = label[triangle_beside(b.s_, b.curves_[holes[0].curve], holes[0].side)];
    std::vector<char> on_s(b.s_.num_vertices(), 0);
    for (int id : s_ids)
        for (int v : b.curves_[id]) on_s[v] = 1;
    std::array<std::vector<double>, 4> field;
    for (int k = 0; k < 4; ++k) field[k] = hole_distances(b, label, piece, holes[k].curve, on_s);
    // The 3 cyclic orders of 4 holes, each in both directions (entries 2i and 2i+1).
    static const int kOrders[6][4] = {{0, 1, 2, 3}, {0, 3, 2, 1}, {0, 1, 3, 2},
                                      {0, 2, 3, 1}, {0, 2, 1, 3}, {0, 3, 1, 2}};
    struct Plan {
        std::array<Hole, 4> holes;
        std::array<int, 4> bottom{}, top{};
        double estimate = 0;  // both rings' length, from the hole distance fields
    };
    const HoleReach reach = hole_reach(b, holes, field, label, piece);
    std::array<Plan, 6> plans;
    for (int o = 0; o < 6; ++o) {
        const auto& order = kOrders[o];
        Plan& plan = plans[o];
        for (int j = 0; j < 4; ++j) {
            const int k = order[j], kp = order[(j + 3) % 4], kn = order[(j + 1) % 4];
            plan.holes[j] = holes[k];
            const Cycle& c = b.curves_[holes[k].curve];
            double low = kInf;
            size_t at = 0;
            for (size_t i = 0; i < c.size(); ++i) {
                const double d = reach[k][kp][i] + reach[k][kn][i];
                if (d < low) {
                    low = d;
                    at = i;
                }
            }
            plan.bottom[j] = c[at];
            plan.top[j] = vertex_at_fraction(b.s_.mesh(), c, at, 0.5);
            plan.estimate += 0.5 * low + reach[k][kn][static_cast<size_t>(index_in(c, plan.top[j]))];
        }
    }
    // Route the cyclic orders from the most promising estimate on, both directions each (each
    // routing is a handful of searches).
    std::array<int, 3> cyclic{0, 1, 2};
    std::stable_sort(cyclic.begin(), cyclic.end(),
                     [&](int x, int y) { return plans[2 * x].estimate < plans[2 * y].estimate; });
    // The shorter direction of the first cyclic order that routes, as long as its rings add at
    // most kRingSplitsAccepted vertices; beyond that, every routing, fewest vertices added first,
    // then shortest: a ring that must squeeze past the curves round it splits a chord per edge of
    // each corridor it takes, and the next arc hugs the split.
    struct Rings {
        Builder b;
        double length = kInf;
        int added = 0;
        std::vector<std::pair<Hole, std::array<int, 2>>> corners;
        std::vector<int> arcs;
    };
    const int n0 = b.s_.num_vertices();
    std::optional<Rings> best;
    bool by_added = false;  // the choice is made by vertices added, then length
    auto better = [&](int added, double length) {
        if (!best) return true;
        if (!by_added) return length < best->length;
        return added < best->added || (added == best->added && length < best->length);
    };
    std::vector<Rings> other;  // the first order's other routing, for the choice by vertices added
    for (int cyc : cyclic) {
        for (int o = 2 * cyc; o < 2 * cyc + 2; ++o) {
            const Plan& plan = plans[o];
            Builder trial = b;
            double length = 0;
            const int cap = by_added ? n0 + best->added : std::numeric_limits<int>::max();
            const auto low_ring = route_ring(trial, s_ids, plan.holes, plan.bottom, true, &length, cap);
            if (!low_ring) continue;
            const auto high_ring = route_ring(trial, s_ids, plan.holes, plan.top, false, &length, cap);
            if (!high_ring) continue;
            Rings r{std::move(trial), length, 0, {}, *low_ring};
            r.added = r.b.s_.num_vertices() - n0;
            for (int j = 0; j < 4; ++j) r.corners.push_back({plan.holes[j], {plan.bottom[j], plan.top[j]}});
            r.arcs.insert(r.arcs.end(), high_ring->begin(), high_ring->end());
            if (better(r.added, r.length)) {
                if (best && !by_added) other.push_back(std::move(*best));
                best = std::move(r);
            } else if (!by_added) {
                other.push_back(std::move(r));
            }
        }
        if (!best || by_added) continue;
        if (best->added <= kRingSplitsAccepted) break;
        by_added = true;
        for (Rings& r : other)
            if (better(r.added, r.length)) best = std::move(r);
        other.clear();
    }
    QC_CHECK(best.has_value(), "no pair of rings could be routed in a T-shirt");
    b = std::move(best->b);
    arcs->insert(arcs->end(), best->arcs.begin(), best->arcs.end());
    return best->corners;
}

// A handle (annulus between holes A and B, 2 corners each) becomes 2 quads: two arcs across it.
// Both pairings (twists) are tried; the shorter is kept.
void route_handle(Builder& b, const std::vector<int>& s_ids, const Hole& A, const std::array<int, 2>& a,
                  const Hole& B, const std::array<int, 2>& c, std::vector<int>* arcs) {
    double best = kInf;
    std::optional<Builder> best_builder;
    std::vector<int> best_arcs;
    for (int twist = 0; twist < 2; ++twist) {
        Builder trial = b;
        double length = 0;
        std::vector<int> made;
        std::vector<char> reached;
        bool opened = false;
        for (int k = 0, attempt = 0; k < 2 && attempt <= kRoomAttempts; ++attempt) {
            const int from = a[k], to = c[(k + twist) % 2];
            if (attempt > 0 && !opened && trial.open_room(reached, attempt) == 0)
                break;  // room on demand, as in route_ring()
            std::vector<int> label;
            label_pieces(trial, s_ids, &label);
            const int piece = label[triangle_beside(trial.s_, trial.curves_[A.curve], A.side)];
            const std::vector<char> block = trial.blocked();
            const std::vector<char> outside = outside_piece(trial.s_, label, piece);
            const auto cost = trial.cost_near(block, &outside, kAdjacency);
            const auto leave = side_toward(trial.s_, trial.curves_[A.curve], from, label, piece);
            const auto arrive = side_toward(trial.s_, trial.curves_[B.curve], to, label, piece);
            const std::vector<int> interior =
                trial.sector_path(from, leave, to, arrive, block, cost, nullptr, &reached);
            if (interior.empty()) {
                opened = trial.open_route(from, leave, to, arrive, block, cost) > 0;
                continue;
            }
            Cycle arc{from};
            arc.insert(arc.end(), interior.begin(), interior.end());
            arc.push_back(to);
            length += path_length(trial.s_.mesh(), arc);
            made.push_back(trial.add_curve(arc, false));
            ++k;
            attempt = -1;
        }
        if (made.size() != 2 || length >= best) continue;
        best = length;
        best_arcs = made;
        best_builder.emplace(std::move(trial));
    }
    QC_CHECK(best_builder.has_value(), "no pair of arcs could be routed across a handle");
    b = std::move(*best_builder);
    arcs->insert(arcs->end(), best_arcs.begin(), best_arcs.end());
}

}  // namespace

Network network_of_handles_and_tshirts(Builder& b, int g, const std::vector<int>& handle_loops,
                                        bool from_handle_loops, bool necks, const Say& say) {
    Network net;
    std::optional<std::vector<int>> tubes;
    if (from_handle_loops) {
        for (int i = 0; i < 2 * g; ++i) b.obstacle_[i] = 0;
        if (necks) {
            tubes = neck_s_cycles(b, g, say);
            if (!tubes) throw NoNecks("no pants decomposition at the necks pairs into T-shirts");
        }
        if (!tubes) tubes = tube_s_cycles(b, handle_loops, g, say);
        if (!tubes) say("the handle loops gave no S-cycles; Algorithm 1's instead");
        for (int i = 0; i < 2 * g; ++i) b.obstacle_[i] = 1;
    }
    net.s_cycles = tubes ? *tubes : place_s_cycles(b, g, say);
    net.s_cycles_from_handle_loops = tubes.has_value();
    // From here on the orthogonal system is scaffolding: layout curves may cross it.
    for (int i = 0; i < 2 * g; ++i) b.obstacle_[i] = 0;
    const Pieces pieces = find_pieces(b, net.s_cycles, g);
    std::vector<std::array<int, 2>> corners_on(b.curves_.size(), {-1, -1});
    int shirt = 0;
    for (const auto& holes : pieces.holes) {
        if (holes.size() != 4) continue;
        say("T-shirt " + std::to_string(++shirt) + " of " + std::to_string(g - 1) + surface_size(b));
        for (const auto& [hole, cs] : route_tshirt(b, net.s_cycles, holes, &net.arcs)) {
            corners_on[hole.curve] = cs;
            net.corners.push_back(cs[0]);
            net.corners.push_back(cs[1]);
        }
    }
    int handle = 0;
    for (const auto& holes : pieces.holes) {
        if (holes.size() != 2) continue;
        say("handle " + std::to_string(++handle) + " of " + std::to_string(2 * g - 2) + surface_size(b));
        route_handle(b, net.s_cycles, holes[0], corners_on[holes[0].curve], holes[1],
                     corners_on[holes[1].curve], &net.arcs);
    }
    for (int id : net.s_cycles) net.closed.push_back({id, {corners_on[id][0], corners_on[id][1]}});
    return net;
}

}  // namespace quadcage::layout::detail
