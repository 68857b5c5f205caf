// Scratch benchmark of the fit alone (no layout): fits a generated torus or cube-sphere through its
// hand-built layout, level by level, and prints errors and seconds by stage.
//
//   fit_bench torus|sphere [resolution] [max_level] [threads]

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "quadcage/fit/fit.h"
#include "quadcage/fit/outputs.h"
#include "support/fit_layouts.h"

int main(int argc, char** argv) {
    using namespace quadcage;
    const std::string shape = argc > 1 ? argv[1] : "torus";
    const int res = argc > 2 ? std::atoi(argv[2]) : 48;
    const int max_level = argc > 3 ? std::atoi(argv[3]) : 4;
    const int threads = argc > 4 ? std::atoi(argv[4]) : 0;
    const layout::QuadLayout L =
        shape == "sphere" ? test::cube_sphere_layout(res) : test::torus_layout(res, res / 2);
    std::printf("%s: %d triangles, %d cage quads\n", shape.c_str(), L.mesh.num_triangles(), L.cage.num_quads());
    fit::FitOptions o;
    o.mode = fit::FitMode::Tolerance;
    o.tolerance = 1e-9;  // run every level
    o.max_level = max_level;
    if (std::getenv("FIT_BENCH_LEVEL")) {
        o.mode = fit::FitMode::Level;
        o.level = max_level;
    }
    o.measure_unfitted = true;
    o.threads = threads;
    if (const char* w = std::getenv("FIT_BENCH_S2I")) o.surface_to_input_weight = std::atof(w);
    if (const char* w = std::getenv("FIT_BENCH_SAMPLES")) o.area_samples = std::atoi(w);
    if (const char* w = std::getenv("FIT_BENCH_ROUNDS")) o.outer_iterations = std::atoi(w);
    if (std::getenv("FIT_BENCH_VERBOSE")) o.progress = [](const std::string& s) { std::printf("  %s\n", s.c_str()); };
    const fit::FitResult r = fit::fit_surface(L, o);
    std::printf("level ctrl  rel_rms    rel_haus   in->surf   surf->in   unfit_rms  ratio  rounds/its param   eval    closest solve   total   stop\n");
    for (const auto& l : r.levels)
        std::printf("%5d %5d  %.3e  %.3e  %.3e  %.3e  %.3e  %5.3f  %3d/%-4d %6.3f  %6.3f  %6.3f  %6.3f  %6.3f  %s\n", l.level,
                    l.control_points, l.relative.rms, l.relative.hausdorff, l.relative.input_to_surface.rms,
                    l.relative.surface_to_input.rms, l.unfitted_relative_rms,
                    l.relative.rms / l.unfitted_relative_rms, l.iterations, l.solver_iterations, l.seconds.parameterization,
                    l.seconds.evaluation, l.seconds.closest_points, l.seconds.solve, l.seconds.total,
                    l.stop_reason.c_str());
    if (argc > 5) {
        const auto t0 = std::chrono::steady_clock::now();
        const fit::FitOutputs out = fit::write_fit_outputs(argv[5], L.mesh, r, o);
        std::printf("outputs in %s: tessellation %d segments, %lld triangles, rms error %.3e (target %.3e) %.2f s\n",
                    argv[5], out.tessellation.segments, out.tessellation.triangles, out.tessellation.rms_error,
                    out.tessellation.target,
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    return 0;
}
