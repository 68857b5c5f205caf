// quadcage: command-line interface. Parses arguments into an options struct and calls the library.

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <new>

#include "commands.h"
#include "quadcage/core/errors.h"

namespace {

// The arguments every mesh-processing command takes: MESH, -o DIR and -q.
void add_mesh_output_quiet(CLI::App* cmd, std::string& mesh, std::string& dir, bool& quiet) {
    cmd->add_option("MESH", mesh, "Closed triangle mesh: OBJ, PLY, OFF or STL")->required();
    cmd->add_option("-o,--output", dir, "Output directory (created if missing)")->required();
    cmd->add_flag("-q,--quiet", quiet, "No progress messages on stderr");
}

// The experimental embedding stage's flags (issue #20), for `layout` and for `fit`'s layout.
// Returns them, for `excludes`.
std::vector<CLI::Option*> add_embedding_flags(CLI::App* cmd, quadcage::cli::EmbeddingFlags& flags) {
    std::vector<CLI::Option*> all;
    all.push_back(
        cmd->add_option(
               "--embedding-iterations", flags.iterations,
               "Newton iterations of the global embedding optimisation of the layout (issue #20; 0: off,\n"
               "the default); experimental: reports the area balance the optimised map would give")
            ->check(CLI::NonNegativeNumber));
    all.push_back(
        cmd->add_flag("--embedding-extract", flags.extract,
                      "With --embedding-iterations: use the optimised map's iso-lines as the layout when\n"
                      "that layout verifies and has a smaller patch area max/min. The corner angles are not\n"
                      "compared: they get worse. On botijo the extracted layout is no better balanced (12.7\n"
                      "against 12.4; 54 deg mean corner angle deviation against 23) and is not kept; with\n"
                      "--embedding-area-weight 100 it is (2.48, 71 deg), and the level-3 fit is worse than the\n"
                      "default layout's (check_fit.py RMS 2.9e-4 against 2.4e-4; README: Balance, angles and fit)"));
    all.push_back(
        cmd->add_option("--embedding-area-weight", flags.area_weight,
                        "Weight of the embedding's area term over symmetric Dirichlet (default 0): higher\n"
                        "evens out the patch areas at the cost of the corner angles")
            ->check(CLI::NonNegativeNumber));
    all.push_back(
        cmd->add_option(
               "--embedding-conformal-weight", flags.conformal_weight,
               "Weight of the embedding's conformal term (MIPS) over symmetric Dirichlet (default 0):\n"
               "higher weighs the angles against the patch areas")
            ->check(CLI::NonNegativeNumber));
    all.push_back(
        cmd->add_option(
               "--embedding-cone-conformal-weight", flags.cone_conformal_weight,
               "Extra weight of that conformal term near the corners, within a fifth of a patch side\n"
               "(default 0): keeps the optimised map's corner angles. With --embedding-area-weight 10,\n"
               "300 took skull's extracted layout to patch area max/min 3.61 and 8.8 deg (the default\n"
               "layout: 7.92, 21.1 deg), but its level-3 fit got worse (README: Corner angles held in the\n"
               "global embedding)")
            ->check(CLI::NonNegativeNumber));
    all.push_back(
        cmd->add_option(
               "--embedding-cone-sweeps", flags.cone_sweeps,
               "Passes of cone relocation in the embedding (default 0; experimental): every corner\n"
               "moves along the surface down the energy's gradient, up to half a patch side per pass,\n"
               "while that lowers the optimised energy")
            ->check(CLI::NonNegativeNumber));
    all.push_back(cmd->add_flag(
        "--no-necks", flags.no_necks,
        "Do not build the layout with S-cycles round the surface's necks (by default, genus 2-33: the\n"
        "shortest loops that cut it into pairs of pants, joined in pairs into T-shirts; that layout\n"
        "is kept when it is the better, see --choose-s-cycles, and the README). Saves its time"));
    all.push_back(cmd->add_flag(
        "--no-long-edge-splits", flags.no_long_edge_splits,
        "Do not split the input's long edges before the layout (by default, edges longer than 4 times\n"
        "the median and than an eighth of a cage quad's side are split at their midpoints where the\n"
        "triangles with such an edge between coplanar triangles (within 1 degree) cover a tenth of the\n"
        "surface, so the layout curves do not follow a CAD mesh's fans of long, thin triangles; the\n"
        "splits no curve needs are undone at the end)"));
    all.push_back(
        cmd->add_option_function<std::string>(
               "--choose-s-cycles",
               [&flags](const std::string& how) { flags.choose_by_shape = how == "shape"; },
               "How the layout's S-cycles are chosen among those built (genus >= 2: the handle loops',\n"
               "Algorithm 1's, the necks'): fit (the default) keeps the one whose cage fits the mesh\n"
               "best at level 1 (relative RMS; a level-1 fit of each, 0.5-1.5 s on botijo, boot and\n"
               "input_wheel), and where two are within 10% there, best at level 2 (2.6-10 s more in the\n"
               "runs measured; README, \"Ties broken at level 2\"); shape keeps a later one only when\n"
               "both its patch area max/min and corner angle deviation are smaller (as fit does where\n"
               "the level-2 fits tie too)")
            ->check(CLI::IsMember({"fit", "shape"})));
    all.push_back(cmd->add_flag(
        "--staircase-edges", flags.staircase_edges,
        "Leave the layout edges along mesh edges as the construction routed them, zigzagging across\n"
        "the triangles. By default each is smoothed: an iso-line of the patch maps made harmonic in a\n"
        "band three vertex rings wide round the edges (each edge's first and last 12% held), cut into\n"
        "the mesh, through the same corners; dropped for these if it would pass the refinement bound.\n"
        "Also skips --edge-embedding"));
    all.push_back(
        cmd->add_option(
               "--edge-embedding", flags.edge_embedding,
               "Newton steps of the global edge embedding, at most (default 30; 0: off, the edges are\n"
               "only smoothed): one map of the whole surface over the cage's squares, the corners and each\n"
               "edge's first and last tenth held, whose iso-lines become the layout edges when they\n"
               "spread the area more evenly over the patches and stay within the refinement bound.\n"
               "Stops after a step that lowers its energy by less than 0.2%. Costs a factorisation a\n"
               "step: at botijo's 39k vertices on 2 cores, 7 steps in 2.5-3.6 s when the machine is idle")
            ->check(CLI::NonNegativeNumber));
    all.push_back(
        cmd->add_option("--proxy-vertices", flags.proxy_vertices,
                        "Build the layout on a copy of the input decimated to N vertices (shortest-edge\n"
                        "collapses; default 10000, 0: never), then carry its curves onto the input's own\n"
                        "triangles; only for inputs of more than --proxy-above vertices and more than 2N.\n"
                        "Falls back to building on the input itself, and says why, where the copy or the\n"
                        "carrying over fails. botijo split twice (658k vertices): 25 s instead of 120-220 s")
            ->check(CLI::NonNegativeNumber));
    all.push_back(
        cmd->add_option("--proxy-above", flags.proxy_above,
                        "Lay out inputs of at most M vertices on themselves, not on a copy (default 100000;\n"
                        "0: every input of more than 2 x --proxy-vertices). On smaller scans the copy's\n"
                        "layouts fit with a larger Hausdorff distance (skull, 50k vertices: past 1e-2)")
            ->check(CLI::NonNegativeNumber));
    all.push_back(
        cmd->add_option("--edge-embedding-max-vertices", flags.edge_embedding_max_vertices,
                        "Skip the edge embedding (only smooth the edges) on layout meshes with more\n"
                        "vertices than this (default 200000; at 648k, on one BLAS thread: 8.4 s a step,\n"
                        "3.1 GiB peak)")
            ->check(CLI::NonNegativeNumber));
    all.push_back(
        cmd->add_option(
               "--edge-embedding-cone-charts", flags.edge_embedding_cone_charts,
               "Strength of the edge embedding's cone charts (default 0: off; 1000 is a strong pull):\n"
               "round each corner the map is pulled towards the conformal map that spreads the corner's\n"
               "edges evenly in its tangent plane, instead of holding the edges' ends, and the embedded\n"
               "edges are kept if they lower the mean corner angle deviation. At 1000 it fell from 23.1\n"
               "to 14.2 deg on botijo, but the level-3 fit's Hausdorff distance rose (README: Cone charts)")
            ->check(CLI::NonNegativeNumber));
    all.push_back(
        cmd->add_option(
               "--edge-embedding-area-weight", flags.edge_embedding_area_weight,
               "Weight of an area term in the edge embedding's energy (default 0: symmetric Dirichlet\n"
               "alone): higher spreads the surface more evenly over the patches, at the cost of their\n"
               "shapes; the corners and the edges' ends stay held. At 10, patch area max/min fell from\n"
               "7.92 to 3.47 on skull and from 12.4 to 8.41 on botijo, but skull's level-3 fit got worse\n"
               "(README: An area term in the edge embedding)")
            ->check(CLI::NonNegativeNumber));
    return all;
}

}  // namespace

