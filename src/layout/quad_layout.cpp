#include "quadcage/layout/quad_layout.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <thread>

#include "detail/curves.h"
#include "detail/embedding.h"
#include "detail/patches.h"
#include "detail/relax.h"
#include "detail/stages.h"
#include "detail/surface.h"
#include "detail/unrefine.h"
#include "quadcage/core/errors.h"
#include "quadcage/core/validate.h"

namespace quadcage::layout {
namespace {

using detail::Builder;
using detail::index_in;
using detail::kInf;
using detail::neighbours_on;
using detail::Network;
using detail::OverBudget;
using detail::PathResult;
using detail::PathSearch;
using detail::Say;
using detail::sectors;
using detail::Surface;

// Removes hairpins from a layout curve: where the curve comes back next to itself (p_i adjacent to
// p_j, j > i + 1) around a small disk that holds nothing else (no vertex of another curve in
// `dirty`, no corner), the detour is replaced by the edge p_i p_j. Shortest paths that must enter
// a corner's sector from one side make such detours; left in place, the one-vertex-wide sliver
// between its branches squeezes the patch map below rounding. Returns the number of shortcuts.
int remove_hairpins(const Surface& s, Cycle& c, bool closed, const std::vector<char>& dirty,
                    const std::vector<char>& corner) {
    int shortcuts = 0;
    const int nt = s.num_half_edges() / 3;
    std::vector<int> pos(s.num_vertices(), -1);
    std::vector<int> seen(nt, -1);
    int stamp = 0;
    for (bool changed = true; changed;) {
        changed = false;
        std::fill(pos.begin(), pos.end(), -1);
        for (size_t i = 0; i < c.size(); ++i) pos[c[i]] = static_cast<int>(i);
        const int n = static_cast<int>(c.size());
        for (int i = 0; i + 2 < n && !changed; ++i) {
            // Shortcuts from p_i: an edge to a later p_j, or two edges through a free vertex m.
            std::vector<std::pair<int, int>> options;  // (j, m or -1)
            for (int w : s.ring(c[i])) {
                if (pos[w] > i + 1)
                    options.push_back({pos[w], -1});
                else if (pos[w] < 0 && !dirty[w] && !corner[w])
                    for (int u : s.ring(w))
                        if (pos[u] > i + 2) options.push_back({pos[u], w});
            }
            std::sort(options.begin(), options.end(), [](const auto& x, const auto& y) {
                return x.first != y.first ? x.first > y.first : x.second < y.second;  // longest detour first
            });
            for (const auto& [j, m] : options) {
                if (closed && i == 0 && j == n - 1) continue;
                bool skips_corner = false;
                for (int k = i + 1; k < j && !skips_corner; ++k) skips_corner = corner[c[k]];
                if (skips_corner) continue;
                // The loop p_i .. p_j (m) p_i; flood each side without crossing it.
                std::vector<std::uint64_t> loop_edges;
                for (int k = i; k < j; ++k) loop_edges.push_back(detail::edge_key(c[k], c[k + 1]));
                if (m < 0)
                    loop_edges.push_back(detail::edge_key(c[j], c[i]));
                else {
                    loop_edges.push_back(detail::edge_key(c[j], m));
                    loop_edges.push_back(detail::edge_key(m, c[i]));
                }
                std::sort(loop_edges.begin(), loop_edges.end());
                auto on_loop = [&](int h) {
                    return std::binary_search(loop_edges.begin(), loop_edges.end(),
                                              detail::edge_key(s.from(h), s.to(h)));
                };
                const size_t limit = 64 + 16 * static_cast<size_t>(j - i) * static_cast<size_t>(j - i);
                const int h0 = s.find_half_edge(c[i], c[i + 1]);
                bool clean_side = false;
                for (int side = 0; side < 2 && !clean_side; ++side) {
                    ++stamp;
                    std::vector<int> queue{(side == 0 ? h0 : s.twin(h0)) / 3};
                    seen[queue[0]] = stamp;
                    bool clean = true;
                    for (size_t q = 0; q < queue.size() && clean; ++q) {
                        if (queue.size() > limit) clean = false;
                        const int t = queue[q];
                        for (int k = 0; k < 3 && clean; ++k) {
                            const int v = s.mesh().triangles[t][k];
                            if ((pos[v] >= i && pos[v] <= j) || v == m) continue;  // on the loop itself
                            if (dirty[v] || corner[v] || pos[v] >= 0) clean = false;
                        }
                        for (int k = 0; k < 3 && clean; ++k) {
                            const int h = 3 * t + k;
                            if (on_loop(h)) continue;
                            const int o = s.twin(h) / 3;
                            if (seen[o] != stamp) {
                                seen[o] = stamp;
                                queue.push_back(o);
                            }
                        }
                    }
                    clean_side = clean;
                }
                if (!clean_side) continue;
                c.erase(c.begin() + i + 1, c.begin() + j);
                if (m >= 0) c.insert(c.begin() + i + 1, m);
                ++shortcuts;
                changed = true;
                break;
            }
        }
    }
    return shortcuts;
}
}  // namespace

std::string QuadLayoutOptions::validate() const {
    if (relax_sweeps < 0) return "relax_sweeps must be >= 0, got " + std::to_string(relax_sweeps);
    if (relax_corner_sweeps < 0)
        return "relax_corner_sweeps must be >= 0, got " + std::to_string(relax_corner_sweeps);
    if (edge_embedding_iterations < 0)
        return "edge_embedding_iterations must be >= 0, got " + std::to_string(edge_embedding_iterations);
    if (edge_embedding_max_vertices < 0)
        return "edge_embedding_max_vertices must be >= 0, got " + std::to_string(edge_embedding_max_vertices);
    if (embedding_iterations < 0)
        return "embedding_iterations must be >= 0, got " + std::to_string(embedding_iterations);
    if (embedding_cone_sweeps < 0)
        return "embedding_cone_sweeps must be >= 0, got " + std::to_string(embedding_cone_sweeps);
    if (!(embedding_area_weight >= 0) || !std::isfinite(embedding_area_weight))
        return "embedding_area_weight must be finite and >= 0";
    if (!(embedding_conformal_weight >= 0) || !std::isfinite(embedding_conformal_weight))
        return "embedding_conformal_weight must be finite and >= 0";
    return cycles.validate();
}

long long vertices_added_bound(int input_vertices, int corners) {
    return static_cast<long long>(input_vertices) / 4 + 200LL * corners;
}

namespace {

// The orthogonal system of a mesh and the mesh it lies on (the input, refined if coarse).
struct Cycles {
    OrthogonalSystem system;
    OrthogonalSystemOptions options;  // with the progress callback
    double seconds = 0;
};

Cycles build_cycles(const Mesh& input, const QuadLayoutOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    Cycles c;
    c.options = options.cycles;
    c.options.progress = options.progress;
    // Validates the input (throws InvalidInput as build_orthogonal_system() would).
    const ValidationReport report = validate(input);
    if (!report.quaddable() || report.components.size() != 1)
        throw InvalidInput(
            "build_quad_layout needs one closed, manifold, orientable component: " +
            (report.components.size() > 1
                 ? std::string("the mesh has ") + std::to_string(report.components.size()) + " components"
                 : report.error_summary()));
    // Coarse meshes get room first (1-to-4 splits: input vertices stay, in order; new ones at edge
    // midpoints): every handle needs its 2 loops, 4 S-cycles and their arcs to pass one another.
    // A split adds about 3 vertices per vertex, which on a mesh just under the threshold exceeds
    // vertices_added_bound() (eight.off: 766 vertices, 2304 added, bound 1792). Splitting less
    // (only while the bound allows, or the longest edges only) met the bound there but left the
    // edge relaxation of a genus-3 plate worse balanced (patch area max/min 3.8 -> 4.9).
    const int genus = report.components[0].genus;
    Mesh mesh = input;
    bool refined = false;
    while (mesh.num_vertices() < 1000 + 200 * genus) mesh = subdivide_midpoint(mesh), refined = true;
    // Builds the cycles (none for a sphere); the input's report serves an unrefined mesh.
    c.system = refined ? build_orthogonal_system(mesh, c.options)
                       : detail::build_orthogonal_system_validated(mesh, c.options, report);
    c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return c;
}

// The layout over `cycles` with the S-cycles from the handle loops (falling back to Algorithm 1's
// where they cannot be placed; *from_handle_loops says which were used) or Algorithm 1's, before
// the embedding stage, with its quality measured. With max_vertices > 0 the layout curves may
// refine the surface up to that many vertices; past it the layout is abandoned (OverBudget).
QuadLayout build_variant(const Mesh& input, const Cycles& cycles, const QuadLayoutOptions& options,
                         bool handle_loops, long long max_vertices, const Say& say, bool* from_handle_loops) {
    auto clock = [start = std::chrono::steady_clock::now()]() {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    const OrthogonalSystemOptions& cycle_options = cycles.options;
    const OrthogonalSystem& system = cycles.system;
    const int g = system.genus;
    const double t_cycles = cycles.seconds;
    // The layout curves' routes depend on the path costs; a layout whose patch maps fold (a patch
    // squeezed below rounding) is rebuilt with stronger, then weaker repulsion before giving up.
    std::string failure;
    for (const double repulsion_scale : {1.0, 2.0, 0.5}) {
        QuadLayout out;
        out.input_vertices = input.num_vertices();
        out.genus = g;
        OrthogonalSystemOptions curve_options = cycle_options;
        curve_options.repulsion *= repulsion_scale;
        Builder b(system.mesh, curve_options);
        for (const Cycle& c : system.cycles) b.add_curve(c);
        std::vector<int> loops;
        b.max_vertices_ = max_vertices;
        if (handle_loops)
            for (const Cycle& c : system.handle_loops) loops.push_back(b.add_curve(c, true, false));
        try {
            Network net;
            if (g >= 2)
                net = network_of_handles_and_tshirts(b, g, loops, handle_loops, say);
            else if (g == 1)
                net = network_of_torus(b, say);
            else
                net = network_of_cube(b, say);
            *from_handle_loops = net.s_cycles_from_handle_loops;

            // Room for the patch maps: no mesh edge may join two points of one patch side without
            // being a layout edge (split below, once the layout edges are known; edges between two
            // different sides need no room). The orthogonal system is no obstacle any more.
            say("patches");
            std::vector<char> layout_curve(b.curves_.size(), 0);
            for (const auto& [id, cs] : net.closed) layout_curve[id] = 1;
            for (int id : net.arcs) layout_curve[id] = 1;
            for (size_t c = 0; c < b.curves_.size(); ++c) b.obstacle_[c] = layout_curve[c];
            {
                // Tighten: remove hairpins. An S-cycle must keep its single crossing with the orthogonal
                // system, so for S-cycles the system's vertices count as other curves too.
                std::vector<char> corner(b.s_.num_vertices(), 0), on_system(b.s_.num_vertices(), 0);
                for (int v : net.corners) corner[v] = 1;
                for (int i = 0; i < 2 * g; ++i)
                    for (int v : b.curves_[i]) on_system[v] = 1;
                for (size_t c = 0; c < b.curves_.size(); ++c) {
                    if (!layout_curve[c]) continue;
                    std::vector<char> dirty(b.s_.num_vertices(), 0);
                    for (size_t d = 0; d < b.curves_.size(); ++d)
                        if (d != c && layout_curve[d])
                            for (int v : b.curves_[d]) dirty[v] = 1;
                    const bool is_s = std::find(net.s_cycles.begin(), net.s_cycles.end(),
                                                static_cast<int>(c)) != net.s_cycles.end();
                    if (is_s || g == 1) {  // g = 1: the four curves include the system's two
                        std::vector<char> mine(b.s_.num_vertices(), 0);
                        for (int v : b.curves_[c]) mine[v] = 1;
                        for (size_t v = 0; v < dirty.size(); ++v)
                            dirty[v] = dirty[v] || (on_system[v] && !mine[v]);
                    }
                    remove_hairpins(b.s_, b.curves_[c], b.closed_[c], dirty, corner);
                }
            }
            // Layout edges: each closed curve cut at its two corners, then the arcs.
            auto edge_paths_of = [&](const Builder& bb, const Network& nn) {
                std::vector<std::vector<int>> paths;
                for (const auto& [id, cs] : nn.closed) {
                    Cycle c = bb.curves_[id];
                    const int i0 = index_in(c, cs[0]);
                    QC_CHECK(i0 >= 0 && index_in(c, cs[1]) >= 0, "a layout cycle lost its corners");
                    std::rotate(c.begin(), c.begin() + i0, c.end());
                    const int i1 = index_in(c, cs[1]);
                    paths.emplace_back(c.begin(), c.begin() + i1 + 1);
                    std::vector<int> rest(c.begin() + i1, c.end());
                    rest.push_back(c[0]);
                    paths.push_back(rest);
                }
                for (int id : nn.arcs) paths.push_back(bb.curves_[id]);
                return paths;
            };
            b.split_dividing_chords(edge_paths_of(b, net));
            // The cage, patches and maps of a network, verified; "" or what fails. Times the maps
            // and the check of the last call.
            double mapped_seconds = 0, checked_seconds = 0;
            auto finish = [&](const Builder& bb, const Network& nn, QuadLayout* L) {
                L->mesh = bb.s_.mesh();
                const double t0 = clock();
                const std::string problem = detail::extract_cage(bb.s_, nn.corners, edge_paths_of(bb, nn), L);
                if (!problem.empty()) return "the layout curves do not form a quad layout: " + problem;
                detail::parameterize_patches(L);
                const double t1 = clock();
                say("verifying");
                const std::string check = verify_quad_layout(*L);
                mapped_seconds = t1 - t0;
                checked_seconds = clock() - t1;
                return check.empty() ? std::string() : "the quad layout fails its own check: " + check;
            };
            std::vector<std::vector<int>> paths = edge_paths_of(b, net);
            bool finished = false;  // out holds the relaxed layout, built and verified
            bool measured = false;  // and out.quality is measured (the relaxed-or-plain choice did)
            std::vector<int> s_cycle_ids = net.s_cycles;
            if (options.relax_sweeps > 0) {
                // Relax: corners towards an even share of their patches' area, every layout edge to
                // the middle of its two patches. The relaxed edges become new curves (the
                // orthogonal system keeps the routes Algorithm 1 gave it; the S-cycles are the
                // relaxed closed curves from then on); chords they make are split as before. Should
                // the relaxed network fail any check below, the unrelaxed one is kept.
                say(options.relax_corner_sweeps > 0 ? "relaxing the layout corners and edges" : "relaxing the layout edges");
                detail::RelaxOptions ro;
                ro.sweeps = options.relax_sweeps;
                try {
                    Builder relaxed = b;
                    std::vector<std::vector<int>> moved = paths;
                    std::vector<int> corners = net.corners;
                    int moves = 0;
                    if (options.relax_corner_sweeps > 0) {
                        // Corners and edges in turn: a moved corner's new edges run straight
                        // through its star, the next edge pass centres them between their patches.
                        detail::RelaxOptions once = ro;
                        once.sweeps = 1;
                        for (int sweep = 0; sweep < ro.sweeps; ++sweep) {
                            if (sweep < options.relax_corner_sweeps)
                                moves += detail::relax_layout_corners(relaxed.s_, &corners, &moved, ro);
                            moves += detail::relax_layout_edges(relaxed.s_, &moved, once);
                        }
                    } else {
                        moves = detail::relax_layout_edges(relaxed.s_, &moved, ro);
                    }
                    if (moves > 0) {
                        Network rn;
                        rn.corners = corners;
                        auto moved_corner = [&](int v) {
                            return corners[std::find(net.corners.begin(), net.corners.end(), v) - net.corners.begin()];
                        };
                        for (auto& o : relaxed.obstacle_) o = 0;
                        size_t k = 0;
                        for (const auto& [id, cs] : net.closed) {
                            Cycle c = moved[k];
                            c.insert(c.end(), moved[k + 1].begin() + 1, moved[k + 1].end() - 1);
                            k += 2;
                            rn.closed.push_back({relaxed.add_curve(c, true, true), {moved_corner(cs[0]), moved_corner(cs[1])}});
                        }
                        for (size_t a = 0; a < net.arcs.size(); ++a)
                            rn.arcs.push_back(relaxed.add_curve(moved[k++], false, true));
                        relaxed.split_dividing_chords(edge_paths_of(relaxed, rn));
                        QuadLayout trial = out;
                        const std::string problem = finish(relaxed, rn, &trial);
                        // Relaxing pulls each edge to the middle of its two patches, which can
                        // undo a decomposition chosen for balance (a genus-1 body's halving
                        // second longitude went back round the handle: area max/min 13.5 -> 31.6,
                        // angle deviation 15.7 -> 31.5 deg). The unrelaxed layout is kept when it
                        // is better in both figures. Only the torus's decomposition is chosen so:
                        // elsewhere the unrelaxed layout was never kept, and mapping and verifying
                        // it cost botijo 0.3 s and skull 0.55 s (timed), igea under 1.3 s (the
                        // interval between the progress lines round it).
                        std::optional<Builder> plain_builder;
                        QuadLayout plain;
                        bool keep_plain = false;
                        if (problem.empty() && g == 1) {
                            plain_builder = b;
                            plain = out;
                            if (finish(*plain_builder, net, &plain).empty()) {
                                detail::measure_quality(&trial);
                                detail::measure_quality(&plain);
                                measured = true;
                                keep_plain = plain.quality.patch_area_max_over_min <
                                                 trial.quality.patch_area_max_over_min &&
                                             plain.quality.corner_angle_mean_deviation_deg <
                                                 trial.quality.corner_angle_mean_deviation_deg;
                            }
                        }
                        if (keep_plain) {
                            say("the relaxed layout is less balanced and has worse corner angles; keeping it "
                                "unrelaxed");
                            b = std::move(*plain_builder);
                            out = std::move(plain);
                            finished = true;
                        } else if (problem.empty()) {
                            // The S-cycles are now the relaxed closed curves (through the moved corners).
                            for (int& id : s_cycle_ids)
                                for (size_t i = 0; i < net.closed.size(); ++i)
                                    if (net.closed[i].first == id) {
                                        id = rn.closed[i].first;
                                        break;
                                    }
                            b = std::move(relaxed);
                            out = std::move(trial);
                            finished = true;
                        } else {
                            say("the relaxed layout edges fail a check (" + problem + "); keeping them unrelaxed");
                        }
                    }
                } catch (const InternalError& e) {
                    say(std::string("relaxing the layout edges failed (") + e.what() + "); keeping them unrelaxed");
                }
            }

            if (!finished)
                if (const std::string problem = finish(b, net, &out); !problem.empty()) throw InternalError(problem);
            for (int i = 0; i < 2 * g; ++i) out.orthogonal_system.push_back(b.curves_[i]);
            for (int id : s_cycle_ids) out.s_cycles.push_back(b.curves_[id]);
            const double t_quality = clock();
            if (!measured) detail::measure_quality(&out);
            const double t_end = clock();
            const double checked = checked_seconds + (t_end - t_quality);
            out.seconds = {t_cycles, t_end - mapped_seconds - checked, mapped_seconds, checked};
            return out;
        } catch (const OverBudget&) {
            throw;
        } catch (const InternalError& e) {
            failure = e.what();
            say(std::string("retrying the layout curves: ") + e.what());
        }
    }
    throw InternalError(failure);
}

// A layout built in a second thread (build_quad_layout's Algorithm 1 S-cycles), with what it said.
struct Speculation {
    struct Cancelled {};  // thrown at the next progress message once `cancel` is set
    explicit Speculation(long long max) : max_vertices(max) {}
    Speculation(const Speculation&) = delete;
    Speculation& operator=(const Speculation&) = delete;
    ~Speculation() { stop(); }
    // Asks the thread to stop and waits for it.
    void stop() {
        cancel.store(true);
        if (thread.joinable()) thread.join();
    }

    const long long max_vertices;  // the vertex budget it was built with
    std::thread thread;
    std::atomic<bool> cancel{false};
    std::vector<std::string> messages;  // its progress messages, prefixed, not yet said
    std::optional<QuadLayout> layout;
    std::exception_ptr error;  // what build_variant threw (nothing if it was cancelled)
};

// A layout's seconds after the orthogonal system (which both S-cycle constructions share).
double seconds_after_cycles(const QuadLayout::Seconds& s) {
    return s.curves + s.parameterization + s.verification;
}

}  // namespace

QuadLayout build_quad_layout(const Mesh& input, const QuadLayoutOptions& options) {
    if (const std::string e = options.validate(); !e.empty()) throw InvalidInput("quad layout options: " + e);
    const Say say = [&options](const std::string& m) {
        if (options.progress) options.progress(m);
    };
    const Cycles cycles = build_cycles(input, options);
    // Algorithm 1's layout for the comparison below depends only on the orthogonal system and the
    // bound, so it is built in a second thread while the handle loops' layout is built here. Its
    // progress messages are held back and said once it is known to be wanted (else it is stopped
    // at its next message and dropped), so the messages and the result are those of building the
    // two one after the other.
    const int g = cycles.system.genus;
    const auto after_cycles = std::chrono::steady_clock::now();
    auto since = [](std::chrono::steady_clock::time_point t) {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
    };
    std::unique_ptr<Speculation> other;
    if (options.s_cycles_from_handle_loops && options.s_cycles_compare && g >= 2) {
        const long long max_vertices =
            input.num_vertices() + vertices_added_bound(input.num_vertices(), 8 * g - 8);
        other = std::make_unique<Speculation>(max_vertices);
        Speculation* sp = other.get();
        other->thread = std::thread([sp, &input, &cycles, &options] {
            const Say held = [sp](const std::string& m) {
                if (sp->cancel.load()) throw Speculation::Cancelled{};
                sp->messages.push_back("Algorithm 1's S-cycles: " + m);
            };
            try {
                bool unused = false;
                sp->layout = build_variant(input, cycles, options, false, sp->max_vertices, held, &unused);
            } catch (const Speculation::Cancelled&) {
            } catch (...) {
                sp->error = std::current_exception();
            }
        });
    }
    bool from_handle_loops = false;
    QuadLayout out = [&] {
        try {
            return build_variant(input, cycles, options, options.s_cycles_from_handle_loops, 0, say,
                                 &from_handle_loops);
        } catch (...) {
            if (other) other->stop();
            throw;
        }
    }();
    const long long bound = vertices_added_bound(out.input_vertices, out.cage.num_corners());
    // The handle loops gave the S-cycles only where the second thread was started (genus >= 2 and
    // both options), and a verified layout has its 8g - 8 corners: the bound is the one it used.
    const bool compare = from_handle_loops && options.s_cycles_compare;
    const bool within_bound = out.mesh.num_vertices() - out.input_vertices <= bound;
    QC_CHECK(!compare || (other && other->max_vertices == out.input_vertices + bound),
             "quad layout: Algorithm 1's layout was not built with the handle loops' bound");
    if (other && !(compare && within_bound)) {
        const auto stopping = std::chrono::steady_clock::now();
        other->stop();  // not wanted
        other.reset();
        out.seconds.curves += since(stopping);  // waiting for it to stop: time of the layout curves
    }
    if (compare && !within_bound) {
        // Algorithm 1's stacked S-cycles refined more than the handle loops' on every mesh where
        // those passed the bound (boot 41k against 29k, input_wheel 290k against 24k), and were
        // abandoned only after 7 s of boot's layout.
        say("S-cycles: keeping the handle loops' (past the refinement bound already; Algorithm 1's not "
            "tried)");
    } else if (compare) {
        // Which S-cycles make the better layout depends on the shape. Level-3 fits (check_fit.py
        // Hausdorff), handle loops' against Algorithm 1's: a big body with 3 small handles
        // (generate handles -g 3) 1.5e-2 against 3.7e-3, 4 in a row 6.2e-3 against 4.7e-3, 3holes
        // 3.2e-3 against 2.6e-3; fertility 2.6e-3 against 2.9e-2, botijo 1.6e-2 against 2.0e-2.
        // Patch area max/min alone mispredicts botijo (17.8 against 7.0); together with the corner
        // angles (34.3 against 35.1 deg) it predicts all five, and eight and skull (fits within
        // 7%). So Algorithm 1's is kept only when it is better on both. It may refine no more than
        // the bound.
        other->thread.join();
        try {
            for (const std::string& m : other->messages) say(m);
            if (other->error) std::rethrow_exception(other->error);
            QuadLayout& alternative = *other->layout;
            const LayoutQuality &a = out.quality, &b = alternative.quality;
            const bool better = b.patch_area_max_over_min < a.patch_area_max_over_min &&
                                b.corner_angle_mean_deviation_deg < a.corner_angle_mean_deviation_deg;
            char line[300];
            std::snprintf(
                line, sizeof line,
                "S-cycles: patch area max/min %.3g and corner angle deviation %.1f deg from the handle "
                "loops, %.3g and %.1f deg from Algorithm 1; keeping %s",
                a.patch_area_max_over_min, a.corner_angle_mean_deviation_deg, b.patch_area_max_over_min,
                b.corner_angle_mean_deviation_deg, better ? "Algorithm 1's" : "the handle loops'");
            say(line);
            if (better) out = std::move(alternative);
        } catch (const InternalError& e) {
            say(std::string("S-cycles: keeping the handle loops' (Algorithm 1's: ") + e.what() + ")");
        }
        // Built side by side: the layout not kept adds the wall time past the kept one's, not its
        // own duration (time spent on the layout curves).
        out.seconds.curves += std::max(0.0, since(after_cycles) - seconds_after_cycles(out.seconds));
    }
    // The curve searches split edges for room (Builder::split_chords and its kin); the splits no
    // curve runs through once the layout is chosen are undone, and the patches where that happened
    // mapped again.
    auto undo_unused_refinement = [&](QuadLayout* L) {
        const auto start = std::chrono::steady_clock::now();
        QuadLayout lean;
        std::vector<char> changed;
        if (const int removed = detail::remove_unused_refinement(*L, &lean, &changed); removed > 0) {
            detail::parameterize_patches(&lean, &changed);
            if (const std::string problem = verify_quad_layout(lean); problem.empty()) {
                detail::measure_quality(&lean);
                say("refinement: " + std::to_string(removed) +
                    " vertices no layout curve runs through removed");
                lean.seconds = L->seconds;
                *L = std::move(lean);
            } else {
                say("refinement: keeping the vertices no layout curve runs through (without them: " +
                    problem + ")");
            }
        }
        L->seconds.parameterization += since(start);
    };
    bool embedded = false;
    const bool embed = options.smooth_edges && options.edge_embedding_iterations > 0;
    if (embed && out.mesh.num_vertices() > options.edge_embedding_max_vertices) {
        // Each Newton step factorises the whole map's Hessian: measured on one BLAS thread, 0.37 s
        // at 39k free vertices (botijo), 1.7 s at 158k, 8.4 s and 3.1 GiB at 648k (botijo split
        // twice).
        say("edge embedding: skipped: the layout mesh has " + std::to_string(out.mesh.num_vertices()) +
            " vertices, more than " + std::to_string(options.edge_embedding_max_vertices) +
            " (--edge-embedding-max-vertices); smoothing the edges instead");
    } else if (embed) {
        // Before the unused refinement is undone, as for smoothing below.
        say("embedding the layout edges in one map of the surface");
        const auto start = std::chrono::steady_clock::now();
        QuadLayout e;
        detail::EdgeEmbeddingReport r;
        std::string why_not;
        try {
            why_not = detail::embed_layout_edges(out, options.edge_embedding_iterations, &e, &r);
        } catch (const InternalError& error) {
            // The smoothing below still gives clean edges; a failure here is a bug to report, not
            // a reason to lose the layout.
            why_not = std::string("it failed: ") + error.what();
        }
        if (why_not.empty()) {
            char line[300];
            std::snprintf(line, sizeof line,
                          "edge embedding: %d Newton steps (%s) on %d vertices, energy %.4g -> %.4g; %.2f s",
                          r.iterations, r.stopped.c_str(), r.variables, r.initial_energy, r.final_energy,
                          r.seconds);
            say(line);
            detail::measure_quality(&e);
            e.seconds = out.seconds;
            e.edges_smoothed = true;
            undo_unused_refinement(&e);
            const long long added = e.mesh.num_vertices() - e.input_vertices;
            const double before = out.quality.patch_area_max_over_min,
                         after = e.quality.patch_area_max_over_min;
            if (added > bound) {
                why_not = "they add " + std::to_string(added) + " vertices, over the bound of " +
                          std::to_string(bound);
            } else if (!(after < before)) {
                std::snprintf(line, sizeof line, "patch area max/min %.3g, not below %.3g", after, before);
                why_not = line;
            } else {
                std::snprintf(
                    line, sizeof line,
                    "edge embedding: keeping the embedded edges: patch area max/min %.3g (was %.3g), "
                    "corner angle deviation %.1f deg (was %.1f)",
                    after, before, e.quality.corner_angle_mean_deviation_deg,
                    out.quality.corner_angle_mean_deviation_deg);
                say(line);
                out = std::move(e);
                embedded = true;
            }
        }
        if (!embedded) say("edge embedding: not kept (" + why_not + "); smoothing the edges instead");
        out.seconds.curves += since(start);
    }
    std::optional<QuadLayout> staircase;  // the layout before smoothing, while it may be wanted back
    if (options.smooth_edges && !embedded) {
        // Before the unused refinement is undone: the splits the old routes took are unused now.
        say("smoothing the layout edges");
        const auto start = std::chrono::steady_clock::now();
        QuadLayout smooth;
        detail::SmoothingReport r;
        if (const std::string problem = detail::smooth_layout_edges(out, &smooth, &r); !problem.empty()) {
            say("smoothing: keeping the edges along mesh edges (" + problem + ")");
        } else {
            detail::measure_quality(&smooth);
            char line[200];
            std::snprintf(
                line, sizeof line,
                "smoothing: the map made harmonic on %d vertices round the edges in %d steps; %.2f s",
                r.band_vertices, r.iterations, r.seconds);
            say(line);
            smooth.seconds = out.seconds;
            smooth.edges_smoothed = true;
            staircase = std::move(out);
            out = std::move(smooth);
        }
        out.seconds.curves += since(start);
    }
    undo_unused_refinement(&out);
    if (staircase && out.mesh.num_vertices() - out.input_vertices > bound) {
        // Each crossing of a mesh edge is a vertex: a plate's coarse, regular mesh (genus 11: 20330
        // added, bound 16137, against 9473 along mesh edges) can take the smoothed edges past the
        // bound.
        say("smoothing: keeping the edges along mesh edges (smoothed, they add " +
            std::to_string(out.mesh.num_vertices() - out.input_vertices) + " vertices, over the bound of " +
            std::to_string(bound) + ")");
        staircase->seconds = out.seconds;
        out = std::move(*staircase);
        undo_unused_refinement(&out);
    }
    if (options.embedding_iterations > 0) {
        const auto start = std::chrono::steady_clock::now();
        detail::EmbeddingOptions eo;
        eo.iterations = options.embedding_iterations;
        eo.area_weight = options.embedding_area_weight;
        eo.conformal_weight = options.embedding_conformal_weight;
        detail::embedding_stage(&out, eo, options.embedding_cone_sweeps, options.embedding_extract, say);
        detail::measure_quality(&out);
        out.seconds.curves += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    const long long added = out.mesh.num_vertices() - out.input_vertices;
    if (added > bound)
        say("refinement: " + std::to_string(added) + " vertices added, over the bound of " +
            std::to_string(bound) + " (a quarter of the input's plus 200 per corner)");
    return out;
}

}  // namespace quadcage::layout
