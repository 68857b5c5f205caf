// build_quad_layout(): the pipeline of design.md §1 from the mesh to a verified minimal quad layout,
// each stage in its own file (named at its call below); and the options' check and the bound on
// the refinement.

#include "quadcage/layout/quad_layout.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "detail/embedding.h"
#include "detail/patches.h"
#include "detail/retrace.h"
#include "detail/stages.h"
#include "detail/surface.h"
#include "quadcage/core/errors.h"
#include "quadcage/core/openmesh_bridge.h"
#include "quadcage/core/validate.h"

namespace quadcage::layout {

std::string QuadLayoutOptions::validate() const {
    if (relax_sweeps < 0) return "relax_sweeps must be >= 0, got " + std::to_string(relax_sweeps);
    if (relax_corner_sweeps < 0)
        return "relax_corner_sweeps must be >= 0, got " + std::to_string(relax_corner_sweeps);
    if (edge_embedding_iterations < 0)
        return "edge_embedding_iterations must be >= 0, got " + std::to_string(edge_embedding_iterations);
    if (proxy_vertices < 0) return "proxy_vertices must be >= 0, got " + std::to_string(proxy_vertices);
    if (proxy_above < 0) return "proxy_above must be >= 0, got " + std::to_string(proxy_above);
    if (edge_embedding_max_vertices < 0)
        return "edge_embedding_max_vertices must be >= 0, got " + std::to_string(edge_embedding_max_vertices);
    if (!(edge_embedding_cone_charts >= 0) || !std::isfinite(edge_embedding_cone_charts))
        return "edge_embedding_cone_charts must be finite and >= 0";
    if (!(edge_embedding_area_weight >= 0) || !std::isfinite(edge_embedding_area_weight))
        return "edge_embedding_area_weight must be finite and >= 0";
    if (!(score_margin >= 0 && score_margin < 1)) return "score_margin must be in [0, 1)";
    if (embedding_iterations < 0)
        return "embedding_iterations must be >= 0, got " + std::to_string(embedding_iterations);
    if (embedding_cone_sweeps < 0)
        return "embedding_cone_sweeps must be >= 0, got " + std::to_string(embedding_cone_sweeps);
    if (!(embedding_area_weight >= 0) || !std::isfinite(embedding_area_weight))
        return "embedding_area_weight must be finite and >= 0";
    if (!(embedding_conformal_weight >= 0) || !std::isfinite(embedding_conformal_weight))
        return "embedding_conformal_weight must be finite and >= 0";
    if (!(embedding_cone_conformal_weight >= 0) || !std::isfinite(embedding_cone_conformal_weight))
        return "embedding_cone_conformal_weight must be finite and >= 0";
    return cycles.validate();
}

long long vertices_added_bound(int input_vertices, int corners) {
    return static_cast<long long>(input_vertices) / 4 + 200LL * corners;
}

namespace {

using detail::Builder;
using detail::Network;
using detail::OverBudget;
using detail::Say;

// The orthogonal system of a mesh and the mesh it lies on (the input, refined if coarse).
struct Cycles {
    OrthogonalSystem system;
    OrthogonalSystemOptions options;  // with the progress callback
    double seconds = 0;
    // Vertices the long edges' splits added (QuadLayoutOptions::split_long_edges): room the
    // constructions' budgets do not count (the end's bound does, once unused splits are undone).
    int long_edge_splits = 0;
};

// The cosine of the largest angle between the triangles of a long edge that counts for
// long_edge_split_length() (1 degree): a CAD export's flat faces, not a long protrusion's stretched
// triangles round its axis.
constexpr double kFlatEdgeCos = 0.9998476951563913;

// The length past which build_cycles() splits the edges (QuadLayoutOptions::split_long_edges), if
// it does: 4 times the median edge length (only the outliers of a tessellation; input_wheel's
// fans reach 60 times it), and an eighth of a cage quad's side, a level-3 control face's (so a mesh
// that is coarse all over, like a generated plate, keeps its edges: its coarseness is the 1-to-4
// splits' business). Only where the triangles with such an edge that is flat (kFlatEdgeCos) cover
// a tenth of the surface or more (input_wheel 80%; the figures with limbs of tools/bench/layout_classes.sh
// 3-8%, whose layouts were worse split; the other shared meshes none): a few long edges do not make
// the curves stack up, and splitting them would only move the layout.
std::optional<double> long_edge_split_length(const detail::Surface& s, int quads) {
    const Mesh& mesh = s.mesh();
    std::vector<double> lengths, areas;
    lengths.reserve(s.num_half_edges() / 2);
    for (int h = 0; h < s.num_half_edges(); ++h)
        if (s.from(h) < s.to(h)) lengths.push_back(s.length(h));
    std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
    const double median = lengths[lengths.size() / 2];
    double area = 0;
    for (const Triangle& t : mesh.triangles)
        area += areas.emplace_back(
            0.5 * norm(cross(mesh.points[t[1]] - mesh.points[t[0]], mesh.points[t[2]] - mesh.points[t[0]])));
    const double length = std::max(4 * median, std::sqrt(area / quads) / 8);
    std::vector<char> counted(areas.size(), 0);
    double long_area = 0;
    for (int h = 0; h < s.num_half_edges(); ++h)
        if (!counted[h / 3] && s.length(h) > length && detail::flat_edge(s, h, kFlatEdgeCos))
            counted[h / 3] = 1, long_area += areas[h / 3];
    if (!(long_area >= 0.1 * area)) return std::nullopt;
    return length;
}

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
    // Whether to split long edges is decided on the input: the 1-to-4 splits below make flat edges
    // of their own inside every triangle.
    const int quads = minimal_quad_count(genus);
    const std::optional<double> split_length =
        options.split_long_edges ? long_edge_split_length(detail::Surface(input), quads) : std::nullopt;
    while (mesh.num_vertices() < 1000 + 200 * genus) mesh = subdivide_midpoint(mesh), refined = true;
    if (split_length) {
        detail::Surface s(std::move(mesh));
        c.long_edge_splits = detail::split_long_edges(&s, *split_length);
        mesh = std::move(s.mutable_mesh());
        refined = true;
        if (options.progress)
            options.progress("long edges split: " + std::to_string(c.long_edge_splits) + " vertices added");
    }
    // Builds the cycles (none for a sphere); the input's report serves an unrefined mesh.
    c.system = refined ? build_orthogonal_system(mesh, c.options)
                       : detail::build_orthogonal_system_validated(mesh, c.options, report);
    c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return c;
}

// The layout over `cycles` with the S-cycles from the handle loops (falling back to Algorithm 1's
// where they cannot be placed; *from_handle_loops says which were used), or round the necks (with
// `necks` too; detail::NoNecks where none are found), or Algorithm 1's, before the embedding stage,
// with its quality measured. With max_vertices > 0 the layout curves may refine the surface up to
// that many vertices; past it the layout is abandoned (OverBudget).
QuadLayout build_variant(const Mesh& input, const Cycles& cycles, const QuadLayoutOptions& options,
                         bool handle_loops, bool necks, long long max_vertices, const Say& say,
                         bool* from_handle_loops) {
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
                net = network_of_handles_and_tshirts(b, g, loops, handle_loops, necks, say);
            else if (g == 1)
                net = network_of_torus(b, say);
            else
                net = network_of_cube(b, say);
            *from_handle_loops = net.s_cycles_from_handle_loops;
            say("patches");
            detail::tighten_layout_curves(b, net, g);
            b.split_dividing_chords(detail::layout_edge_paths(b, net));
            detail::NetworkSeconds network_seconds;
            std::vector<int> s_cycle_ids = net.s_cycles;
            bool measured = false;  // out.quality is measured (the relaxed-or-plain choice did)
            const bool finished =   // out holds the relaxed layout, built and verified
                options.relax_sweeps > 0 && detail::relax_network(&b, net, options, g, say, &out,
                                                                  &s_cycle_ids, &network_seconds, &measured);
            if (!finished)
                if (const std::string problem = detail::finish_network(b, net, &out, say, &network_seconds);
                    !problem.empty())
                    throw InternalError(problem);
            for (int i = 0; i < 2 * g; ++i) out.orthogonal_system.push_back(b.curves_[i]);
            for (int id : s_cycle_ids) out.s_cycles.push_back(b.curves_[id]);
            const double t_quality = clock();
            if (!measured) detail::measure_quality(&out);
            const double t_end = clock();
            const double checked = network_seconds.checked + (t_end - t_quality);
            out.seconds = {t_cycles, t_end - network_seconds.mapped - checked, network_seconds.mapped,
                           checked};
            return out;
        } catch (const OverBudget&) {
            throw;
        } catch (const detail::NoNecks&) {
            throw;
        } catch (const InternalError& e) {
            failure = e.what();
            say(std::string("retrying the layout curves: ") + e.what());
        }
    }
    throw InternalError(failure);
}

