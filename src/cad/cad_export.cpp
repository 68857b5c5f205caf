#include "quadcage/cad/cad_export.h"

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeSolid.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepGProp.hxx>
#include <BRepLib.hxx>
#include <BRep_Tool.hxx>
#include <GProp_GProps.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_Surface.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Reader.hxx>
#include <IGESControl_Writer.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Precision.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Reader.hxx>
#include <STEPControl_Writer.hxx>
#include <Standard_Failure.hxx>
#include <Standard_Version.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Solid.hxx>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <nlohmann/json.hpp>

#include "quadcage/core/errors.h"

namespace quadcage::cad {

struct Solid::Impl {
    TopoDS_Shape shape;
};

Solid::Solid() : impl_(std::make_unique<Impl>()) {}
Solid::~Solid() = default;
Solid::Solid(Solid&&) noexcept = default;
Solid& Solid::operator=(Solid&&) noexcept = default;

namespace {

// OCCT's translators keep global settings and print to stdout by default: set them up once, quietly.
void init_occt() {
    static std::once_flag once;
    std::call_once(once, [] {
        Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_Printer));
        STEPControl_Controller::Init();
        IGESControl_Controller::Init();
    });
}

std::string extension(const std::string& path) {
    const size_t dot = path.find_last_of('.');
    std::string e = dot == std::string::npos ? "" : path.substr(dot + 1);
    std::transform(e.begin(), e.end(), e.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return e;
}

struct Topology {
    int solids = 0, shells = 0, faces = 0, edges = 0, vertices = 0, free_edges = 0;
};

Topology topology(const TopoDS_Shape& shape) {
    Topology t;
    TopTools_IndexedMapOfShape m;
    TopExp::MapShapes(shape, TopAbs_SOLID, m);
    t.solids = m.Extent();
    m.Clear();
    TopExp::MapShapes(shape, TopAbs_SHELL, m);
    t.shells = m.Extent();
    m.Clear();
    TopExp::MapShapes(shape, TopAbs_FACE, m);
    t.faces = m.Extent();
    m.Clear();
    TopExp::MapShapes(shape, TopAbs_VERTEX, m);
    t.vertices = m.Extent();
    TopTools_IndexedDataMapOfShapeListOfShape edge_faces;
    TopExp::MapShapesAndAncestors(shape, TopAbs_EDGE, TopAbs_FACE, edge_faces);
    t.edges = edge_faces.Extent();
    for (int i = 1; i <= edge_faces.Extent(); ++i) {
        if (BRep_Tool::Degenerated(TopoDS::Edge(edge_faces.FindKey(i)))) continue;
        TopTools_IndexedMapOfShape faces;  // a seam lists its face twice
        for (const TopoDS_Shape& f : edge_faces(i)) faces.Add(f);
        if (faces.Extent() < 2 && edge_faces(i).Extent() < 2) ++t.free_edges;
    }
    return t;
}

void mass_properties(const TopoDS_Shape& shape, double& area, double& volume) {
    GProp_GProps s, v;
    BRepGProp::SurfaceProperties(shape, s);
    BRepGProp::VolumeProperties(shape, v);
    area = s.Mass();
    volume = v.Mass();
}

}  // namespace

std::string SolidOptions::validate() const {
    if (!(sewing_tolerance >= 0) || !std::isfinite(sewing_tolerance))
        return "sewing_tolerance must be finite and >= 0";
    return {};
}

