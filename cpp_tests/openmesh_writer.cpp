// A mesh written from C++ through OpenMesh, read by Rust (openmesh-sys, through the quadopt
// CLI built with --features openmesh) and optimized to the same result as the C++ path:
//
// 1. each test mesh is loaded into an OpenMesh PolyMesh with double points; some vertices get
//    the vertex property "fixed" (uchar), others the locked status;
// 2. it is written as OM (property + status) and as binary PLY (the flags of both kinds in the
//    property; PLY has no status);
// 3. the C++ path: quadopt::openmesh::optimize with the default options, the property as
//    MeshOptions::fixed and locked vertices fixed (the adapter's default);
// 4. `quadopt optimize IN -o OUT.om` for both files; OUT.om, read back with OpenMesh, must hold
//    bit for bit the C++ result, the same faces, and the fixed flags in the property and the
//    locked status.
//
// mixed_grid.obj, quads and triangles: the triangles come back as triangles (the same faces).
// A PLY with a pentagon, written from C++, is refused by the CLI naming the face.
//
// Usage: openmesh_writer DATA_DIR CLI TMP_DIR. CMake registers it only for a CLI with OpenMesh
// support; one without fails at once, saying so.
#include "test_support.hpp"

#include <quadopt/openmesh.hpp>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <cstdio>
#include <string>
#include <vector>

namespace {

struct DoubleTraits : OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
};
using Mesh = OpenMesh::PolyMesh_ArrayKernelT<DoubleTraits>;

std::vector<double> points_of(const Mesh &m) {
  std::vector<double> p;
  for (auto v : m.vertices()) p.insert(p.end(), {m.point(v)[0], m.point(v)[1], m.point(v)[2]});
  return p;
}

std::vector<int> faces_of(const Mesh &m) {
  std::vector<int> f;
  for (auto fh : m.faces()) {
    for (auto v : m.fv_range(fh)) f.push_back(v.idx());
    f.push_back(-1);
  }
  return f;
}

void run_case(const std::string &data, const std::string &cli, const std::string &tmp, const std::string &file) {
  Mesh m;
  OpenMesh::IO::Options ro;
  CHECK_MSG(OpenMesh::IO::read_mesh(m, data + "/" + file, ro), file);
  const std::size_t n = m.n_vertices();
  // Interior and boundary vertices alike: every 7th in the property, every 11th locked.
  OpenMesh::VPropHandleT<unsigned char> prop;
  m.add_property(prop, "fixed");
  m.property(prop).set_persistent(true);
  m.request_vertex_status();
  std::vector<std::uint8_t> flags(n, 0), either(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Mesh::VertexHandle vh(static_cast<int>(i));
    flags[i] = i % 7 == 3;
    m.property(prop, vh) = flags[i];
    m.status(vh).set_locked(i % 11 == 5);
    either[i] = flags[i] || i % 11 == 5;
  }
  const std::string base = tmp + "/cxx_" + file.substr(0, file.rfind('.'));
  OpenMesh::IO::Options wo = OpenMesh::IO::Options::Custom;
  wo += OpenMesh::IO::Options::Status;
  CHECK(OpenMesh::IO::write_mesh(m, base + ".om", wo));
  {
    Mesh ply = m;  // the PLY carries both kinds of flag in the property
    for (std::size_t i = 0; i < n; ++i) ply.property(prop, Mesh::VertexHandle(static_cast<int>(i))) = either[i];
    OpenMesh::IO::Options po = OpenMesh::IO::Options::Custom;
    po += OpenMesh::IO::Options::Binary;
    CHECK(OpenMesh::IO::write_mesh(ply, base + ".ply", po));
  }

  Mesh cxx = m;
  quadopt::openmesh::MeshOptions mo;
  mo.fixed = flags;
  const quadopt::Report r = quadopt::openmesh::optimize(cxx, quadopt::Options(), mo);
  CHECK_MSG(r.output.min > r.input.min || r.output.inverted < r.input.inverted, file << ": no improvement");
  const std::vector<double> want = points_of(cxx);
  CHECK_MSG(!qt::same_bits(want, points_of(m)), file << ": nothing moved");

  for (const std::string ext : {".om", ".ply"}) {
    const std::string out = base + "_rust_from" + (ext == ".om" ? "_om" : "_ply") + ".om";
    std::remove(out.c_str());
    const std::string cmd = "\"" + cli + "\" optimize \"" + base + ext + "\" -o \"" + out + "\"";
    const int rc = qt::run(cmd, out + ".log");
    CHECK_MSG(rc == 0, cmd << " exited with " << rc << ": " << qt::slurp(out + ".log"));
    if (rc != 0) continue;
    Mesh rust;
    rust.request_vertex_status();
    OpenMesh::IO::Options o = OpenMesh::IO::Options::Custom;
    o += OpenMesh::IO::Options::Status;
    CHECK_MSG(OpenMesh::IO::read_mesh(rust, out, o), out);
    const std::vector<double> got = points_of(rust);
    CHECK_MSG(qt::same_bits(got, want),
              cmd << ": coordinates differ from the C++ path, first at index " << qt::first_difference(got, want));
    CHECK_MSG(faces_of(rust) == faces_of(m), cmd << ": the faces changed");
    std::size_t triangles = 0;
    for (auto fh : rust.faces()) triangles += rust.valence(fh) == 3 ? 1 : 0;
    CHECK_MSG((triangles > 0) == (file.rfind("mixed", 0) == 0), cmd << ": " << triangles << " triangles");
    OpenMesh::VPropHandleT<unsigned char> back;
    CHECK_MSG(rust.get_property_handle(back, "fixed"), cmd << ": no vertex property 'fixed'");
    bool flags_ok = rust.n_vertices() == n && rust.get_property_handle(back, "fixed");
    for (std::size_t i = 0; flags_ok && i < n; ++i) {
      const Mesh::VertexHandle vh(static_cast<int>(i));
      flags_ok = (rust.property(back, vh) != 0) == (either[i] != 0) && rust.status(vh).locked() == (either[i] != 0);
    }
    CHECK_MSG(flags_ok, cmd << ": the fixed flags differ");
  }
}