// A layout built in another thread (build_quad_layout's Algorithm 1 and necks' S-cycles), with what
// it said.
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
    // Says what it has said so far and, as it goes on, what it says next, until it ends: the
    // messages of a layout that is wanted, in their order, live while it is awaited.
    void finish(const Say& say) {
        for (size_t said = 0;;) {
            std::vector<std::string> next;
            bool ended = false;
            {
                std::unique_lock<std::mutex> lock(mutex);
                changed.wait(lock, [&] { return done || messages.size() > said; });
                next.assign(messages.begin() + static_cast<long>(said), messages.end());
                said = messages.size();
                ended = done;
            }
            for (const std::string& m : next) say(m);  // not under the lock: say() may take its time
            if (ended) break;
        }
        thread.join();
    }

    const long long max_vertices;  // the vertex budget it was built with
    std::thread thread;
    std::atomic<bool> cancel{false};
    std::mutex mutex;  // guards messages and done
    std::condition_variable changed;
    std::vector<std::string> messages;  // its progress messages, prefixed
    bool done = false;
    std::optional<QuadLayout> layout;
    std::exception_ptr error;  // what build_variant threw (nothing if it was cancelled)
};

// Starts build_variant(input, cycles, options, handle_loops, necks, max_vertices) in a thread of
// its own, its progress messages held with `prefix`.
std::unique_ptr<Speculation> speculate(const Mesh& input, const Cycles& cycles, const QuadLayoutOptions& options,
                                       bool handle_loops, bool necks, long long max_vertices, std::string prefix) {
    auto sp = std::make_unique<Speculation>(max_vertices);
    Speculation* p = sp.get();
    sp->thread = std::thread([p, &input, &cycles, &options, handle_loops, necks, prefix = std::move(prefix)] {
        const Say held = [p, &prefix](const std::string& m) {
            if (p->cancel.load()) throw Speculation::Cancelled{};
            {
                const std::lock_guard<std::mutex> lock(p->mutex);
                p->messages.push_back(prefix + m);
            }
            p->changed.notify_one();
        };
        try {
            bool unused = false;
            p->layout = build_variant(input, cycles, options, handle_loops, necks, p->max_vertices, held, &unused);
        } catch (const Speculation::Cancelled&) {
        } catch (...) {
            p->error = std::current_exception();
        }
        {
            const std::lock_guard<std::mutex> lock(p->mutex);
            p->done = true;
        }
        p->changed.notify_one();
    });
    return sp;
}

