#include "quadcage/layout/orthogonal_system.h"

#include <algorithm>
#include <bitset>
#include <cmath>
#include <limits>
#include <functional>
#include <memory>
#include <numeric>
#include <set>
#include <thread>
#include <tuple>
#include <unordered_set>

#include "detail/curves.h"
#include "detail/surface.h"
#include "quadcage/core/errors.h"
#include "quadcage/core/validate.h"

namespace quadcage::layout {
namespace {

using detail::PathResult;
using detail::PathSearch;
using detail::Surface;
using detail::Builder;
using detail::edge_key;
using detail::neighbours_on;
using detail::sectors;
using detail::spread;
using Class = std::bitset<128>;  // Z2 homology class: one bit per tree-cotree generator
constexpr double kInf = std::numeric_limits<double>::infinity();

// Z2 homology masks from a tree-cotree split (Eppstein 2003): h(tree) = 0, h(leftover k) = bit k,
// cotree edges from the leaves up so that every face boundary sums to zero. A closed walk is
// null-homologous iff the XOR of h over its edges is zero.
std::vector<Class> homology_masks(const Surface& s, int* generators) {
    const int n = s.num_vertices(), nh = s.num_half_edges(), nt = nh / 3;
    std::vector<char> tree(nh, 0), cotree(nh, 0), seen(n, 0);
    std::vector<int> queue{0};
    seen[0] = 1;
    for (size_t i = 0; i < queue.size(); ++i)
        for (int h : s.out_half_edges(queue[i]))
            if (!seen[s.to(h)]) {
                seen[s.to(h)] = 1;
                tree[h] = tree[s.twin(h)] = 1;
                queue.push_back(s.to(h));
            }
    std::vector<int> faces{0}, parent_edge(nt, -1);
    std::vector<char> face_seen(nt, 0);
    face_seen[0] = 1;
    for (size_t i = 0; i < faces.size(); ++i)
        for (int k = 0; k < 3; ++k) {
            const int h = 3 * faces[i] + k;
            if (tree[h]) continue;
            const int g = s.twin(h) / 3;
            if (face_seen[g]) continue;
            face_seen[g] = 1;
            cotree[h] = cotree[s.twin(h)] = 1;
            parent_edge[g] = s.twin(h);
            faces.push_back(g);
        }
    std::vector<Class> mask(nh);
    int bit = 0;
    for (int h = 0; h < nh; ++h)
        if (!tree[h] && !cotree[h] && h < s.twin(h)) {
            QC_CHECK(bit < 128, "homology_masks: genus too large");
            mask[h].set(bit);
            mask[s.twin(h)].set(bit);
            ++bit;
        }
    for (size_t i = faces.size(); i-- > 1;) {
        const int f = faces[i], e = parent_edge[f];
        Class c;
        for (int k = 0; k < 3; ++k)
            if (3 * f + k != e) c ^= mask[3 * f + k];
        mask[e] = mask[s.twin(e)] = c;
    }
    *generators = bit;
    return mask;
}

// A Z2 subspace kept in reduced echelon form.
class Span {
public:
    bool contains(Class v) const { return reduce(v).none(); }
    void add(Class v) {
        v = reduce(v);
        if (v.none()) return;
        int p = 0;
        while (!v[p]) ++p;
        for (Class& b : basis_)
            if (b[p]) b ^= v;
        basis_.push_back(v);
        pivot_.push_back(p);
    }

private:
    Class reduce(Class v) const {
        for (size_t i = 0; i < basis_.size(); ++i)
            if (v[pivot_[i]]) v ^= basis_[i];
        return v;
    }
    std::vector<Class> basis_;
    std::vector<int> pivot_;
};

std::vector<int> farthest_point_samples(const Mesh& mesh, int k) {
    const int n = mesh.num_vertices();
    std::vector<int> picks{0};
    std::vector<double> d(n, kInf);
    while (static_cast<int>(picks.size()) < std::min(k, n)) {
        const Vec3& p = mesh.points[picks.back()];
        int far = 0;
        for (int v = 0; v < n; ++v) {
            d[v] = std::min(d[v], norm(mesh.points[v] - p));
            if (d[v] > d[far]) far = v;
        }
        if (d[far] <= 0) break;
        picks.push_back(far);
    }
    return picks;
}

// Homology class of the tree path from the search's source to every reached vertex (`reached`:
// the vertices the search settled). Only the reached vertices' entries of *H are written; `known`
// is all 0 on entry and left so.
void path_classes(const Surface& s, const PathResult& r, const std::vector<Class>& mask,
                  const std::vector<int>& reached, std::vector<Class>* H, std::vector<char>* known) {
    std::vector<int> stack;
    std::vector<Class>& cls = *H;
    std::vector<char>& kn = *known;
    for (int v : reached) {
        if (kn[v]) continue;
        int u = v;
        while (!kn[u] && r.parent_half_edge[u] >= 0) {
            stack.push_back(u);
            u = s.from(r.parent_half_edge[u]);
        }
        if (!kn[u]) cls[u] = Class();  // a source: class 0
        kn[u] = 1;
        while (!stack.empty()) {
            const int w = stack.back();
            stack.pop_back();
            cls[w] = cls[s.from(r.parent_half_edge[w])] ^ mask[r.parent_half_edge[w]];
            kn[w] = 1;
        }
    }
    for (int v : reached) kn[v] = 0;
}

// The loop closed by non-tree half-edge h in a shortest-path tree, trimmed at the lowest common
// ancestor so that it is simple.
Cycle loop_through(const Surface& s, const PathResult& r, int h) {
    std::vector<int> up_u = r.path_to(s, s.from(h));  // root ... u
    std::vector<int> up_v = r.path_to(s, s.to(h));    // root ... v
    size_t common = 0;
    while (common < up_u.size() && common < up_v.size() && up_u[common] == up_v[common]) ++common;
    QC_CHECK(common >= 1, "loop_through: paths do not share the root");
    Cycle c(up_u.begin() + static_cast<long>(common) - 1, up_u.end());  // lca ... u
    for (size_t i = up_v.size(); i-- > common;) c.push_back(up_v[i]);  // v ... child of lca
    return c;
}


// Step 1: a1..ag, disjoint, with independent homology classes, each the shortest found.
std::vector<Cycle> independent_loops(Builder& b, int genus, std::vector<double>* lengths) {
    int generators = 0;
    const std::vector<Class> mask = homology_masks(b.s_, &generators);
    QC_CHECK(generators == 2 * genus, "tree-cotree found " + std::to_string(generators) + " generators for genus " +
                                          std::to_string(genus));
    const std::vector<int> roots = farthest_point_samples(b.s_.mesh(), b.o_.root_samples);
    Span span;
    std::vector<Cycle> loops;
    std::vector<char> block(b.s_.num_vertices(), 0);
    const int n = b.s_.num_vertices();
    std::vector<Class> H(n);
    std::vector<char> known(n, 0);
    std::vector<int> reached;
    for (int i = 0; i < genus; ++i) {
        double best = kInf;
        int best_h = -1;
        PathResult best_r;  // the search from best_root (its tree holds the loop)
        for (int root : roots) {
            if (block[root]) continue;
            PathSearch q;
            q.sources = {{root, 0.0}};
            q.blocked = &block;
            q.max_distance = 0.5 * best;  // a shorter loop through the root stays within this radius
            PathResult r = detail::dijkstra(b.s_, q);
            reached.clear();
            for (int v = 0; v < n; ++v)
                if (r.distance[v] != kInf) reached.push_back(v);
            path_classes(b.s_, r, mask, reached, &H, &known);
            // The non-tree edges u-v (u < v) between reached vertices: the least (len, h) that closes
            // a loop shorter than the best so far outside the span (the first such h in index order).
            int root_h = -1;
            for (int u : reached) {
                const int h0 = b.s_.out_half_edge(u);
                int h = h0;
                do {
                    const int v = b.s_.to(h);
                    if (u < v && r.distance[v] != kInf && r.parent_half_edge[v] != h &&
                        r.parent_half_edge[u] != b.s_.twin(h)) {
                        const double len = r.distance[u] + r.distance[v] + b.s_.length(h);
                        if ((len < best || (len == best && root_h >= 0 && h < root_h)) &&
                            !span.contains(H[u] ^ H[v] ^ mask[h])) {
                            best = len;
                            root_h = h;
                        }
                    }
                    h = b.s_.rotate(h);
                } while (h != h0);
            }
            if (root_h >= 0) {
                best_h = root_h;
                best_r = std::move(r);
            }
        }
        QC_CHECK(best_h >= 0, "no non-separating loop found for handle " + std::to_string(i + 1));
        // best_r settled every vertex of the loop (and their tree paths) as a search without the
        // radius would: the same tree there.
        const PathResult& r = best_r;
        const Cycle loop = loop_through(b.s_, r, best_h);
        Class c;
        for (size_t k = 0; k < loop.size(); ++k)
            c ^= mask[b.s_.find_half_edge(loop[k], loop[(k + 1) % loop.size()])];
        QC_CHECK(!span.contains(c), "trimmed loop lost its homology class");
        span.add(c);
        for (int v : loop) block[v] = 1;
        lengths->push_back(cycle_length(b.s_.mesh(), loop));
        loops.push_back(loop);
    }
    return loops;
}

// Step 2: order the loops along a short Hamiltonian path of loop-to-loop distances, starting
// with the end whose loop is shorter (it stays in the system as a1).
std::vector<int> chain_order(const Builder& b, const std::vector<Cycle>& loops) {
    const int g = static_cast<int>(loops.size());
    std::vector<std::vector<double>> D(g, std::vector<double>(g, 0));
    for (int i = 0; i < g; ++i) {
        PathSearch q;
        for (int v : loops[i]) q.sources.push_back({v, 0.0});
        const PathResult r = detail::dijkstra(b.s_, q);
        for (int j = 0; j < g; ++j) {
            double d = kInf;
            for (int v : loops[j]) d = std::min(d, r.distance[v]);
            D[i][j] = d;
        }
    }
    for (int i = 0; i < g; ++i)
        for (int j = 0; j < i; ++j) D[i][j] = D[j][i] = std::min(D[i][j], D[j][i]);
    std::vector<int> order;
    if (g <= 14) {  // exact: DP over subsets
        const int full = 1 << g;
        std::vector<double> cost(static_cast<size_t>(full) * g, kInf);
        std::vector<int> prev(static_cast<size_t>(full) * g, -1);
        for (int i = 0; i < g; ++i) cost[(1u << i) * g + i] = 0;
        for (int m = 1; m < full; ++m)
            for (int i = 0; i < g; ++i) {
                const double c = cost[static_cast<size_t>(m) * g + i];
                if (c == kInf) continue;
                for (int j = 0; j < g; ++j) {
                    if (m & (1 << j)) continue;
                    const size_t k = static_cast<size_t>(m | (1 << j)) * g + j;
                    if (c + D[i][j] < cost[k]) {
                        cost[k] = c + D[i][j];
                        prev[k] = i;
                    }
                }
            }
        int end = 0;
        for (int i = 1; i < g; ++i)
            if (cost[static_cast<size_t>(full - 1) * g + i] < cost[static_cast<size_t>(full - 1) * g + end]) end = i;
        for (int m = full - 1, i = end; i >= 0;) {
            order.push_back(i);
            const int p = prev[static_cast<size_t>(m) * g + i];
            m &= ~(1 << i);
            i = p;
        }
    } else {  // greedy nearest neighbour from every start, keep the shortest
        double best = kInf;
        for (int s = 0; s < g; ++s) {
            std::vector<int> o{s};
            std::vector<char> used(g, 0);
            used[s] = 1;
            double total = 0;
            while (static_cast<int>(o.size()) < g) {
                int nxt = -1;
                for (int j = 0; j < g; ++j)
                    if (!used[j] && (nxt < 0 || D[o.back()][j] < D[o.back()][nxt])) nxt = j;
                total += D[o.back()][nxt];
                used[nxt] = 1;
                o.push_back(nxt);
            }
            if (total < best) {
                best = total;
                order = o;
            }
        }
    }
    const Mesh& m = b.s_.mesh();
    if (cycle_length(m, loops[order.back()]) < cycle_length(m, loops[order.front()]))
        std::reverse(order.begin(), order.end());
    return order;
}


// Steps 3 and 4 on a copy of the builder: b_i crossing a_i once, c_i joining b_i and b(i+1); the
// loops enter in chain `order` (order[0] stays as a1).
struct Chain {
    std::vector<Cycle> cycles;
    std::vector<Cycle> loops;  // a1..ag in chain order, after the chain's refinement
    Mesh mesh;
    int splits = 0;
    double length = 0;
};

Chain build_chain(Builder b, const std::vector<Cycle>& loops, const std::vector<int>& order,
                  const std::function<void(const std::string&)>& say) {
    // Curves: the g loops in chain order first, then the b's and c's as they come.
    for (int i : order) {
        b.add_curve(loops[i]);
    }
    const int g = static_cast<int>(order.size());
    std::vector<int> b_index(g), c_index;

    // Step 3: b_i crosses a_i once and avoids every other curve so far.
    for (int i = 0; i < g; ++i) {
        say("crossing curve b" + std::to_string(i + 1) + " of " + std::to_string(g));
        std::fill(b.obstacle_.begin(), b.obstacle_.end(), 1);
        b.split_chords();
        const std::vector<char> block = b.blocked();
        const auto cost = detail::memoised(b.cost_near(block));  // crossing_candidates searches share it
        const Cycle& a = b.curves_[i];
        double best = kInf;
        Cycle best_b;
        for (int x : spread(a, b.o_.crossing_candidates, [](int) { return false; })) {
            const auto [p, n] = neighbours_on(a, x);
            const auto sec = sectors(b.s_, x, p, n);
            double total = kInf;
            // Bounded by the best so far: a search that passes it could only find a longer path.
            std::vector<int> path = b.sector_path(x, sec[0], x, sec[1], block, cost, &total, nullptr, best);
            if (path.empty() || total >= best) continue;
            best = total;
            best_b = {x};
            best_b.insert(best_b.end(), path.begin(), path.end());
        }
        QC_CHECK(!best_b.empty(), "no curve crosses handle loop " + std::to_string(i + 1) + " once");
        b_index[i] = static_cast<int>(b.curves_.size());
        b.add_curve(best_b);
    }

    // Step 4: c_i crosses b_i and b(i+1) once each, avoiding a1, every b and the earlier c's.
    auto final_count = [&](int v) {
        int k = 0;
        for (size_t c = 0; c < b.curves_.size(); ++c)
            if ((c == 0 || c >= static_cast<size_t>(g)) &&
                std::find(b.curves_[c].begin(), b.curves_[c].end(), v) != b.curves_[c].end())
                ++k;
        return k;
    };
    for (int i = 0; i + 1 < g; ++i) {
        say("joining curve c" + std::to_string(i + 1) + " of " + std::to_string(g - 1));
        for (size_t c = 0; c < b.curves_.size(); ++c) b.obstacle_[c] = c == 0 || c >= static_cast<size_t>(g);
        b.split_chords();
        std::vector<char> block = b.blocked();
        auto cost = detail::memoised(b.cost_near(block));  // two searches per crossing candidate share it
        const Cycle &bi = b.curves_[b_index[i]], &bj = b.curves_[b_index[i + 1]];
        const auto skip = [&](int v) { return final_count(v) != 1; };
        const std::vector<int> xs = spread(bi, b.o_.crossing_candidates, skip);
        const std::vector<int> ys = spread(bj, b.o_.crossing_candidates, skip);
        QC_CHECK(!xs.empty() && !ys.empty(), "no free crossing vertex on b" + std::to_string(i + 1));
        // Distances from each (x, side) to each (y, side): one search per (x, side).
        struct Option {
            double cost;
            int x, s, y, t;
        };
        std::vector<Option> options_found;
        std::vector<std::vector<std::array<double, 2>>> D(xs.size() * 2,
                                                          std::vector<std::array<double, 2>>(ys.size(), {kInf, kInf}));
        std::vector<int> y_ring;  // the searches may stop once these are settled
        for (int y : ys)
            for (int w : b.s_.ring(y))
                if (!block[w]) y_ring.push_back(w);
        for (size_t xi = 0; xi < xs.size(); ++xi) {
            const auto [p, n] = neighbours_on(bi, xs[xi]);
            const auto sec = sectors(b.s_, xs[xi], p, n);
            for (int s = 0; s < 2; ++s) {
                PathSearch q;
                q.blocked = &block;
                q.cost = cost;
                for (int w : sec[s])
                    if (!block[w]) q.sources.push_back({w, b.edge_cost(cost, xs[xi], w)});
                if (q.sources.empty()) continue;
                q.settle = y_ring;
                const PathResult r = detail::dijkstra(b.s_, q);
                for (size_t yi = 0; yi < ys.size(); ++yi) {
                    const auto [py, ny] = neighbours_on(bj, ys[yi]);
                    const auto secy = sectors(b.s_, ys[yi], py, ny);
                    for (int t = 0; t < 2; ++t)
                        for (int w : secy[t])
                            if (!block[w] && r.distance[w] < kInf)
                                D[xi * 2 + s][yi][t] =
                                    std::min(D[xi * 2 + s][yi][t], r.distance[w] + b.edge_cost(cost, w, ys[yi]));
                }
            }
        }
        for (size_t xi = 0; xi < xs.size(); ++xi)
            for (size_t yi = 0; yi < ys.size(); ++yi)
                for (int s = 0; s < 2; ++s)
                    for (int t = 0; t < 2; ++t) {
                        const double c = D[xi * 2 + s][yi][t] + D[xi * 2 + 1 - s][yi][1 - t];
                        if (c < kInf)
                            options_found.push_back({c, static_cast<int>(xi), s, static_cast<int>(yi), t});
                    }
        std::sort(options_found.begin(), options_found.end(), [](const Option& l, const Option& r) {
            return l.cost != r.cost ? l.cost < r.cost : std::tie(l.x, l.s, l.y, l.t) < std::tie(r.x, r.s, r.y, r.t);
        });
        Cycle ci;
        for (size_t k = 0; k < options_found.size() && k < 64 && ci.empty(); ++k) {
            const Option& op = options_found[k];
            const int x = xs[op.x], y = ys[op.y];
            auto sec_of = [&](const Cycle& curve, int v) {
                const auto [p, n] = neighbours_on(curve, v);
                return sectors(b.s_, v, p, n);
            };
            if (k > 0) {  // an earlier try split chords: the mesh changed
                block = b.blocked();
                cost = b.cost_near(block);
            }
            const std::vector<int> first =
                b.sector_path(x, sec_of(bi, x)[op.s], y, sec_of(bj, y)[op.t], block, cost, nullptr);
            if (first.empty()) continue;
            // Cut along the first half before routing the second, so that the two cannot touch.
            Cycle half{x};
            half.insert(half.end(), first.begin(), first.end());
            half.push_back(y);
            b.split_chords({half});
            std::vector<char> block2 = b.blocked();
            for (int v : first) block2[v] = 1;
            const auto cost2 = b.cost_near(block2);
            const std::vector<int> second =
                b.sector_path(y, sec_of(bj, y)[1 - op.t], x, sec_of(bi, x)[1 - op.s], block2, cost2, nullptr);
            if (second.empty()) continue;
            ci = half;
            ci.insert(ci.end(), second.begin(), second.end());
        }
        QC_CHECK(!ci.empty(), "no curve joins b" + std::to_string(i + 1) + " and b" + std::to_string(i + 2));
        c_index.push_back(static_cast<int>(b.curves_.size()));
        b.add_curve(ci);
    }

    Chain out;
    out.cycles.push_back(b.curves_[0]);
    for (int i = 0; i < g; ++i) {
        out.cycles.push_back(b.curves_[b_index[i]]);
        if (i + 1 < g) out.cycles.push_back(b.curves_[c_index[i]]);
    }
    for (int i = 0; i < g; ++i) out.loops.push_back(b.curves_[i]);
    out.splits = b.splits_;
    out.mesh = b.s_.mesh();
    for (const Cycle& c : out.cycles) out.length += cycle_length(out.mesh, c);
    return out;
}

}  // namespace

std::string OrthogonalSystemOptions::validate() const {
    if (root_samples < 1) return "root_samples must be >= 1";
    if (crossing_candidates < 1) return "crossing_candidates must be >= 1";
    if (repulsion < 0) return "repulsion must be >= 0";
    if (!(repulsion_radius > 0)) return "repulsion_radius must be > 0";
    if (max_genus < 1 || max_genus > 64) return "max_genus must be in 1..64";
    return "";
}

double cycle_length(const Mesh& mesh, const Cycle& c) {
    double len = 0;
    for (size_t i = 0; i < c.size(); ++i) len += norm(mesh.points[c[(i + 1) % c.size()]] - mesh.points[c[i]]);
    return len;
}

OrthogonalSystem build_orthogonal_system(const Mesh& mesh, const OrthogonalSystemOptions& options) {
    return detail::build_orthogonal_system_validated(mesh, options, validate(mesh));
}

namespace detail {

OrthogonalSystem build_orthogonal_system_validated(const Mesh& mesh, const OrthogonalSystemOptions& options,
                                                   const ValidationReport& report) {
    if (const std::string e = options.validate(); !e.empty())
        throw InvalidInput("orthogonal system options: " + e);
    if (!report.quaddable() || report.components.size() != 1)
        throw InvalidInput("build_orthogonal_system needs one closed, manifold, orientable component: " +
                           (report.components.size() > 1 ? std::string("the mesh has ") +
                                                               std::to_string(report.components.size()) + " components"
                                                         : report.error_summary()));
    if (!report.components[0].consistently_oriented)
        throw InvalidInput("build_orthogonal_system: triangles are not consistently oriented (call orient_outward)");
    if (report.unused_vertices > 0)
        throw InvalidInput("build_orthogonal_system: the mesh has unused vertices (call remove_unused_vertices)");
    const int g = report.components[0].genus;
    if (g > options.max_genus)
        throw InvalidInput("genus " + std::to_string(g) + " exceeds the supported maximum " +
                           std::to_string(options.max_genus));

    OrthogonalSystem out;
    out.input_vertices = mesh.num_vertices();
    out.genus = g;
    if (g == 0) {
        out.mesh = mesh;
        return out;
    }
    auto say = [&options](const std::string& m) {
        if (options.progress) options.progress(m);
    };
    Builder b(mesh, options);
    say("handle loops (genus " + std::to_string(g) + ")");
    const std::vector<Cycle> loops = independent_loops(b, g, &out.handle_lengths);
    std::sort(out.handle_lengths.begin(), out.handle_lengths.end());
    const std::vector<int> order = chain_order(b, loops);
    // The chain's direction changes the b's and c's a lot (a c must get around every curve built
    // before it): build both directions at once and keep the shorter system.
    std::vector<int> reversed(order.rbegin(), order.rend());
    const std::function<void(const std::string&)> quiet = [](const std::string&) {};
    Chain chains[2];
    std::string errors[2];
    auto run = [&](int k) {
        try {
            chains[k] = build_chain(b, loops, k == 0 ? order : reversed, k == 0 ? say : quiet);
        } catch (const std::exception& e) {
            errors[k] = e.what();
        }
    };
    std::thread other(run, 1);
    run(0);
    other.join();
    if (!errors[0].empty() && !errors[1].empty()) throw InternalError(errors[0]);
    const int pick = !errors[0].empty() ? 1
                     : !errors[1].empty() ? 0
                     : (chains[1].length < chains[0].length ? 1 : 0);
    out.cycles = std::move(chains[pick].cycles);
    out.handle_loops = std::move(chains[pick].loops);
    out.mesh = std::move(chains[pick].mesh);
    out.refinement_splits = chains[pick].splits;
    say("verifying");
    const std::string problem = verify_orthogonal_system(out.mesh, out.cycles);
    QC_CHECK(problem.empty(), "the orthogonal system fails its own check: " + problem);
    return out;
}

}  // namespace detail

std::string verify_orthogonal_system(const Mesh& mesh, const std::vector<Cycle>& cycles) {
    const ValidationReport r = validate(mesh);
    if (r.components.size() != 1 || !r.components[0].quaddable()) return "the mesh is not one closed orientable surface";
    const int g = r.components[0].genus;
    if (g == 0 && cycles.empty()) return "";  // a sphere: the empty system (no cut needed)
    if (static_cast<int>(cycles.size()) != 2 * g)
        return std::to_string(cycles.size()) + " cycles for genus " + std::to_string(g) + " (want 2g)";
    const Surface s(mesh);
    const int n = s.num_vertices();
    std::vector<std::unordered_set<std::uint64_t>> edges(cycles.size());
    for (size_t i = 0; i < cycles.size(); ++i) {
        const Cycle& c = cycles[i];
        if (c.size() < 3) return "cycle " + std::to_string(i) + " has fewer than 3 vertices";
        std::set<int> distinct(c.begin(), c.end());
        if (distinct.size() != c.size()) return "cycle " + std::to_string(i) + " is not simple";
        for (size_t k = 0; k < c.size(); ++k) {
            const int a = c[k], b = c[(k + 1) % c.size()];
            if (a < 0 || a >= n || b < 0 || b >= n || s.find_half_edge(a, b) < 0)
                return "cycle " + std::to_string(i) + " leaves the mesh edges at position " + std::to_string(k);
            edges[i].insert(edge_key(a, b));
        }
    }
    for (size_t i = 0; i < cycles.size(); ++i)
        for (size_t j = i + 1; j < cycles.size(); ++j) {
            std::vector<int> common;
            std::set<int> si(cycles[i].begin(), cycles[i].end());
            for (int v : cycles[j])
                if (si.count(v)) common.push_back(v);
            if (j == i + 1) {
                if (common.size() != 1)
                    return "cycles " + std::to_string(i) + " and " + std::to_string(j) + " share " +
                           std::to_string(common.size()) + " vertices (want 1)";
                const int x = common[0];
                const auto [p, q] = neighbours_on(cycles[i], x);
                const auto sec = sectors(s, x, p, q);
                const auto [p2, q2] = neighbours_on(cycles[j], x);
                auto side = [&](int v) {
                    return std::find(sec[0].begin(), sec[0].end(), v) != sec[0].end()   ? 0
                           : std::find(sec[1].begin(), sec[1].end(), v) != sec[1].end() ? 1
                                                                                         : -1;
                };
                const int s1 = side(p2), s2 = side(q2);
                if (s1 < 0 || s2 < 0 || s1 == s2)
                    return "cycles " + std::to_string(i) + " and " + std::to_string(j) + " touch at vertex " +
                           std::to_string(x) + " without crossing";
            } else if (!common.empty()) {
                return "cycles " + std::to_string(i) + " and " + std::to_string(j) + " are not consecutive but share " +
                       std::to_string(common.size()) + " vertices";
            }
        }
    // Face components of the surface cut along a set of edges.
    auto face_components = [&](const std::unordered_set<std::uint64_t>& cut) {
        const int nt = mesh.num_triangles();
        std::vector<int> comp(nt, -1);
        int count = 0;
        for (int f0 = 0; f0 < nt; ++f0) {
            if (comp[f0] >= 0) continue;
            std::vector<int> stack{f0};
            comp[f0] = count;
            while (!stack.empty()) {
                const int f = stack.back();
                stack.pop_back();
                for (int k = 0; k < 3; ++k) {
                    const int h = 3 * f + k;
                    if (cut.count(edge_key(s.from(h), s.to(h)))) continue;
                    const int o = s.twin(h) / 3;
                    if (comp[o] < 0) {
                        comp[o] = count;
                        stack.push_back(o);
                    }
                }
            }
            ++count;
        }
        return count;
    };
    for (size_t i = 0; i < cycles.size(); ++i)
        if (face_components(edges[i]) != 1) return "cycle " + std::to_string(i) + " separates the surface";
    std::unordered_set<std::uint64_t> all;
    std::set<int> verts;
    for (size_t i = 0; i < cycles.size(); ++i) {
        all.insert(edges[i].begin(), edges[i].end());
        verts.insert(cycles[i].begin(), cycles[i].end());
    }
    if (face_components(all) != 1) return "the cycles together separate the surface";
    const long chi = static_cast<long>(verts.size()) - static_cast<long>(all.size());
    if (chi != 1 - 2 * g)
        return "the cycles do not form a cutting graph: chi(G) = " + std::to_string(chi) + ", want " +
               std::to_string(1 - 2 * g);
    return "";
}

}  // namespace quadcage::layout