namespace {

// The fields of a SolidReport, into an ordered (SolidReport::to_json) or sorted (ExportReport) object.
template <class Json>
void put_solid(const SolidReport& r, Json& j) {
    const double d = r.diagonal > 0 ? r.diagonal : 1;
    j["faces"] = r.faces;
    j["edges"] = r.edges;
    j["vertices"] = r.vertices;
    j["shells"] = r.shells;
    j["solids"] = r.solids;
    j["free_edges"] = r.free_edges;
    j["closed"] = r.closed;
    j["valid"] = r.valid;
    j["verdict"] = r.verdict();
    j["sewing_tolerance"] = r.sewing_tolerance;
    j["max_tolerance"] = r.max_tolerance;
    j["area"] = r.area;
    j["volume"] = r.volume;
    j["knot_depth"] = r.depth;
    j["knots_per_direction"] = r.knots;
    j["diagonal"] = r.diagonal;
    j["tolerance"] = r.tolerance;
    j["relative_tolerance"] = r.tolerance / d;
    j["max_deviation"] = r.max_deviation;
    j["relative_max_deviation"] = r.max_deviation / d;
    j["max_deviation_regular"] = r.max_deviation_regular;
    j["max_deviation_corner"] = r.max_deviation_corner;
    j["max_normal_jump_deg"] = {{"regular", r.max_normal_jump_regular_deg},
                                {"corner", r.max_normal_jump_corner_deg}};
    j["seconds"] = r.seconds;
    j["stage_seconds"] = {
        {"sewing", r.sewing_seconds}, {"check", r.check_seconds}, {"properties", r.properties_seconds}};
    j["message"] = r.message;
}

}  // namespace

const char* SolidReport::verdict() const {
    return valid && closed ? "valid closed solid" : (closed ? "closed but invalid (BRepCheck_Analyzer)" : "not closed");
}

std::string SolidReport::to_json(int indent) const {
    nlohmann::ordered_json j;
    put_solid(*this, j);
    return j.dump(indent);
}

std::string ExportReport::to_json(int indent) const {
    nlohmann::json j;
    put_solid(solid, j);
    j["patch_seconds"] = patch_seconds;
    j["exactness"] = exactness;
    j["deviation_samples"] = deviation_samples;
    nlohmann::json written = nlohmann::json::object();
    for (const File& f : files) written[f.kind] = {{"path", f.path}, {"bytes", f.bytes}};
    j["files"] = written;
    j["total_seconds"] = total_seconds;
    if (!fit_dir.empty()) {
        j["command"] = "export";
        j["fit"] = fit_dir;
        j["level"] = level;
    }
    return j.dump(indent);
}