// A layout's seconds after the orthogonal system (which both S-cycle constructions share).
double seconds_after_cycles(const QuadLayout::Seconds& s) {
    return s.curves + s.parameterization + s.verification;
}

// options.score of a layout: its value once computed, or the InternalError it threw (not asked
// again: a score may take seconds).
struct Score {
    std::optional<double> value;
    std::optional<double> tie;  // options.tie_score's, once asked
    std::exception_ptr failure;

    // Computes it unless it was computed or failed before.
    void of(const QuadLayout& layout, const QuadLayoutOptions& options) {
        if (value || failure) return;
        try {
            value = options.score(layout);
        } catch (const InternalError&) {
            failure = std::current_exception();
        }
    }
    double get() const {  // the value; rethrows the failure
        if (failure) std::rethrow_exception(failure);
        return *value;
    }
    // options.tie_score(layout), computed once (its InternalError is thrown, not kept).
    double tie_of(const QuadLayout& layout, const QuadLayoutOptions& options) {
        if (!tie) tie = options.tie_score(layout);
        return *tie;
    }
};

// Whether `candidate`, a layout of other S-cycles, is to be kept instead of `kept`. With
// options.score the lower score wins (kept's is scored once: *kept_score holds it, and the
// candidate's once it is kept); where the scores differ by no more than options.score_margin of
// kept's, the lower options.tie_score wins by the same margin (asked then, once a layout); where
// there is none, where those tie too, or where scoring fails (InternalError), the candidate wins
// when both its patch area max/min and its corner angle deviation are smaller. Says the figures,
// the scores' time and the choice.
bool candidate_is_better(const QuadLayout& kept, const QuadLayout& candidate, const std::string& kept_name,
                         const std::string& candidate_name, const QuadLayoutOptions& options, Score* kept_score,
                         const Say& say) {
    const LayoutQuality &a = kept.quality, &b = candidate.quality;
    char line[400];
    std::snprintf(line, sizeof line,
                  "S-cycles: %s give patch area max/min %.3g and corner angle deviation %.1f deg, %s %.3g and "
                  "%.1f deg",
                  kept_name.c_str(), a.patch_area_max_over_min, a.corner_angle_mean_deviation_deg,
                  candidate_name.c_str(), b.patch_area_max_over_min, b.corner_angle_mean_deviation_deg);
    std::string why = line;
    bool better = b.patch_area_max_over_min < a.patch_area_max_over_min &&
                  b.corner_angle_mean_deviation_deg < a.corner_angle_mean_deviation_deg;
    Score candidate_score;  // left unscored where kept's fails
    if (options.score) {
        const auto start = std::chrono::steady_clock::now();
        try {
            kept_score->of(kept, options);
            const double k = kept_score->get();
            candidate_score.of(candidate, options);
            const double s = candidate_score.get();
            // Scores decide where they differ by more than the margin of the kept layout's.
            const auto apart = [&options](double kept_value, double value) {
                return std::abs(value - kept_value) > options.score_margin * kept_value;
            };
            const bool decides = apart(k, s);
            if (decides) better = s < k;
            std::snprintf(line, sizeof line, "; scores %.4g and %.4g (%.1f s)%s", k, s,
                          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                          decides ? "" : options.tie_score ? ", too close to decide" : ", too close to decide, so by those");
            why += line;
            if (!decides && options.tie_score) {
                // Within the margin the level-1 fits ranked the constructions' level-3 fits no
                // better than chance (2 of 8 pairs); the finer score is taken only here, where it
                // is needed, since it costs several times as much.
                const auto tie_start = std::chrono::steady_clock::now();
                const double tk = kept_score->tie_of(kept, options), ts = candidate_score.tie_of(candidate, options);
                const bool tie_decides = apart(tk, ts);
                if (tie_decides) better = ts < tk;
                std::snprintf(line, sizeof line, "; finer scores %.4g and %.4g (%.1f s)%s", tk, ts,
                              std::chrono::duration<double>(std::chrono::steady_clock::now() - tie_start).count(),
                              tie_decides ? "" : ", too close again, so by those");
                why += line;
            }
        } catch (const InternalError& e) {  // the score's own failure: the rule chooses
            why += std::string("; not scored (") + e.what() + "), so by those";
        }
    }
    if (better) *kept_score = candidate_score;
    say(why + "; keeping " + (better ? candidate_name : kept_name));
    return better;
}

