// Where the layout edges finally run (issue #20's "clean curves"): along the iso-lines of one map
// of the whole surface with the corners held (embed_layout_edges()), else smoothed round where the
// relaxation left them (smooth_layout_edges()), else along mesh edges; the layout mesh within the
// refinement bound.

#include <chrono>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>

#include "detail/embedding.h"
#include "detail/patches.h"
#include "detail/unrefine.h"
#include "quadcage/core/errors.h"

namespace quadcage::layout::detail {

void place_layout_edges(const Mesh& input, QuadLayout* layout, const QuadLayoutOptions& options,
                        long long bound, const std::function<void(const std::string&)>& say) {
    auto since = [](std::chrono::steady_clock::time_point t) {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
    };
    QuadLayout& out = *layout;
    // Traced again on the input's triangles over the bound, unless the edges are to stay as routed.
    const Mesh* retrace = options.smooth_edges ? &input : nullptr;
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
        EdgeEmbeddingReport r;
        std::string why_not;
        try {
            why_not =
                embed_layout_edges(out, options.edge_embedding_iterations, &e, &r, kEdgeEmbeddingTolerance,
                                   options.edge_embedding_cone_charts, options.edge_embedding_area_weight);
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
            std::string said = line;
            if (options.edge_embedding_area_weight > 0) {
                std::snprintf(line, sizeof line, "; with an area term of weight %g",
                              options.edge_embedding_area_weight);
                said += line;
            }
            if (r.pulled > 0)
                said += "; " + std::to_string(r.pulled) + " of them pulled towards the cone charts";
            say(said);
            measure_quality(&e);
            e.seconds = out.seconds;
            e.edges_smoothed = true;
            undo_unused_refinement(&e, say, bound, retrace);
            const long long added = e.mesh.num_vertices() - e.input_vertices;
            const double before = out.quality.patch_area_max_over_min,
                         after = e.quality.patch_area_max_over_min;
            // With the cone charts, what the embedding is for is the corner angles.
            const bool charts = options.edge_embedding_cone_charts > 0;
            const double angle_before = out.quality.corner_angle_mean_deviation_deg,
                         angle_after = e.quality.corner_angle_mean_deviation_deg;
            if (added > bound) {
                why_not = "they add " + std::to_string(added) + " vertices, over the bound of " +
                          std::to_string(bound);
            } else if (!charts && !(after < before)) {
                std::snprintf(line, sizeof line, "patch area max/min %.3g, not below %.3g", after, before);
                why_not = line;
            } else if (charts && !(angle_after < angle_before)) {
                std::snprintf(line, sizeof line, "corner angle deviation %.1f deg, not below %.1f",
                              angle_after, angle_before);
                why_not = line;
            } else {
                std::snprintf(
                    line, sizeof line,
                    "edge embedding: keeping the embedded edges: patch area max/min %.3g (was %.3g), "
                    "corner angle deviation %.1f deg (was %.1f)",
                    after, before, angle_after, angle_before);
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
        SmoothingReport r;
        if (const std::string problem = smooth_layout_edges(out, &smooth, &r); !problem.empty()) {
            say("smoothing: keeping the edges along mesh edges (" + problem + ")");
        } else {
            measure_quality(&smooth);
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
    undo_unused_refinement(&out, say, bound, retrace);
    if (staircase && out.mesh.num_vertices() - out.input_vertices > bound) {
        // Each crossing of a mesh edge is a vertex: a plate's coarse, regular mesh (genus 11: 20330
        // added, bound 16137, against 9473 along mesh edges) can take the smoothed edges past the
        // bound.
        say("smoothing: keeping the edges along mesh edges (smoothed, they add " +
            std::to_string(out.mesh.num_vertices() - out.input_vertices) + " vertices, over the bound of " +
            std::to_string(bound) + ")");
        staircase->seconds = out.seconds;
        out = std::move(*staircase);
        undo_unused_refinement(&out, say, bound, retrace);
    }
}

}  // namespace quadcage::layout::detail
