// `quadcage render`: pictures of a layout, a deviation map or a plain mesh.

#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "quadcage/core/errors.h"
#include "quadcage/core/io.h"
#include "quadcage/render/figures.h"

namespace quadcage::cli {
namespace {

namespace fs = std::filesystem;

// "1200x600" -> width, height.
void parse_size(const std::string& text, int& width, int& height) {
    int w = 0, h = 0;
    char x = 0, rest = 0;
    if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &rest) != 3 || (x != 'x' && x != 'X'))
        throw InvalidInput("--size '" + text + "': expected WIDTHxHEIGHT, e.g. 1200x600");
    width = w;
    height = h;
}

}  // namespace

int run_render(const RenderCommandOptions& o) {
    std::string kind = o.kind;
    std::string mesh_path = o.input;
    std::error_code ec;
    if (fs::is_directory(o.input, ec)) {
        const fs::path dir(o.input);
        if (kind == "auto") kind = fs::exists(dir / "deviation.ply") ? "deviation" : "layout";
        if (kind == "plain")
            throw InvalidInput(o.input + ": a directory; --kind plain needs a mesh file (e.g. " +
                               (dir / "limit.ply").string() + ")");
        mesh_path = (dir / (kind == "layout" ? "layout.ply" : "deviation.ply")).string();
        if (!fs::exists(mesh_path))
            throw InvalidInput(mesh_path + ": not found (a directory written by `quadcage " +
                               (kind == "layout" ? "layout" : "fit") + "` holds it)");
    } else if (!fs::exists(o.input, ec)) {
        throw InvalidInput(o.input + ": no such file or directory");
    }

    if (fs::exists(o.output, ec) && fs::equivalent(mesh_path, o.output, ec))
        throw OutputConflict(o.output + ": this output would replace the input " + mesh_path +
                             "; choose another output file (-o)");
    output_extension(o.output, {".png"});  // render writes PNG

    render::FigureOptions fig;
    parse_size(o.size, fig.width, fig.height);
    if (const std::string e = fig.validate(); !e.empty()) throw InvalidInput("--size " + o.size + ": " + e);
    fig.title = o.title.empty() ? fs::path(o.input).filename().string() : o.title;
    if (fig.title.empty()) fig.title = o.input;

    PlyExtras extras;
    extras.face_int_name = "patch";
    extras.vertex_float_name = "distance";
    // Not regular (a FIFO would block this peek): read_mesh() refuses it with a clear message.
    const bool is_ply = fs::is_regular_file(mesh_path, ec) && [&] {
        std::FILE* f = std::fopen(mesh_path.c_str(), "rb");
        char magic[4] = {0, 0, 0, 0};
        const bool ok = f && std::fread(magic, 1, 3, f) == 3 && std::string(magic, 3) == "ply";
        if (f) std::fclose(f);
        return ok;
    }();
    const Mesh mesh = is_ply ? read_ply_with_extras(mesh_path, extras) : read_mesh(mesh_path);
    if (kind == "auto")
        kind = !extras.face_ints.empty() ? "layout" : !extras.vertex_floats.empty() ? "deviation" : "plain";

    render::Image image(1, 1);
    if (kind == "layout") {
        if (extras.face_ints.empty())
            throw InvalidInput(mesh_path + ": has no int face property 'patch' (written by `quadcage layout`; "
                               "`quadcage cycles` writes none): use --kind plain");
        image = render::layout_figure(mesh, extras.face_ints, fig);
    } else if (kind == "deviation") {
        if (extras.vertex_floats.empty())
            throw InvalidInput(mesh_path + ": has no float vertex property 'distance' (written by `quadcage fit`): "
                               "use --kind plain");
        // `quadcage fit` writes 'distance' to the fitted surface on deviation.ply (the input's
        // vertices) and to the input on limit.ply (the surface's vertices).
        const std::string name = fs::path(mesh_path).filename().string();
        fig.distance_meaning = name == "deviation.ply" ? "distance to the fitted surface"
                               : name == "limit.ply"   ? "distance to the input mesh"
                                                       : "vertex property 'distance'";
        image = render::deviation_figure(mesh, extras.vertex_floats, fig);
    } else {
        image = render::plain_figure(mesh, fig);
    }
    render::write_png(o.output, image);
    if (!o.quiet)
        std::printf("%s: %s picture of %s (%dx%d)\n", o.output.c_str(), kind.c_str(), mesh_path.c_str(), image.width(),
                    image.height());
    return kOk;
}

}  // namespace quadcage::cli