// The layout over `cycles` (build_variant()) with the S-cycles from the handle loops and, for
// genus >= 2, with Algorithm 1's and with the necks'; the best of them is kept (see below).
QuadLayout layout_of_better_s_cycles(const Mesh& input, const Cycles& cycles,
                                     const QuadLayoutOptions& options, const Say& say) {
    // Algorithm 1's layout and the necks' for the comparisons below depend only on the orthogonal
    // system and the bound, so each is built in a thread of its own while the handle loops' layout
    // is built here, and they are scored here while the others finish. Their progress messages are
    // held back until each is known to be wanted (else it is stopped at its next message and
    // dropped), then said, and said as they come while it is awaited (Speculation::finish()), so the
    // messages and the result are those of building them one after the other.
    // (Their factorisations and the scores' take turns: blas_threads.h.) On the 2-core machine,
    // with the necks' built after the others, botijo's layout took 23.7 s and boot's 29.8 s; built
    // beside them, 21.9 s and 27.0 s, the same layouts.
    const int g = cycles.system.genus;
    const auto after_cycles = std::chrono::steady_clock::now();
    auto since = [](std::chrono::steady_clock::time_point t) {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
    };
    std::unique_ptr<Speculation> other, necks;
    if (options.s_cycles_from_handle_loops && options.s_cycles_compare && g >= 2) {
        const long long max_vertices = input.num_vertices() + cycles.long_edge_splits +
                                       vertices_added_bound(input.num_vertices(), 8 * g - 8);
        other = speculate(input, cycles, options, false, false, max_vertices, "Algorithm 1's S-cycles: ");
        if (options.s_cycles_from_necks && g <= detail::kMaxNeckGenus)  // else there is none to build
            necks = speculate(input, cycles, options, true, true, max_vertices, "S-cycles at the necks: ");
    }
    auto drop = [](std::unique_ptr<Speculation>* sp) {
        if (*sp) (*sp)->stop(), sp->reset();
    };
    bool from_handle_loops = false;
    Score out_score;  // options.score(out), once computed
    QuadLayout out = [&] {
        try {
            return build_variant(input, cycles, options, options.s_cycles_from_handle_loops, false, 0, say,
                                 &from_handle_loops);
        } catch (...) {
            drop(&other);
            drop(&necks);
            throw;
        }
    }();
    const long long bound = vertices_added_bound(out.input_vertices, out.cage.num_corners());
    // The handle loops gave the S-cycles only where the other threads were started (genus >= 2 and
    // both options), and a verified layout has its 8g - 8 corners: the bound is the one they used.
    const bool compare = from_handle_loops && options.s_cycles_compare;
    const bool within_bound = out.mesh.num_vertices() - out.input_vertices - cycles.long_edge_splits <= bound;
    QC_CHECK(
        !compare || (other && other->max_vertices == out.input_vertices + cycles.long_edge_splits + bound),
        "quad layout: Algorithm 1's layout was not built with the handle loops' bound");
    if (!(compare && within_bound)) drop(&other);  // not wanted
    if (!compare) drop(&necks);
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
        // 7%). So Algorithm 1's is kept only when it is better on both, unless options.score
        // decides (a level-1 fit in the CLI: with its margin it kept the lowest level-3 RMS on 10
        // of 14 meshes, the rule on 6; the README's "The S-cycles chosen by a level-1 fit"). It may
        // refine no more than the bound.
        other->finish(say);
        try {
            if (other->error) std::rethrow_exception(other->error);
            if (candidate_is_better(out, *other->layout, "the handle loops'", "Algorithm 1's", options, &out_score,
                                    say))
                out = std::move(*other->layout);
        } catch (const InternalError& e) {
            say(std::string("S-cycles: keeping the handle loops' (Algorithm 1's: ") + e.what() + ")");
        }
        other.reset();
    }
    if (necks) {
        // The S-cycles round the necks, kept when better than the layout kept so far, as
        // Algorithm 1's are. Level-3 check_fit.py RMS / Hausdorff, the necks' against the best of
        // the other two: a wheel (generate wheel -g 7 -r 3) 3.7e-4 / 4.6e-3 against 1.4e-3 /
        // 1.9e-2, boot 1.1e-3 / 1.1e-2 against 2.0e-3 / 2.8e-2, botijo 2.8e-4 / 2.9e-3 against
        // 3.2e-4 / 3.7e-3; on a big body with small handles in a row (generate handles -g 3
        // --in-a-row) 5.5e-4 / 7.1e-3 against Algorithm 1's 3.7e-4 / 4.2e-3. The rule keeps the
        // handle loops' on boot (the necks' patch area max/min is the larger there, 1.16e3 against
        // 1.11e3); the level-1 fit score keeps the necks'. Built within the same bound (OverBudget
        // past it).
        // Scored while the necks' layout is still being built (its score is the same whenever it is
        // taken; a failure is said by candidate_is_better()).
        if (options.score) out_score.of(out, options);
        necks->finish(say);
        try {
            if (necks->error) std::rethrow_exception(necks->error);
            if (candidate_is_better(out, *necks->layout, "those kept so far", "the necks'", options, &out_score, say))
                out = std::move(*necks->layout);
        } catch (const InternalError& e) {  // OverBudget and NoNecks too
            say(std::string("S-cycles: keeping the ones so far (at the necks: ") + e.what() + ")");
        }
        necks.reset();
    }
    // Built side by side: the layouts not kept, the scores and the waits add the wall time past the
    // kept one's own (time spent on the layout curves).
    out.seconds.curves += std::max(0.0, since(after_cycles) - seconds_after_cycles(out.seconds));
    return out;
}

