// The CGAL example of the user guide (docs/guide/cpp.md): the part between "doc:begin" and
// "doc:end" is shown in the docs as it is here (tests/docs.rs checks that); cpp_tests/ builds and
// runs this program (ctest: doc_example_cgal).
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <quadopt/cgal.hpp>

#include <iostream>

using Kernel = CGAL::Simple_cartesian<double>;

int main() {
  // doc:begin quickstart
  CGAL::Surface_mesh<Kernel::Point_2> mesh;
  std::vector<CGAL::Surface_mesh<Kernel::Point_2>::Vertex_index> v;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) v.push_back(mesh.add_vertex(Kernel::Point_2(i, j)));
  mesh.point(v[4]) = Kernel::Point_2(1.6, 1.5);  // drag the centre vertex off-centre
  mesh.add_face(v[0], v[1], v[4], v[3]);
  mesh.add_face(v[1], v[2], v[5], v[4]);
  mesh.add_face(v[3], v[4], v[7], v[6]);
  mesh.add_face(v[4], v[5], v[8], v[7]);
  auto fixed = mesh.add_property_map<decltype(mesh)::Vertex_index, bool>("v:fixed", false).first;
  fixed[v[0]] = true;  // optional: a fixed vertex keeps its coordinates bit for bit
  quadopt::Report r = quadopt::cgal::optimize(mesh, quadopt::Options().boundary(quadopt::Boundary::Fixed));
  std::cout << r.input.min << " -> " << r.output.min << ", centre at " << mesh.point(v[4]) << "\n";
  // doc:end
  const bool ok = r.output.min > r.input.min && std::abs(mesh.point(v[4]).x() - 1.0) < 0.05;
  std::cout << "doc_example_cgal: " << (ok ? 1 : 0) << " passed, " << (ok ? 0 : 1) << " failed\n";
  return ok ? 0 : 1;
}