Solid make_solid(const fit::BSplinePatches& patches, const SolidOptions& options) {
    if (const std::string why = options.validate(); !why.empty()) throw InvalidInput("make_solid: " + why);
    if (patches.patches.empty()) throw InvalidInput("make_solid: no patches");
    init_occt();
    const auto t0 = std::chrono::steady_clock::now();
    Solid out;
    SolidReport& r = out.report_;
    r.sewing_tolerance = options.sewing_tolerance > 0 ? options.sewing_tolerance : patches.tolerance;
    if (!(r.sewing_tolerance > 0)) r.sewing_tolerance = 1e-7;
    // Knots with multiplicities, shared by every patch and both directions.
    std::vector<double> values;
    std::vector<int> mults;
    for (double k : patches.knots) {
        if (!values.empty() && values.back() == k)
            ++mults.back();
        else
            values.push_back(k), mults.push_back(1);
    }
    TColStd_Array1OfReal knots(1, static_cast<int>(values.size()));
    TColStd_Array1OfInteger multiplicities(1, static_cast<int>(values.size()));
    for (size_t i = 0; i < values.size(); ++i) {
        knots(static_cast<int>(i) + 1) = values[i];
        multiplicities(static_cast<int>(i) + 1) = mults[i];
    }
    try {
        BRepBuilderAPI_Sewing sewing(r.sewing_tolerance);
        for (const fit::BSplinePatch& p : patches.patches) {
            TColgp_Array2OfPnt poles(1, p.n, 1, p.n);
            for (int j = 0; j < p.n; ++j)
                for (int i = 0; i < p.n; ++i) {
                    const Vec3& x = p.at(i, j);
                    poles(i + 1, j + 1) = gp_Pnt(x.x, x.y, x.z);
                }
            Handle(Geom_BSplineSurface) surface = new Geom_BSplineSurface(
                poles, knots, knots, multiplicities, multiplicities, patches.degree, patches.degree);
            sewing.Add(BRepBuilderAPI_MakeFace(surface, Precision::Confusion()).Face());
        }
        sewing.Perform();
        const TopoDS_Shape sewn = sewing.SewedShape();
        const Topology ts = topology(sewn);
        r.shells = ts.shells;
        TopoDS_Shape result = sewn;
        if (ts.shells == 1 && ts.free_edges == 0) {
            TopExp_Explorer shells(sewn, TopAbs_SHELL);
            BRepBuilderAPI_MakeSolid make(TopoDS::Shell(shells.Current()));
            if (make.IsDone()) {
                TopoDS_Solid solid = make.Solid();
                BRepLib::OrientClosedSolid(solid);
                result = solid;
            }
        }
        r.sewing_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const Topology t = topology(result);
        r.solids = t.solids;
        r.faces = t.faces;
        r.edges = t.edges;
        r.vertices = t.vertices;
        r.free_edges = t.free_edges;
        r.closed = t.solids == 1 && t.free_edges == 0 && t.faces > 0;
        const auto t1 = std::chrono::steady_clock::now();
        r.valid = BRepCheck_Analyzer(result).IsValid();
        const auto t2 = std::chrono::steady_clock::now();
        r.check_seconds = std::chrono::duration<double>(t2 - t1).count();
        r.max_tolerance = std::max(BRep_Tool::MaxTolerance(result, TopAbs_EDGE),
                                   BRep_Tool::MaxTolerance(result, TopAbs_VERTEX));
        mass_properties(result, r.area, r.volume);
        r.properties_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t2).count();
        out.impl_->shape = result;
    } catch (const Standard_Failure& e) {
        throw InvalidInput(std::string("make_solid: OpenCASCADE failed: ") + e.GetMessageString());
    }
    r.depth = patches.depth;
    r.knots = static_cast<int>(patches.knots.size());
    r.tolerance = patches.tolerance;
    r.diagonal = patches.diagonal;
    r.max_deviation = patches.measurement.max_deviation;
    r.max_deviation_regular = patches.measurement.max_deviation_regular;
    r.max_deviation_corner = patches.measurement.max_deviation_corner;
    r.max_normal_jump_regular_deg = patches.measurement.max_normal_jump_regular_deg;
    r.max_normal_jump_corner_deg = patches.measurement.max_normal_jump_corner_deg;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    char line[300];
    std::snprintf(line, sizeof line,
                  "%d faces, %d edges, %d vertices: %s; max deviation %.3g of the diagonal", r.faces, r.edges,
                  r.vertices,
                  r.valid && r.closed ? "valid closed solid"
                                      : (r.closed ? "closed, but OCCT finds it invalid" : "not closed"),
                  r.max_deviation / (r.diagonal > 0 ? r.diagonal : 1));
    r.message = line;
    return out;
}

void write_step(const Solid& solid, const std::string& path) {
    init_occt();
    try {
        STEPControl_Writer writer;
        Interface_Static::SetCVal("write.step.schema", "AP214IS");
        Interface_Static::SetCVal("write.step.product.name", "quadcage fitted surface");
        if (writer.Transfer(solid.impl_->shape, STEPControl_AsIs) != IFSelect_RetDone)
            throw InvalidInput(path + ": OpenCASCADE could not translate the solid to STEP");
        if (writer.Write(path.c_str()) != IFSelect_RetDone)
            throw InvalidInput(path + ": cannot write the STEP file");
    } catch (const Standard_Failure& e) {
        throw InvalidInput(path + ": OpenCASCADE failed writing STEP: " + e.GetMessageString());
    }
}

void write_iges(const Solid& solid, const std::string& path) {
    init_occt();
    try {
        Interface_Static::SetIVal("write.iges.brep.mode", 1);
        IGESControl_Writer writer("MM", 1);
        if (!writer.AddShape(solid.impl_->shape))
            throw InvalidInput(path + ": OpenCASCADE could not translate the solid to IGES");
        writer.ComputeModel();
        if (!writer.Write(path.c_str())) throw InvalidInput(path + ": cannot write the IGES file");
    } catch (const Standard_Failure& e) {
        throw InvalidInput(path + ": OpenCASCADE failed writing IGES: " + e.GetMessageString());
    }
}

