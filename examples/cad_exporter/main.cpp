// cad_exporter MESH OUTDIR [LEVEL]
//
// The smallest program a CAD exporter starts from: a closed triangle mesh in, a fitted
// Catmull-Clark surface out, through quadcage's library alone (no CLI).
//   1. read the mesh and prepare it for quadding (validate, orient, split into components);
//   2. fit_cage(): minimal quad layout + Catmull-Clark fit at LEVEL (default 2), with the same
//      default options as `quadcage fit MESH --level LEVEL`, so both give the same control mesh;
//   3. evaluate position and normal on the limit surface at a grid of (face, u, v) points and write
//      them to OUTDIR/points.csv (face,u,v,x,y,z,nx,ny,nz; 17 significant digits);
//   4. write the control mesh to OUTDIR/control_mesh.obj (its Catmull-Clark limit is the surface).
// Exit codes as the CLI's: 0 ok, 2 bad usage, 3 invalid input, 1 anything else.

#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <string>

#include "quadcage/core/errors.h"
#include "quadcage/core/io.h"
#include "quadcage/core/validate.h"
#include "quadcage/fit/fit.h"
#include "quadcage/fit/outputs.h"

namespace {

constexpr int kSamplesPerSide = 4;  // evaluation grid per control face: 4 x 4 points, one per cell
// Where in its cell each point lies: an irrational fraction, so that no point falls on a vertex of a
// uniform tessellation of the face (limit.ply's), where a check against the tessellation would
// measure nothing.
const double kCellOffset = 0.5 / std::sqrt(2.0);

int run(const std::string& mesh_path, const std::string& out_dir, int level) {
    namespace fit = quadcage::fit;

    // 1. Load and prepare. prepare_for_quadding() throws InvalidInput for open, non-manifold or
    //    non-orientable meshes; a valid mesh may still have several components (take the first).
    const quadcage::Mesh input = quadcage::read_mesh(mesh_path);
    const quadcage::PreparedMesh prepared = quadcage::prepare_for_quadding(input, mesh_path);
    if (prepared.components.size() > 1)
        std::fprintf(stderr, "cad_exporter: %zu components, fitting the first\n", prepared.components.size());
    const quadcage::Mesh& mesh = prepared.components.front();

    // 2. Layout + fit. Default options, except the level (FitMode::Level is the default mode).
    quadcage::layout::QuadLayoutOptions layout_options;
    fit::FitOptions fit_options;
    fit_options.level = level;
    const fit::CageFit result = fit::fit_cage(mesh, layout_options, fit_options);

    // The fitted surface is an immutable, shared evaluator: copies are cheap and evaluate() may be
    // called from several threads at once.
    const fit::FittedSurface& surface = result.fit.surface;
    const quadcage::subdiv::QuadMesh& control = surface.control_mesh();

    // 3. Positions and unit normals at a grid of points on every control face. (u, v) are the
    //    face's own parameters in [0, 1]^2; the normal is du x dv normalised, outward.
    std::filesystem::create_directories(out_dir);
    const std::string csv_path = (std::filesystem::path(out_dir) / "points.csv").string();
    std::ofstream csv(csv_path);
    csv << "face,u,v,x,y,z,nx,ny,nz\n" << std::setprecision(17);
    long long points = 0;
    for (int f = 0; f < control.num_quads(); ++f)
        for (int i = 0; i < kSamplesPerSide; ++i)
            for (int j = 0; j < kSamplesPerSide; ++j) {
                const double u = (i + kCellOffset) / kSamplesPerSide, v = (j + kCellOffset) / kSamplesPerSide;
                const quadcage::subdiv::FacePoint p{f, u, v};
                const quadcage::subdiv::LimitPoint s = surface.evaluate(p);
                csv << p.face << ',' << p.u << ',' << p.v << ',' << s.position.x << ',' << s.position.y << ','
                    << s.position.z << ',' << s.normal.x << ',' << s.normal.y << ',' << s.normal.z << '\n';
                ++points;
            }
    csv.close();
    if (!csv) throw quadcage::InvalidInput("cannot write " + csv_path);

    // 4. The control mesh (OBJ, 17 significant digits): what a CAD tool subdivides or converts.
    fit::write_quad_obj((std::filesystem::path(out_dir) / "control_mesh.obj").string(), control);

    const fit::LevelReport& last = result.fit.levels.back();
    std::printf("cad_exporter: %s: genus %d, %d-quad cage, fitted at level %d\n", mesh_path.c_str(),
                prepared.report.components.front().genus, surface.cage_quads(), surface.level());
    std::printf("control mesh: %d faces, %d vertices\n", control.num_quads(), control.num_vertices());
    std::printf("points: %lld\n", points);
    std::printf("relative RMS: %.6g (Hausdorff %.6g of the bounding-box diagonal)\n", last.relative.rms,
                last.relative.hausdorff);
    std::printf("wrote %s/points.csv, %s/control_mesh.obj\n", out_dir.c_str(), out_dir.c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 3 || argc > 4) {
        std::fprintf(stderr, "usage: cad_exporter MESH OUTDIR [LEVEL]   (LEVEL: 1..%d, default 2)\n",
                     quadcage::fit::kMaxFitLevel);
        return 2;
    }
    int level = 2;
    if (argc == 4) {
        try {
            level = std::stoi(argv[3]);
        } catch (const std::exception&) {
            std::fprintf(stderr, "cad_exporter: LEVEL must be a whole number, not '%s'\n", argv[3]);
            return 2;
        }
    }
    try {
        return run(argv[1], argv[2], level);
    } catch (const quadcage::InvalidInput& e) {  // the input or the options: the user can act on it
        std::fprintf(stderr, "cad_exporter: %s\n", e.what());
        return 3;
    } catch (const std::exception& e) {  // quadcage::InternalError or anything else
        std::fprintf(stderr, "cad_exporter: internal error: %s\n", e.what());
        return 1;
    }
}
