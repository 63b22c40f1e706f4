// The OpenMesh example of the user guide (docs/guide/cpp.md and the README): the part between
// "doc:begin" and "doc:end" is shown in the docs as it is here (tests/docs.rs checks that);
// cpp_tests/ builds and runs this program on cpp_tests/data/plate_hole.obj (ctest:
// doc_example_openmesh).
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <quadopt/openmesh.hpp>

#include <iostream>

int main(int argc, char **argv) {
  const char *path = argc > 1 ? argv[1] : "plate.obj";
  // doc:begin quickstart
  OpenMesh::PolyMesh_ArrayKernelT<> mesh;
  OpenMesh::IO::read_mesh(mesh, path);
  mesh.request_vertex_status();  // optional: locked / feature vertices stay put
  try {
    quadopt::Report r = quadopt::openmesh::optimize(mesh, quadopt::Options().boundary(quadopt::Boundary::Slide));
    std::cout << r.input.min << " -> " << r.output.min << "\n";
    return r.output.min > r.input.min ? 0 : 1;
  } catch (const quadopt::Error &e) {  // e.status(), e.message(); UnsupportedFace for 5+ vertices
    std::cerr << e.what() << "\n";
    return 1;
  }
  // doc:end
}