std::string occt_version() {
    // A call into the library: the area of a unit square as a degree-1 B-spline face.
    double area = 0;
    try {
        TColgp_Array2OfPnt poles(1, 2, 1, 2);
        poles(1, 1) = gp_Pnt(0, 0, 0), poles(2, 1) = gp_Pnt(1, 0, 0), poles(1, 2) = gp_Pnt(0, 1, 0), poles(2, 2) = gp_Pnt(1, 1, 0);
        TColStd_Array1OfReal k(1, 2);
        TColStd_Array1OfInteger m(1, 2);
        k(1) = 0, k(2) = 1, m(1) = 2, m(2) = 2;
        GProp_GProps props;
        BRepGProp::SurfaceProperties(BRepBuilderAPI_MakeFace(new Geom_BSplineSurface(poles, k, k, m, m, 1, 1), 1e-7).Face(), props);
        area = props.Mass();
    } catch (const Standard_Failure&) {
        return std::string("OpenCASCADE ") + OCC_VERSION_COMPLETE + " (test face: FAILED)";
    }
    char line[80];
    std::snprintf(line, sizeof line, " (unit B-spline face: area %.6g)", area);
    return std::string("OpenCASCADE ") + OCC_VERSION_COMPLETE + line;
}

ReadBack read_back(const std::string& path, int grid, double sewing_tolerance) {
    init_occt();
    const std::string ext = extension(path);
    ReadBack out;
    try {
        TopoDS_Shape shape;
        if (ext == "step" || ext == "stp") {
            STEPControl_Reader reader;
            if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
                throw InvalidInput(path + ": OpenCASCADE cannot read it as STEP");
            reader.TransferRoots();
            shape = reader.OneShape();
        } else if (ext == "igs" || ext == "iges") {
            IGESControl_Reader reader;
            if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
                throw InvalidInput(path + ": OpenCASCADE cannot read it as IGES");
            reader.TransferRoots();
            shape = reader.OneShape();
            if (topology(shape).solids == 0) {
                BRepBuilderAPI_Sewing sewing(sewing_tolerance);
                sewing.Add(shape);
                sewing.Perform();
                shape = sewing.SewedShape();
                TopExp_Explorer shells(shape, TopAbs_SHELL);
                if (shells.More() && topology(shape).shells == 1) {
                    BRepBuilderAPI_MakeSolid make(TopoDS::Shell(shells.Current()));
                    if (make.IsDone()) {
                        TopoDS_Solid s = make.Solid();
                        BRepLib::OrientClosedSolid(s);
                        shape = s;
                    }
                }
            }
        } else {
            throw InvalidInput(path + ": not a .step/.stp or .igs/.iges file");
        }
        if (shape.IsNull()) throw InvalidInput(path + ": holds no shape");
        const Topology t = topology(shape);
        out.solids = t.solids;
        out.shells = t.shells;
        out.faces = t.faces;
        out.edges = t.edges;
        out.free_edges = t.free_edges;
        out.closed = t.faces > 0 && t.free_edges == 0;
        out.valid = BRepCheck_Analyzer(shape).IsValid();
        mass_properties(shape, out.area, out.volume);
        if (grid > 0)
            for (TopExp_Explorer f(shape, TopAbs_FACE); f.More(); f.Next()) {
                Handle(Geom_Surface) s = BRep_Tool::Surface(TopoDS::Face(f.Current()));
                double u0, u1, v0, v1;
                s->Bounds(u0, u1, v0, v1);
                std::vector<Vec3> pts;
                for (int i = 0; i <= grid; ++i)
                    for (int j = 0; j <= grid; ++j) {
                        const gp_Pnt p = s->Value(u0 + (u1 - u0) * i / grid, v0 + (v1 - v0) * j / grid);
                        pts.push_back({p.X(), p.Y(), p.Z()});
                    }
                out.samples.push_back(std::move(pts));
            }
    } catch (const Standard_Failure& e) {
        throw InvalidInput(path + ": OpenCASCADE failed reading it: " + e.GetMessageString());
    }
    return out;
}

}  // namespace quadcage::cad
