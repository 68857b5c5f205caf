#pragma once
// The fitted surface as a closed B-rep solid, written as STEP or IGES (issue 22). The only module
// that uses OpenCASCADE; its types stay out of this header.

#include <memory>
#include <string>
#include <vector>

#include "quadcage/fit/bspline_patches.h"

namespace quadcage::cad {

/// Options for make_solid().
struct SolidOptions {
    /// Sewing tolerance in the units of the surface; 0: BSplinePatches::tolerance. >= 0. The
    /// patches share their boundary rows exactly, so sewing needs next to nothing.
    double sewing_tolerance = 0;
    std::string validate() const;  ///< Empty if valid, else what is wrong.
};

/// What the B-rep is and how it was checked.
struct SolidReport {
    int faces = 0;                ///< B-rep faces (one per patch when sewing worked).
    int edges = 0;                ///< Distinct B-rep edges.
    int vertices = 0;             ///< Distinct B-rep vertices.
    int shells = 0;               ///< Shells after sewing (1 for a closed surface).
    int solids = 0;               ///< Solids made (1).
    int free_edges = 0;           ///< Edges with one face only (0 when closed).
    bool closed = false;          ///< Every edge has exactly two faces.
    bool valid = false;           ///< OCCT's BRepCheck_Analyzer verdict on the solid.
    double sewing_tolerance = 0;  ///< Used for sewing.
    double max_tolerance = 0;     ///< Largest tolerance of an edge or vertex of the result.
    double area = 0;              ///< Surface area (BRepGProp).
    double volume = 0;            ///< Enclosed volume (BRepGProp), positive: faces oriented outward.
    // From the patches (bspline_patches()):
    int depth = 0;                           ///< Knot refinements toward extraordinary corners.
    int knots = 0;                           ///< Knots per direction (with the end multiplicities).
    double tolerance = 0;                    ///< Deviation allowed (absolute).
    double max_deviation = 0;                ///< Measured max distance to the limit surface (absolute).
    double max_deviation_regular = 0;        ///< ... in the polynomial cells.
    double max_deviation_corner = 0;         ///< ... in the corner cells.
    double max_normal_jump_regular_deg = 0;  ///< Across patch sides away from extraordinary corners.
    double max_normal_jump_corner_deg = 0;   ///< Across patch sides along corner cells.
    double diagonal = 0;                     ///< The length relative figures use.
    double seconds = 0;                      ///< Building the solid (not the patches), of which:
    double sewing_seconds = 0;               ///< ... faces and sewing,
    double check_seconds = 0;                ///< ... BRepCheck_Analyzer,
    double properties_seconds = 0;           ///< ... area and volume.
    std::string message;                     ///< One line.
    /// "valid closed solid", "closed but invalid (BRepCheck_Analyzer)" or "not closed".
    const char* verdict() const;
    /// The report as a JSON object (relative figures divided by `diagonal` included).
    std::string to_json(int indent = 2) const;
};

/// The report of one export (`quadcage export`, `fit --step/--iges`): the solid's, the patches'
/// and the files written.
struct ExportReport {
    SolidReport solid;
    double patch_seconds = 0;          ///< fit::bspline_patches().
    double exactness = 0;              ///< fit::BSplinePatches::measurement.exactness.
    long long deviation_samples = 0;   ///< fit::BSplinePatches::measurement.samples.
    struct File {
        std::string kind;              ///< "step" or "iges".
        std::string path;              ///< As the user named it.
        long long bytes = 0;
    };
    std::vector<File> files;           ///< In the order written.
    double total_seconds = 0;          ///< Patches, solid and files.
    std::string fit_dir;               ///< `quadcage export`: the fit's directory (empty inside fit's report).
    int level = -1;                    ///< With fit_dir: the fitted level.
    /// A JSON object, keys sorted: the solid's fields (SolidReport::to_json()), patch_seconds,
    /// exactness, deviation_samples, files {kind: {path, bytes}}, total_seconds and, with fit_dir,
    /// command ("export"), fit and level.
    std::string to_json(int indent = 2) const;
};

/// A B-rep solid held by OpenCASCADE (opaque here). Movable, not copyable.
class Solid {
public:
    Solid();
    ~Solid();
    Solid(Solid&&) noexcept;
    Solid& operator=(Solid&&) noexcept;
    Solid(const Solid&) = delete;
    Solid& operator=(const Solid&) = delete;
    const SolidReport& report() const { return report_; }

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    SolidReport report_;
    friend Solid make_solid(const fit::BSplinePatches&, const SolidOptions&);
    friend void write_step(const Solid&, const std::string&);
    friend void write_iges(const Solid&, const std::string&);
};

/// One Geom_BSplineSurface face per patch (no trimming: its boundary is the four cage edges),
/// sewn into a shell (BRepBuilderAPI_Sewing), made a solid (BRepBuilderAPI_MakeSolid, oriented
/// outward), checked (BRepCheck_Analyzer) and measured (BRepGProp). A shell that does not close,
/// or a solid OCCT finds invalid, is reported (closed, valid), not thrown.
/// \throw InvalidInput if the options are invalid or there are no patches.
Solid make_solid(const fit::BSplinePatches& patches, const SolidOptions& options = {});

/// Writes the solid as STEP (AP214, STEPControl_Writer) to `path`.
/// \throw InvalidInput (naming the file) if OCCT cannot transfer or write it.
void write_step(const Solid& solid, const std::string& path);

/// Writes the solid as IGES (5.3, B-rep mode: manifold solid B-rep object) to `path`.
/// \throw InvalidInput (naming the file) if OCCT cannot transfer or write it.
void write_iges(const Solid& solid, const std::string& path);

/// What a STEP or IGES file holds, read back with OCCT's own readers (tests and checks).
struct ReadBack {
    int solids = 0, shells = 0, faces = 0, edges = 0, free_edges = 0;
    bool closed = false;  ///< The faces form a closed shell (every edge has two faces).
    bool valid = false;   ///< BRepCheck_Analyzer on the whole shape.
    double area = 0, volume = 0;
    /// The faces' B-spline surfaces (in file order) evaluated at (u, v) in [0,1]^2 of each face's
    /// parameter range: used to compare the file with the patches.
    std::vector<std::vector<Vec3>> samples;
};

/// Reads a STEP file (by extension .step/.stp) or IGES (.igs/.iges); for IGES, whose faces may come
/// as separate faces, they are sewn with `sewing_tolerance` first. Samples `grid` x `grid` points
/// per face. \throw InvalidInput if the file cannot be read.
ReadBack read_back(const std::string& path, int grid = 0, double sewing_tolerance = 1e-6);

/// "OpenCASCADE X.Y.Z", from the linked library (OCCT's run-time version string).
std::string occt_version();

}  // namespace quadcage::cad