int main(int argc, char** argv) {
    using namespace quadcage::cli;
    CLI::App app{
        "quadcage: the smallest quad cage of a closed triangle mesh (10g-10 quads for genus g >= 2,\n"
        "4 for a torus, 6 for a sphere).\n\n"
        "Exit codes: 0 ok, 1 internal error, 2 bad usage, 3 invalid input (one line on stderr says why)."};
    app.require_subcommand(1);
    app.set_version_flag("--version", std::string("quadcage ") + QUADCAGE_VERSION);

    InfoOptions info;
    CLI::App* info_cmd = app.add_subcommand(
        "info", "Load and validate a mesh; print vertices, triangles, components and, per component,\n"
                "closed/manifold/orientable, genus, boundary loops and the minimal quad count.\n"
                "Exits 3 if the mesh cannot be quadded.");
    info_cmd->add_option("MESH", info.mesh, "Mesh file: OBJ, PLY (ascii/binary), OFF or STL")->required();
    info_cmd->add_flag("--json", info.json, "Print the report as JSON");

    CyclesOptions cycles;
    CLI::App* cycles_cmd = app.add_subcommand(
        "cycles", "Compute an orthogonal system of 2g cycles (paper, Definition 6) on each component.\n"
                  "Writes DIR/layout.ply (the surface the cycles live on), DIR/cycles.json and\n"
                  "DIR/report.json; a mesh of several components gets DIR/component_<i>/ each.");
    add_mesh_output_quiet(cycles_cmd, cycles.mesh, cycles.output_dir, cycles.quiet);

    LayoutOptions layout;
    CLI::App* layout_cmd = app.add_subcommand(
        "layout", "Build the minimal quad layout of each component: 10g-10 quads with all 8g-8 corners of\n"
                  "degree 5 for genus g >= 2 (paper, Algorithm 1), 4 quads for a torus, a 6-quad cube for a\n"
                  "sphere; verified before anything is written. Writes DIR/layout.ply (face property patch),\n"
                  "cage.obj, cage.json (exact topology), cage_level1.obj, cycles.json and report.json; a mesh\n"
                  "of several components gets DIR/component_<i>/ each.");
    add_mesh_output_quiet(layout_cmd, layout.mesh, layout.output_dir, layout.quiet);
    add_embedding_flags(layout_cmd, layout.embedding);

    // --cad-tolerance: relative to the diagonal; below 1e-9 of it double precision cannot tell.
    const CLI::Validator cad_tolerance(
        [](std::string& text) -> std::string {
            try {
                const double t = std::stod(text);
                if (t >= 1e-9 && t <= 0.1) return {};
            } catch (const std::exception&) {
            }
            return "must be a number in [1e-9, 0.1] (relative to the bounding-box diagonal), got " + text;
        },
        "in [1e-9, 0.1]");

    FitCommandOptions fitopt;
    CLI::App* fit_cmd = app.add_subcommand(
        "fit", "Build the minimal quad layout (as `layout`), or take the control mesh given with --cage,\n"
               "then fit the control points of its cage refined K times so that the Catmull-Clark limit\n"
               "surface matches the mesh (Ceres, OpenSubdiv, Embree). Writes the layout files (not with\n"
               "--cage) and fitted_cage.obj, limit.ply (per-vertex distance to the\n"
               "input), deviation.ply (the input with per-vertex distance to the surface) and report.json.\n"
               "Errors are relative to the bounding-box diagonal.");
    add_mesh_output_quiet(fit_cmd, fitopt.mesh, fitopt.output_dir, fitopt.quiet);
    CLI::Option* cage_opt = fit_cmd->add_option(
        "--cage", fitopt.cage,
        "Fit this control mesh (OBJ/PLY/OFF: closed, manifold, quads or any polygons, the genus\n"
        "and components of MESH, near it) instead of building a layout: its limit surface's\n"
        "closest points on MESH start the fit. Writes fitted_cage.obj (at level 0 the cage's\n"
        "own faces), limit.ply, deviation.ply and report.json; CAGE is only read");
    for (CLI::Option* flag : add_embedding_flags(fit_cmd, fitopt.embedding)) cage_opt->excludes(flag);
    auto* level_opt = fit_cmd->add_option("--level", fitopt.level,
                                          "Refinements of the cage to fit (0 = the 8g-8 corners, or CAGE's own vertices);\n"
                                          "default 3. Levels 1..K are fitted in turn and all reported; from level 2 on, a\n"
                                          "level that measures worse than the one before is fitted again from the previous\n"
                                          "fit refined (with --cage: from level 2 on, each level starts from the previous fit)")
        ->check(CLI::Range(0, 7));
    fit_cmd->add_option("--tolerance", fitopt.tolerance,
                        "Fit levels 0, 1, 2, ... until the relative symmetric RMS error <= T (or --max-level)")
        ->check(CLI::PositiveNumber)
        ->excludes(level_opt);
    fit_cmd->add_option("--max-level", fitopt.max_level, "Highest level tried with --tolerance (default 5)")
        ->check(CLI::Range(0, 7));
    fit_cmd->add_option("--solver", fitopt.solver,
                        "How each round's linear least-squares problem is solved: direct (default: the normal\n"
                        "equations by CHOLMOD, analysed once per level) or ceres (one Levenberg-Marquardt step of\n"
                        "Ceres per round; the same fit up to rounding, several times slower)")
        ->check(CLI::IsMember({"direct", "ceres"}));
    fit_cmd->add_option("--rounds", fitopt.rounds,
                        "Rounds a level takes at most (default 16; the level asked for may take --extra-rounds\n"
                        "more), each a solve with the feet fixed, then the feet found again, while the smoothness\n"
                        "weight falls from 1e-3 to 1e-6; fewer once a round improves the data RMS by less than\n"
                        "0.2%. With 8 (and no extra rounds) botijo's level 3 fitted in 6.7 s instead of 11.7 s,\n"
                        "to relative RMS / Hausdorff 4.5e-4 / 9.3e-3 instead of 3.2e-4 / 3.9e-3")
        ->check(CLI::Range(1, 1000));
    fit_cmd->add_option("--extra-rounds", fitopt.extra_rounds,
                        "Rounds past --rounds, at most, at the final smoothness weight, while each improves\n"
                        "the data RMS by 0.2% or more (default 32; 0: none): only at the level asked for\n"
                        "(at every level with --tolerance). Botijo's level 3: relative RMS 2.7e-4 -> 2.4e-4 in\n"
                        "39 rounds; the same decimated to 10k vertices: 5.3e-4 / Hausdorff 1.2e-2 -> 3.1e-4 / 7.4e-3")
        ->check(CLI::Range(0, 1000));
    fit_cmd->add_option("--tangential-weight", fitopt.tangential_weight,
                        "Final weight, squared, of the tangential part of each input point's distance to its foot\n"
                        "on the surface (the part along the normal counts fully; round r of a level uses\n"
                        "max(W, 2^-r), point to point first; default 0.002). It sets how fast the rounds let the\n"
                        "surface slide along itself: botijo's level 3 fitted to relative RMS 2.41e-4 at 0.02 (the\n"
                        "default before), 2.29e-4 at 0.002; at 0 it can fold where no input point holds it")
        ->check(CLI::Range(0.0, 1.0));
    fit_cmd->add_option("--turned-over-weight", fitopt.turned_over_weight,
                        "Weight of the term that keeps the fitted surface from turning over against the input\n"
                        "(the middle sheet of a pleat, lying on the input where no distance sees it; default\n"
                        "0.01; 0: off). With 0.01 botijo's level-3 surface had 1.1% more area than the input\n"
                        "instead of 19% with 0, boot's 3.5% instead of 64%, at +8% and +14% RMS; skull and\n"
                        "input_wheel fitted closer. The summary and report.json's limit_tessellation give the\n"
                        "pleats left: folded_area_fraction and inverted_area_fraction")
        ->check(CLI::NonNegativeNumber);
    fit_cmd->add_flag(
        "--plane-feet-only", fitopt.plane_feet_only,
        "Measure a limit-surface sample's distance to MESH in the fit always along the normal of\n"
        "the closest triangle. By default, where the closest point lies on an edge or at a vertex\n"
        "of MESH (a convex crease, the rim of a hole), along the offset from that point, the\n"
        "direction the true distance grows in there: the surface cannot bulge past a crease unseen");
    fit_cmd->add_option("--limit-max-error", fitopt.limit_max_error,
                        "Tessellate limit.ply finely enough that its measured largest distance to the limit\n"
                        "surface is at most R of the bounding-box diagonal (default: only its RMS distance is\n"
                        "held below 10% of the fit's RMS)")
        ->check(CLI::Range(1e-9, 1.0));
    fit_cmd->add_flag("--json", fitopt.json, "Print report.json instead of the summary");
    fit_cmd->add_option("--step", fitopt.step,
                        "Also export the fitted surface as a closed B-spline solid in this STEP file (AP214),\n"
                        "as `quadcage export` does; if the export fails, nothing is written. One component only");
    fit_cmd->add_option("--iges", fitopt.iges, "... and/or in this IGES file (5.3, B-rep solid)");
    fit_cmd->add_option("--cad-tolerance", fitopt.cad_tolerance,
                        "With --step/--iges: max deviation from the limit surface near extraordinary corners,\n"
                        "relative to the diagonal (default 1e-5, at least 1e-9)")
        ->check(cad_tolerance);

    ExportOptions exportopt;
    CLI::App* export_cmd = app.add_subcommand(
        "export", "Export the surface `fit` wrote in DIR (fitted_cage.obj and report.json) as a closed B-rep\n"
                  "solid (OpenCASCADE): one bicubic B-spline face per level-0 cage quad (per quad of the cage\n"
                  "refined once if it has other faces), its boundary the four cage edges. Away from\n"
                  "extraordinary corners each face is the limit surface to rounding (uniform knots at the fit\n"
                  "level); toward them the knots are refined geometrically until the corner cells are within\n"
                  "--cad-tolerance of it. Faces are sewn, made a solid and checked (BRepCheck_Analyzer).\n"
                  "Writes DIR/surface.step unless --step/--iges name the files, and DIR/export.json (faces,\n"
                  "edges, vertices, deviation, normal jumps, sewing tolerance, validity, area, volume); a\n"
                  "summary on stdout. Nothing is written if any step fails. Exit 3: DIR holds no fit, its\n"
                  "files disagree, or the tolerance cannot be reached.");
    export_cmd->add_option("DIR", exportopt.dir, "Output directory of `quadcage fit` (one component)")->required();
    export_cmd->add_option("--step", exportopt.step, "STEP file to write (AP214)");
    export_cmd->add_option("--iges", exportopt.iges, "IGES file to write (5.3, B-rep solid)");
    export_cmd->add_option("--cad-tolerance", exportopt.cad_tolerance,
                           "Max deviation from the limit surface near extraordinary corners, relative to the\n"
                           "fit's bounding-box diagonal (default 1e-5, at least 1e-9; below 1e-9 is a usage error,\n"
                           "exit 2). The corner cells approximate OpenSubdiv's corner patch, which meets its\n"
                           "neighbours with tangent continuity only: about 1e-6 is the floor; an unreachable\n"
                           "tolerance is reported and exits 3")
        ->check(cad_tolerance);
    export_cmd->add_flag("--json", exportopt.json, "Print export.json instead of the summary");
    export_cmd->add_flag("-q,--quiet", exportopt.quiet, "No progress messages on stderr");

    CLI::App* version_cmd = app.add_subcommand(
        "version", "Print the versions of quadcage and the libraries it runs on (each checked by a call).");

    GenerateOptions gen;
    CLI::App* gen_cmd = app.add_subcommand("generate", "Write a closed test surface of known genus.");
    gen_cmd->add_option("SHAPE", gen.shape,
                        "sphere, torus, plate (a thickened plate with holes), limbs (a genus-0 body with\n"
                        "long limbs, like a cartoon figure), handles (a big smooth body with --genus small\n"
                        "handles on its top) or wheel (a disc with an axle through a hub and --genus - 1\n"
                        "holes in a ring round it)")
        ->required()
        ->check(CLI::IsMember({"sphere", "torus", "plate", "limbs", "handles", "wheel"}));
    gen_cmd->add_option("--genus,-g", gen.genus,
                        "Number of holes of the plate, of handles (handles: at most 64), or the wheel's\n"
                        "genus (its holes and the axle; 1..65)")
        ->check(CLI::Range(0, 200));
    gen_cmd->add_option("--resolution,-r", gen.resolution,
                        "Mesh resolution (plate: cells per unit; sphere, limbs: icosphere subdivisions;\n"
                        "handles: voxels per handle width, wheel: voxels per disc thickness, at least 2)")
        ->check(CLI::Range(1, 64));
    gen_cmd->add_flag("--in-a-row", gen.in_a_row, "handles: side by side along one edge of the top (genus in one region)");
    gen_cmd->add_option("--limbs", gen.limbs, "limbs: number of limbs (default 4)")->check(CLI::Range(0, 32));
    gen_cmd
        ->add_option("--bumps", gen.bumps,
                     "handles: smooth bumps and dents on the body below its top, a body with detail of\n"
                     "its own (default 0: a plain ball)")
        ->check(CLI::Range(0, 64));
    gen_cmd
        ->add_option("--fins", gen.fins,
                     "limbs, handles: thin, flat protrusions (fins; handles: on the body below its\n"
                     "middle), like a creature's (default 0)")
        ->check(CLI::Range(0, 16));
    gen_cmd->add_option("--ribs", gen.ribs, "wheel: radial ribs one cell high round the hub (default 0)")
        ->check(CLI::Range(0, 64));
    gen_cmd->add_flag(
        "--cad", gen.cad,
        "wheel: its flat faces tessellated as a CAD system exports a solid: fans of long, thin\n"
        "triangles between the vertices of their borders (input_wheel's class)");
    gen_cmd->add_option("--seed", gen.seed, "limbs: which figure; handles: where the bumps and fins go (default 1)");
    gen_cmd->add_option("-o,--output", gen.output, "Output file (.obj or .ply)")->required();

    SubdivideOptions sub;
    CLI::App* sub_cmd = app.add_subcommand(
        "subdivide", "Split every triangle 1-to-4 at edge midpoints, TIMES times (same surface, for benchmarks).");
    sub_cmd->add_option("MESH", sub.mesh, "Closed triangle mesh")->required();
    sub_cmd->add_option("-t,--times", sub.times, "Number of 1-to-4 splits")->check(CLI::Range(1, 6));
    sub_cmd->add_option("-o,--output", sub.output, "Output file (.ply or .obj)")->required();

    RenderCommandOptions render;
    CLI::App* render_cmd = app.add_subcommand(
        "render", "Draw a PNG (software renderer, no display needed), two views side by side.\n"
                  "  layout:    patches of a 'patch' face property in distinct colours, patch boundaries\n"
                  "             as lines, corners (>= 3 patches) as dots (DIR/layout.ply of `quadcage layout`);\n"
                  "  deviation: colours by a 'distance' vertex property, with a colour bar in absolute units\n"
                  "             and % of the bounding-box diagonal (DIR/deviation.ply of `quadcage fit`);\n"
                  "  plain:     any mesh, shaded.\n"
                  "  auto (default): for DIR, deviation.ply if present else layout.ply; for a file, by the\n"
                  "             properties it has.");
    render_cmd->add_option("INPUT", render.input, "Mesh file, or a directory written by layout / fit")->required();
    render_cmd->add_option("-o,--output", render.output, "Output PNG file")->required();
    render_cmd->add_option("--kind", render.kind, "layout, deviation, plain or auto")
        ->check(CLI::IsMember({"layout", "deviation", "plain", "auto"}));
    render_cmd->add_option("--size", render.size, "Image size WIDTHxHEIGHT (default 1200x600)");
    render_cmd->add_option("--title", render.title, "Title line (default: the input's name)");
    render_cmd->add_flag("-q,--quiet", render.quiet, "Print nothing on success");

    BenchCommandOptions bench;
    CLI::App* bench_cmd = app.add_subcommand(
        "bench", "Benchmark many meshes. For each: `info --json` (exit 3 -> status rejected), `layout`,\n"
                 "its picture, `fit --level K` per level with a deviation picture, and per level the peer: a\n"
                 "QuadriFlow remesh (through Blender, if `blender` is on PATH) at our control-face count,\n"
                 "fitted by `fit --cage REMESH --level 0`, with the ratios ours / peer. Every stage runs in\n"
                 "its own child process\n"
                 "with a timeout: a crash or timeout is recorded and the run goes on. A failed layout\n"
                 "skips that mesh's fits. Writes DIR/bench.csv, bench.json, bench.md, plot.png and\n"
                 "DIR/meshes/<name>/ (stage outputs, pictures, log.txt). Progress on stderr.\n"
                 "Exits 0 once the tables are written, whatever the meshes' statuses.");
    bench_cmd->add_option("PATH", bench.paths, "Mesh files, folders (their .obj/.ply/.off/.stl) or manifests (.txt, one path a line)")
        ->required();
    bench_cmd->add_option("-o,--output", bench.output_dir, "Output directory (created if missing)")->required();
    bench_cmd->add_option("--levels", bench.levels, "Fit levels, comma-separated (default 0,1,2,3; 'none': no fits)");
    bench_cmd->add_option("--tolerance", bench.tolerance, "Passed to every fit as --tolerance T (default: not passed)")
        ->check(CLI::NonNegativeNumber);
    bench_cmd->add_option("--rounds", bench.rounds,
                          "Passed to every fit, ours and the peer's, as --rounds N (default: not passed; fit's\n"
                          "default is 16 rounds a level; with 8, botijo's level 3 fits in 6.7 s instead of 11.7 s, to\n"
                          "relative RMS 4.5e-4 instead of 3.2e-4: see fit --rounds)")
        ->check(CLI::Range(1, 1000));
    bench_cmd->add_option("--turned-over-weight", bench.turned_over_weight,
                          "Passed to every fit, ours and the peer's, as --turned-over-weight W (default: not\n"
                          "passed: fit's default); 0 compares surfaces free to pleat: see fit --turned-over-weight")
        ->check(CLI::NonNegativeNumber);
    bench_cmd->add_option("-j,--jobs", bench.jobs, "Meshes processed at the same time (default 1)")->check(CLI::Range(1, 64));
    bench_cmd->add_option("--timeout", bench.timeout_seconds, "Wall-clock limit of each stage in seconds (default 1800)")
        ->check(CLI::PositiveNumber);
    bench_cmd->add_flag("--no-peer", bench.no_peer, "Do not run QuadriFlow");
    bench_cmd->add_flag("--no-pictures", bench.no_pictures, "Do not draw the layout and deviation pictures");
    add_embedding_flags(bench_cmd, bench.embedding);  // passed to our layout and fits, not to the peer's
    bench_cmd->add_option("--blender", bench.blender, "Blender executable (default: blender on PATH)");
    bench_cmd->add_option("--peer-script", bench.peer_script, "QuadriFlow script (default: PREFIX/share/quadcage/quadriflow.py beside an installed quadcage, else the\nrepository's tools/bench/quadriflow.py)");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);
        return code == 0 ? kOk : kUsage;
    }
    try {
        if (*info_cmd) return run_info(info);
        if (*version_cmd) return run_version();
        if (*cycles_cmd) return run_cycles(cycles);
        if (*layout_cmd) return run_layout(layout);
        if (*fit_cmd) return run_fit(fitopt);
        if (*export_cmd) return run_export(exportopt);
        if (*gen_cmd) return run_generate(gen);
        if (*sub_cmd) return run_subdivide(sub);
        if (*render_cmd) return run_render(render);
        if (*bench_cmd) return run_bench(bench);
    } catch (const quadcage::OutputConflict& e) {  // an output would replace an input: bad usage
        std::fprintf(stderr, "quadcage: error: %s\n", e.what());
        return kUsage;
    } catch (const quadcage::InvalidInput& e) {
        std::fprintf(stderr, "quadcage: error: %s\n", e.what());
        return kInvalidInput;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "quadcage: internal error: out of memory\n");
        return kInternalError;
    } catch (const quadcage::ResourceError& e) {  // the system's, not the input's nor a bug
        std::fprintf(stderr, "quadcage: error: %s\n", e.what());
        return kInternalError;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "quadcage: internal error: %s\n", e.what());
        return kInternalError;
    }
    return kUsage;
}
