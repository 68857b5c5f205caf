#pragma once
// Which meshes a benchmark run covers: files, folders of meshes and manifests, expanded to a list.

#include <string>
#include <vector>

namespace quadcage::bench {

/// One mesh of a benchmark run.
struct BenchInput {
    std::string path;      ///< The mesh file as it will be passed to the stages.
    std::string name;      ///< Display name: the file name without extension (unique in the run).
    std::string dir_name;  ///< `name` made safe as a directory name (letters, digits, '-', '_', '.').
};

/// True for the mesh extensions a folder is scanned for: .obj, .ply, .off, .stl (any case).
bool is_mesh_file_name(const std::string& path);

/// Expands the PATH arguments of `quadcage bench`, in order:
///  - a mesh file is taken as it is (any extension read_mesh() can detect);
///  - a folder contributes every .obj/.ply/.off/.stl file directly in it, sorted by file name;
///  - a `.txt` file is a manifest: one path per line, relative to the manifest's folder unless
///    absolute; blank lines and lines starting with '#' are skipped; listed folders and manifests are
///    expanded as above (a manifest including itself is an error).
/// A mesh reached twice (same canonical path) is kept once. Names that collide (bunny.obj and
/// bunny.off) get "_2", "_3", ... in order.
/// \throw InvalidInput naming the PATH (and manifest line) if it does not exist, a folder holds no
///        mesh, a manifest cannot be read or lists nothing, or nothing at all is left.
std::vector<BenchInput> expand_inputs(const std::vector<std::string>& paths);

}  // namespace quadcage::bench