// How far build_quad_layout() moves a mesh along each axis before the layout: along an axis where it
// lies at least kFarFromOrigin times its extent from the origin, by its nearest coordinate (every
// coordinate c along it is then within a factor of 2 of that one, so c - nearest is exact
// (Sterbenz), and so is the way back); else not at all. Far out, the coordinates' rounding is large
// against the triangles and the layout's tolerances, which are relative to the triangles: eight
// moved by 1e6 along each axis (an ulp of 1e6 is 1.2e-10; its triangles' edges are about 0.05) had
// 590 of its unused splits undone instead of 2,072, its embedded edges added 2,129 vertices against
// a bound of 1,791, its curves could not be traced again on the input's triangles, and it kept its
// edges along mesh edges with 1,699 vertices added, against 832 and embedded edges at the origin.
constexpr double kFarFromOrigin = 64;

Vec3 offset_for_layout(const Mesh& mesh) {
    const double inf = std::numeric_limits<double>::infinity();
    double lo[3] = {inf, inf, inf}, hi[3] = {-inf, -inf, -inf};
    for (const Vec3& p : mesh.points) {
        const double c[3] = {p.x, p.y, p.z};
        for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], c[k]), hi[k] = std::max(hi[k], c[k]);
    }
    double offset[3] = {0, 0, 0};
    for (int k = 0; k < 3 && !mesh.points.empty(); ++k) {
        const double extent = hi[k] - lo[k];
        if (lo[k] > 0 && lo[k] >= kFarFromOrigin * extent) offset[k] = lo[k];
        if (hi[k] < 0 && -hi[k] >= kFarFromOrigin * extent) offset[k] = hi[k];
    }
    return {offset[0], offset[1], offset[2]};
}

