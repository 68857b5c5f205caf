// libFuzzer target for one loader entry point, chosen at compile time (tests/fuzz/CMakeLists.txt):
//   QUADCAGE_FUZZ_OBJ / _PLY / _OFF / _STL  read_mesh() on a file of that extension, then validate()
//                                           (what `quadcage info` does with a file);
//   QUADCAGE_FUZZ_EXTRAS                    read_ply_with_extras() with 'patch' and 'distance' (`render`);
//   QUADCAGE_FUZZ_CAGE                      read_polygon_mesh() (the cage reader of `fit --cage`).
// The loaders read paths, so each input is written to a scratch file first. InvalidInput is the
// expected answer to a bad file; anything else (a crash, a sanitizer report, another exception, a
// timeout or running out of memory) is a finding.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "quadcage/core/errors.h"
#include "quadcage/core/io.h"
#include "quadcage/core/validate.h"

namespace {

#if defined(QUADCAGE_FUZZ_OBJ)
const char* const kExtension = ".obj";
#elif defined(QUADCAGE_FUZZ_PLY) || defined(QUADCAGE_FUZZ_EXTRAS)
const char* const kExtension = ".ply";
#elif defined(QUADCAGE_FUZZ_OFF)
const char* const kExtension = ".off";
#elif defined(QUADCAGE_FUZZ_STL)
const char* const kExtension = ".stl";
#elif defined(QUADCAGE_FUZZ_CAGE)
const char* const kExtension = ".obj";
#else
#error "define one of QUADCAGE_FUZZ_OBJ, _PLY, _OFF, _STL, _EXTRAS, _CAGE"
#endif

std::string scratch_file() {
    static const std::string path = [] {
        const std::string p = (std::filesystem::temp_directory_path() /
                               ("quadcage_fuzz_" + std::to_string(::getpid()) + kExtension))
                                  .string();
        static std::string keep = p;
        std::atexit([] { std::remove(keep.c_str()); });
        return p;
    }();
    return path;
}

void load(const std::string& path) {
#if defined(QUADCAGE_FUZZ_EXTRAS)
    quadcage::PlyExtras extras;
    extras.face_int_name = "patch";
    extras.vertex_float_name = "distance";
    const quadcage::Mesh mesh = quadcage::read_ply_with_extras(path, extras);
    if (!extras.face_ints.empty() && extras.face_ints.size() != mesh.triangles.size()) std::abort();
    if (!extras.vertex_floats.empty() && extras.vertex_floats.size() != mesh.points.size()) std::abort();
#elif defined(QUADCAGE_FUZZ_CAGE)
    const quadcage::PolygonMesh cage = quadcage::read_polygon_mesh(path);
    for (const auto& face : cage.faces)
        if (face.size() < 3) std::abort();
#else
    quadcage::LoadInfo info;
    const quadcage::Mesh mesh = quadcage::read_mesh(path, &info);
    (void)quadcage::validate(mesh);
#endif
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string& path = scratch_file();
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) std::abort();
    if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
    std::fclose(f);
    try {
        load(path);
    } catch (const quadcage::InvalidInput&) {
        // The expected answer to a bad file.
    }
    return 0;
}