/// Two quads, a pentagon (face 2) and a triangle, written as PLY: the CLI refuses the file,
/// naming the pentagon, and writes nothing.
void pentagon_refused(const std::string &cli, const std::string &tmp) {
  Mesh m;
  const double pts[9][2] = {{0, 0}, {1, 0}, {2, 0}, {0, 1}, {1, 1}, {2, 1}, {0.5, 2}, {1.5, 2.5}, {2, 2}};
  std::vector<Mesh::VertexHandle> v;
  for (const auto &p : pts) v.push_back(m.add_vertex(Mesh::Point(p[0], p[1], 0)));
  m.add_face(std::vector<Mesh::VertexHandle>{v[0], v[1], v[4], v[3]});
  m.add_face(std::vector<Mesh::VertexHandle>{v[1], v[2], v[5], v[4]});
  m.add_face(std::vector<Mesh::VertexHandle>{v[3], v[4], v[8], v[7], v[6]});
  m.add_face(std::vector<Mesh::VertexHandle>{v[4], v[5], v[8]});
  CHECK(m.n_faces() == 4);
  const std::string in = tmp + "/cxx_pentagon.ply", out = tmp + "/cxx_pentagon_out.om";
  CHECK(OpenMesh::IO::write_mesh(m, in));
  std::remove(out.c_str());
  const std::string cmd = "\"" + cli + "\" optimize \"" + in + "\" -o \"" + out + "\" 2> \"" + out + ".err\"";
  const int rc = qt::run(cmd, out + ".log");
  const std::string said = qt::slurp(out + ".err");
  CHECK_MSG(rc != 0 && said.find("face 2 has 5 vertices") != std::string::npos,
            cmd << " exited with " << rc << ": " << said);
  std::FILE *f = std::fopen(out.c_str(), "rb");
  CHECK_MSG(f == nullptr, out << " was written");
  if (f) std::fclose(f);
}

}  // namespace

int main(int argc, char **argv) {
  if (argc != 4) {
    std::cerr << "usage: openmesh_writer DATA_DIR CLI TMP_DIR\n";
    return 2;
  }
  const std::string data = argv[1], cli = argv[2], tmp = argv[3];
  const std::string version_file = tmp + "/cli_version.txt";
  qt::run("\"" + cli + "\" --version", version_file);
  // "(OpenMesh support: PLY, OM; ...)" with it, "(without OpenMesh support: ...)" without.
  if (qt::slurp(version_file).find("(OpenMesh support:") == std::string::npos) {
    std::cerr << "FAIL: " << cli << " was built without OpenMesh support (cargo feature openmesh), "
              << "yet this test was registered for it\n";
    return 1;
  }
  for (const char *file : {"plate_hole.obj", "jittered_grid.off", "mixed_grid.obj"}) run_case(data, cli, tmp, file);
  pentagon_refused(cli, tmp);
  return qt::finish("openmesh_writer");
}