std::optional<QuadLayout> layout_on_proxy(const Mesh& input, const QuadLayoutOptions& options, const Say& say);

QuadLayout build_layout_in_place(const Mesh& input, const QuadLayoutOptions& options) {
    const Say say = [&options](const std::string& m) {
        if (options.progress) options.progress(m);
    };
    // Built on a decimated copy and carried onto the input (retrace.cpp), if asked and it works.
    if (options.proxy_vertices > 0 && input.num_vertices() > 2 * static_cast<long long>(options.proxy_vertices) &&
        input.num_vertices() > options.proxy_above)
        if (std::optional<QuadLayout> traced = layout_on_proxy(input, options, say)) return std::move(*traced);
    // The orthogonal system of cycles (orthogonal_system.cpp), on the input or a refined copy.
    const Cycles cycles = build_cycles(input, options);
    // S-cycles and pieces (handle_loop_s_cycles.cpp, s_cycles.cpp, pieces.cpp), then T-shirts and
    // handles (tshirts_and_handles.cpp) or the torus or the cube (torus_and_cube.cpp), relaxed and
    // verified (network.cpp).
    QuadLayout out = layout_of_better_s_cycles(input, cycles, options, say);
    // The embedding: the layout edges along one map of the surface, else smoothed (edges.cpp).
    const long long bound = vertices_added_bound(out.input_vertices, out.cage.num_corners());
    detail::place_layout_edges(input, &out, options, bound, say);
    // The experimental embedding stage, which can move the corners (embedding.cpp; off by default).
    if (options.embedding_iterations > 0) {
        const auto start = std::chrono::steady_clock::now();
        detail::EmbeddingOptions eo;
        eo.iterations = options.embedding_iterations;
        eo.area_weight = options.embedding_area_weight;
        eo.conformal_weight = options.embedding_conformal_weight;
        eo.cone_conformal_weight = options.embedding_cone_conformal_weight;
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

std::optional<QuadLayout> layout_on_proxy(const Mesh& input, const QuadLayoutOptions& options, const Say& say) {
    using Clock = std::chrono::steady_clock;
    const auto seconds_since = [](Clock::time_point t) {
        return std::chrono::duration<double>(Clock::now() - t).count();
    };
    const auto start = Clock::now();
    const std::string n = std::to_string(options.proxy_vertices);
    say("proxy: decimating the input to " + n + " vertices");
    const Mesh proxy = decimated(input, options.proxy_vertices);
    const ValidationReport in = validate(input), copy = validate(proxy);
    if (!copy.quaddable() || copy.components.size() != 1 || copy.zero_area_triangles > 0 ||
        in.components.size() != 1 || copy.components[0].genus != in.components[0].genus) {
        say("proxy: the decimated copy is not a closed surface of the input's genus; building on the input itself");
        return std::nullopt;
    }
    const double decimation = seconds_since(start);
    QuadLayoutOptions on_copy = options;
    on_copy.proxy_vertices = 0;
    on_copy.progress = [&say](const std::string& m) { say("proxy: " + m); };
    QuadLayout made;
    try {
        made = build_layout_in_place(proxy, on_copy);
    } catch (const InternalError& e) {
        say(std::string("proxy: no layout on the decimated copy (") + e.what() + "); building on the input itself");
        return std::nullopt;
    }
    const auto trace_start = Clock::now();
    QuadLayout out;
    std::string how;
    if (const std::string problem = detail::trace_from_proxy(input, made, &out, &how); !problem.empty()) {
        say("proxy: not carried onto the input (" + problem + "); building on the input itself");
        return std::nullopt;
    }
    detail::measure_quality(&out);
    out.seconds.cycles += decimation;
    out.seconds.curves += seconds_since(trace_start);
    char line[256];
    std::snprintf(line, sizeof line,
                  "proxy: carried onto the input %s (%d vertices added): patch area max/min %.3g, corner angle "
                  "deviation %.1f deg; %.2f s in all",
                  how.c_str(), out.mesh.num_vertices() - out.input_vertices, out.quality.patch_area_max_over_min,
                  out.quality.corner_angle_mean_deviation_deg, seconds_since(start));
    say(line);
    const long long bound = vertices_added_bound(out.input_vertices, out.cage.num_corners());
    if (const long long added = out.mesh.num_vertices() - out.input_vertices; added > bound)
        say("refinement: " + std::to_string(added) + " vertices added, over the bound of " +
            std::to_string(bound) + " (a quarter of the input's plus 200 per corner)");
    return out;
}

}  // namespace

QuadLayout build_quad_layout(const Mesh& input, const QuadLayoutOptions& options) {
    if (const std::string e = options.validate(); !e.empty()) throw InvalidInput("quad layout options: " + e);
    const Vec3 offset = offset_for_layout(input);
    if (offset.x == 0 && offset.y == 0 && offset.z == 0) return build_layout_in_place(input, options);
    // Built near the origin and moved back: the input's points come back exactly.
    Mesh near = input;
    for (Vec3& p : near.points) p = p - offset;
    QuadLayout out = build_layout_in_place(near, options);
    for (Vec3& p : out.mesh.points) p = p + offset;
    for (Vec3& p : out.cage.points) p = p + offset;
    return out;
}

}  // namespace quadcage::layout
