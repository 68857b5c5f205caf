// Benchmark helper: a closed triangle mesh decimated to a vertex count by OpenMesh's quadric
// decimater (with normal-flip and aspect-ratio guards), as a coarser scan of the same shape would be.
// OpenMesh's collapses keep the surface's topology (the link condition), so the genus stays.
// Used by tools/bench/decimated.sh.
//
//   decimate_bench IN OUT VERTICES

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModAspectRatioT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <cstdio>
#include <cstdlib>

int main(int argc, char** argv) {
    using Mesh = OpenMesh::TriMesh_ArrayKernelT<>;
    if (argc != 4 || std::atoi(argv[3]) < 4) {
        std::fprintf(stderr, "usage: decimate_bench IN OUT VERTICES (VERTICES >= 4)\n");
        return 2;
    }
    Mesh mesh;
    if (!OpenMesh::IO::read_mesh(mesh, argv[1])) {
        std::fprintf(stderr, "decimate_bench: cannot read %s\n", argv[1]);
        return 3;
    }
    OpenMesh::Decimater::DecimaterT<Mesh> decimater(mesh);
    OpenMesh::Decimater::ModQuadricT<Mesh>::Handle quadric;
    OpenMesh::Decimater::ModNormalFlippingT<Mesh>::Handle normals;
    OpenMesh::Decimater::ModAspectRatioT<Mesh>::Handle aspect;
    decimater.add(quadric);
    decimater.add(normals);
    decimater.add(aspect);
    decimater.module(aspect).set_aspect_ratio(5.0);  // no collapse that leaves a triangle thinner
    decimater.module(aspect).set_binary(true);
    if (!decimater.initialize()) {
        std::fprintf(stderr, "decimate_bench: the decimater did not initialise\n");
        return 1;
    }
    decimater.decimate_to(static_cast<size_t>(std::atoi(argv[3])));
    mesh.garbage_collection();
    if (!OpenMesh::IO::write_mesh(mesh, argv[2])) {
        std::fprintf(stderr, "decimate_bench: cannot write %s\n", argv[2]);
        return 1;
    }
    std::printf("%zu vertices, %zu triangles\n", mesh.n_vertices(), mesh.n_faces());
    return 0;
}
