// Algorithm 1 (paper, Section 4): the 4g-4 S-cycles placed on the arcs of the b-curves.

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

std::vector<int> place_s_cycles(Builder& b, int g, const Say& say) {
    struct Spot {
        int curve;  // the b-curve
        int u;      // crossing vertex
    };
    std::vector<Spot> spots;
    for (int h = 1; h <= g; ++h) {
        const int bi = 2 * h - 1;
        const int per_arc = (h == 1 || h == g) ? 1 : 2;
        // Room: every arc needs enough vertices for its u's, away from its ends and each other.
        for (int guard = 0;; ++guard) {
            const Cycle& c = b.curves_[bi];
            const int p1 = common_vertex(b.curves_[bi - 1], c);
            const size_t i1 = static_cast<size_t>(index_in(c, p1));
            const int p2 =
                h < g ? common_vertex(c, b.curves_[bi + 1]) : vertex_at_fraction(b.s_.mesh(), c, i1, 0.5);
            const size_t i2 = static_cast<size_t>(index_in(c, p2));
            const size_t n = c.size();
            const size_t arc1 = (i2 + n - i1) % n - 1, arc2 = (i1 + n - i2) % n - 1;
            if (std::min(arc1, arc2) >= static_cast<size_t>(4 * per_arc + 3)) {
                for (int arc = 0; arc < 2; ++arc) {
                    const size_t start = arc == 0 ? i1 : i2, stop = arc == 0 ? i2 : i1;
                    Cycle piece;  // the arc, ends included
                    for (size_t i = start; i != stop; i = (i + 1) % n) piece.push_back(c[i]);
                    piece.push_back(c[stop]);
                    const double len = path_length(b.s_.mesh(), piece);
                    std::vector<int> used;
                    for (int k = 1; k <= per_arc; ++k) {
                        const double want = len * k / (per_arc + 1);
                        double run = 0, best = kInf;
                        int pick = -1;
                        for (size_t i = 1; i + 1 < piece.size(); ++i) {
                            run += norm(b.s_.point(piece[i]) - b.s_.point(piece[i - 1]));
                            if (i < 2 || i + 2 >= piece.size()) continue;  // keep off the crossings
                            if (std::find(used.begin(), used.end(), piece[i]) != used.end()) continue;
                            if (std::abs(run - want) < best) {
                                best = std::abs(run - want);
                                pick = piece[i];
                            }
                        }
                        QC_CHECK(pick >= 0, "no room for an S-cycle on b" + std::to_string(h));
                        used.push_back(pick);
                        spots.push_back({bi, pick});
                    }
                }
                break;
            }
            QC_CHECK(guard < 8, "b" + std::to_string(h) + ": arcs stay too short after refinement");
            std::vector<std::pair<int, int>> edges;
            for (size_t i = 0; i < n; ++i) edges.push_back({c[i], c[(i + 1) % n]});
            b.split_curve_edges(edges);
        }
    }
    std::vector<int> ids;
    for (size_t k = 0; k < spots.size(); ++k) {
        say("S-cycle " + std::to_string(k + 1) + " of " + std::to_string(spots.size()) + surface_size(b));
        std::vector<int> path;
        std::vector<char> reached;
        bool opened = false;
        for (int attempt = 0; attempt <= kRoomAttempts && path.empty(); ++attempt) {
            if (attempt > 0 && !opened && b.open_room(reached, attempt) == 0)
                break;  // room on demand, as in route_ring()
            const std::vector<char> block = b.blocked();
            const auto cost = b.cost_near(block, nullptr, kAdjacency);
            const int u = spots[k].u;
            const auto [p, n] = neighbours_on(b.curves_[spots[k].curve], u);
            const auto sec = sectors(b.s_, u, p, n);
            path = b.sector_path(u, sec[0], u, sec[1], block, cost, nullptr, &reached);
            if (path.empty()) opened = b.open_route(u, sec[0], u, sec[1], block, cost) > 0;
        }
        const int u = spots[k].u;
        QC_CHECK(!path.empty(), "no cycle S crosses b at vertex " + std::to_string(u) + " alone");
        Cycle s{u};
        s.insert(s.end(), path.begin(), path.end());
        ids.push_back(b.add_curve(s));
    }
    return ids;
}

}  // namespace quadcage::layout::detail
