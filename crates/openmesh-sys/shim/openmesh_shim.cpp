// openmesh_shim.cpp: the C interface of openmesh_shim.h over OpenMesh 9.
//
// Reading goes through OpenMesh's own readers (OpenMesh::IO::IOManager) with an importer that
// records what the reader passes on: the counts the file declared, every face record and what
// became of it, and any handle out of range (a corrupt OM file can name arbitrary handles,
// which OpenMesh's ImporterT would write through unchecked). The arrays are then extracted by a
// bounds-checked walk of the halfedge structure, so a corrupt file never makes the shim index
// outside OpenMesh's arrays or loop forever.
#include "openmesh_shim.h"

#include "failure.h"
#include "prevalidate.h"

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/ImporterT.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <cmath>
#include <cstring>
#include <iostream>
#include <limits>
#include <locale>
#include <mutex>
#include <new>
#include <sstream>
#include <string>
#include <vector>

namespace {

struct DoubleTraits : OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
};
using Mesh = OpenMesh::PolyMesh_ArrayKernelT<DoubleTraits>;

constexpr uint64_t kUndeclared = std::numeric_limits<uint64_t>::max();

struct Dropped {
  uint64_t record;
  OmsysDropReason reason;
};

}  // namespace

struct OmsysMesh {
  Mesh mesh;
  std::vector<double> points;
  std::vector<uint32_t> offsets{0};
  std::vector<uint32_t> indices;
  std::vector<uint8_t> fixed;
  bool has_fixed = false;
  OmsysReadInfo info{};
  bool has_info = false;
  std::vector<Dropped> dropped;
  std::string output;
  std::string error;
};

namespace {

using omsys::Failure;
using omsys::fail;

/// OpenMesh's readers and writers are singletons with per-call state, and omerr/omlog are
/// process-wide: every call into OpenMesh::IO holds this lock.
std::mutex &io_mutex() {
  static std::mutex m;
  return m;
}

/// While alive, what OpenMesh prints on std::cerr (omerr, and a few direct messages) goes to a
/// buffer, for the error message, and its log and output streams are muted. std::cerr's buffer
/// is swapped rather than omerr's targets because mostream::disconnect leaks its target.
class QuietOpenMesh {
 public:
  QuietOpenMesh() : old_(std::cerr.rdbuf(captured_.rdbuf())) {
    log_on_ = omlog().is_enabled();
    out_on_ = omout().is_enabled();
    omlog().disable();
    omout().disable();
  }
  ~QuietOpenMesh() {
    omerr().flush();
    std::cerr.rdbuf(old_);
    if (log_on_) omlog().enable();
    if (out_on_) omout().enable();
  }
  QuietOpenMesh(const QuietOpenMesh &) = delete;
  QuietOpenMesh &operator=(const QuietOpenMesh &) = delete;

  /// What OpenMesh reported, on one line.
  std::string text() {
    omerr().flush();
    std::string s = captured_.str();
    for (char &c : s) {
      if (c == '\n' || c == '\r') c = ' ';
    }
    while (!s.empty() && s.back() == ' ') s.pop_back();
    return s;
  }

 private:
  std::ostringstream captured_;
  std::streambuf *old_;
  bool log_on_ = true, out_on_ = true;
};

enum class Format { Ply, Om, Obj, Off };

Format parse_format(const char *format) {
  if (format == nullptr) fail(OMSYS_INVALID_ARGUMENT, "the format is a null pointer");
  std::string f(format);
  for (char &c : f) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  if (f == "ply") return Format::Ply;
  if (f == "om") return Format::Om;
  if (f == "obj") return Format::Obj;
  if (f == "off") return Format::Off;
  fail(OMSYS_INVALID_ARGUMENT, "unknown format '" + std::string(format) + "' (expected ply, om, obj or off)");
}

const char *extension(Format f) {
  switch (f) {
    case Format::Ply: return ".ply";
    case Format::Om: return ".om";
    case Format::Obj: return ".obj";
    case Format::Off: return ".off";
  }
  return "";
}

/// ImporterT with a record of what the reader passed on, and every handle checked before it
/// is written through.
class RecordingImporter : public OpenMesh::IO::ImporterT<Mesh> {
  using Base = OpenMesh::IO::ImporterT<Mesh>;
  using VertexHandle = OpenMesh::VertexHandle;
  using HalfedgeHandle = OpenMesh::HalfedgeHandle;
  using EdgeHandle = OpenMesh::EdgeHandle;
  using FaceHandle = OpenMesh::FaceHandle;

 public:
  explicit RecordingImporter(Mesh &mesh) : Base(mesh), mesh_(mesh) {}

  uint64_t declared_vertices = kUndeclared, declared_faces = kUndeclared;
  uint64_t vertex_records = 0, face_records = 0;
  std::vector<Dropped> dropped;
  std::string bad_handle;  // the first out-of-range handle the reader used

  // The counts are the file's claims: recorded, not used to allocate.
  void reserve(unsigned int nV, unsigned int, unsigned int nF) override {
    declared_vertices = nV;
    declared_faces = nF;
  }

  VertexHandle add_vertex(const OpenMesh::Vec3f &p) override {
    ++vertex_records;
    return Base::add_vertex(p);
  }
  VertexHandle add_vertex(const OpenMesh::Vec3d &p) override {
    ++vertex_records;
    return Base::add_vertex(p);
  }
  VertexHandle add_vertex() override {
    ++vertex_records;
    return Base::add_vertex();
  }

  // A face by its vertices (PLY, OBJ, OFF, OM before 2.0). Unlike ImporterT, a face that
  // add_face refuses is not added with copies of its vertices: it is reported.
  FaceHandle add_face(const VHandles &vs) override {
    const uint64_t record = face_records++;
    const int nv = static_cast<int>(mesh_.n_vertices());
    if (vs.size() < 3) return drop(record, OMSYS_DROP_TOO_FEW_VERTICES);
    for (const auto &v : vs) {
      if (v.idx() < 0 || v.idx() >= nv) return drop(record, OMSYS_DROP_INVALID_INDEX);
    }
    for (std::size_t i = 0; i < vs.size(); ++i) {
      for (std::size_t j = i + 1; j < vs.size(); ++j) {
        if (vs[i] == vs[j]) return drop(record, OMSYS_DROP_REPEATED_VERTEX);
      }
    }
    const FaceHandle fh = mesh_.add_face(vs);
    if (!fh.is_valid()) return drop(record, OMSYS_DROP_NON_MANIFOLD);
    return fh;
  }

  // A face by one of its halfedges (OM 2.x); the topology is checked after reading.
  FaceHandle add_face(HalfedgeHandle heh) override {
    ++face_records;
    return Base::add_face(heh);
  }

  void set_point(VertexHandle vh, const OpenMesh::Vec3f &p) override {
    if (vertex_ok(vh, "set_point")) Base::set_point(vh, p);
  }
  void set_halfedge(VertexHandle vh, HalfedgeHandle heh) override {
    if (vertex_ok(vh, "set_halfedge")) Base::set_halfedge(vh, heh);
  }
  void set_next(HalfedgeHandle heh, HalfedgeHandle next) override {
    // set_next_halfedge_handle also writes `next`'s prev handle.
    if (halfedge_ok(heh, "set_next") && halfedge_ok(next, "set_next")) Base::set_next(heh, next);
  }
  void set_face(HalfedgeHandle heh, FaceHandle fh) override {
    if (halfedge_ok(heh, "set_face")) Base::set_face(heh, fh);
  }
  void set_status(VertexHandle vh, const OpenMesh::Attributes::StatusInfo &s) override {
    if (vertex_ok(vh, "set_status")) Base::set_status(vh, s);
  }
  void set_status(HalfedgeHandle heh, const OpenMesh::Attributes::StatusInfo &s) override {
    if (halfedge_ok(heh, "set_status")) Base::set_status(heh, s);
  }
  void set_status(EdgeHandle eh, const OpenMesh::Attributes::StatusInfo &s) override {
    if (in_range(eh.idx(), mesh_.n_edges(), "edge", "set_status")) Base::set_status(eh, s);
  }
  void set_status(FaceHandle fh, const OpenMesh::Attributes::StatusInfo &s) override {
    if (in_range(fh.idx(), mesh_.n_faces(), "face", "set_status")) Base::set_status(fh, s);
  }

 private:
  FaceHandle drop(uint64_t record, OmsysDropReason reason) {
    dropped.push_back(Dropped{record, reason});
    return FaceHandle();
  }
  bool vertex_ok(VertexHandle vh, const char *what) { return in_range(vh.idx(), mesh_.n_vertices(), "vertex", what); }
  bool halfedge_ok(HalfedgeHandle heh, const char *what) {
    return in_range(heh.idx(), mesh_.n_halfedges(), "halfedge", what);
  }
  bool in_range(int idx, std::size_t n, const char *kind, const char *what) {
    if (idx >= 0 && static_cast<std::size_t>(idx) < n) return true;
    if (bad_handle.empty()) {
      bad_handle = std::string("the reader's ") + what + " names " + kind + " " + std::to_string(idx) + " of " +
                   std::to_string(n);
    }
    return false;
  }

  Mesh &mesh_;
};

uint32_t read_le32(const uint8_t *p) {
  return static_cast<uint32_t>(p[0]) | static_cast<uint32_t>(p[1]) << 8 | static_cast<uint32_t>(p[2]) << 16 |
         static_cast<uint32_t>(p[3]) << 24;
}

/// The OM header's vertex and face counts (OpenMesh's OM reader does not pass them on).
void om_declared(const uint8_t *data, RecordingImporter &imp) {
  imp.declared_vertices = read_le32(data + 4);
  imp.declared_faces = read_le32(data + 8);
}

/// OBJ declares nothing: count its `v` and `f` statements.
void obj_declared(const uint8_t *data, std::size_t len, RecordingImporter &imp) {
  uint64_t v = 0, f = 0;
  std::size_t i = 0;
  while (i < len) {
    while (i < len && (data[i] == ' ' || data[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < len && data[i] != ' ' && data[i] != '\t' && data[i] != '\n' && data[i] != '\r') ++i;
    const std::size_t n = i - start;
    if (n == 1 && data[start] == 'v') ++v;
    if (n == 1 && data[start] == 'f') ++f;
    while (i < len && data[i] != '\n') ++i;
    ++i;
  }
  imp.declared_vertices = v;
  imp.declared_faces = f;
}

/// The vertex property "fixed" as flags, if the mesh has one; fails on a non-numeric type.
template <class T>
bool fixed_from(OpenMesh::BaseProperty *bp, std::vector<uint8_t> &out) {
  auto *p = dynamic_cast<OpenMesh::PropertyT<T> *>(bp);
  if (p == nullptr) return false;
  for (std::size_t i = 0; i < out.size(); ++i) {
    if ((*p)[i] != T(0)) out[i] = 1;
  }
  return true;
}

/// OpenMesh's ASCII PLY reader reads a char-typed property as one character ('0', '1'), not
/// as a number.
template <class T>
bool fixed_from_chars(OpenMesh::BaseProperty *bp, std::vector<uint8_t> &out) {
  auto *p = dynamic_cast<OpenMesh::PropertyT<T> *>(bp);
  if (p == nullptr) return false;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const int c = static_cast<int>((*p)[i]);
    if (c < '0' || c > '9') {
      fail(OMSYS_READ_FAILED, "vertex " + std::to_string(i) + ": the 'fixed' value is not a digit 0-9");
    }
    if (c != '0') out[i] = 1;
  }
  return true;
}

bool read_fixed_property(Mesh &m, std::vector<uint8_t> &out, bool ascii_ply) {
  for (auto it = m.vprops_begin(); it != m.vprops_end(); ++it) {
    OpenMesh::BaseProperty *bp = *it;
    if (bp == nullptr || bp->name() != "fixed") continue;
    if (bp->n_elements() != m.n_vertices()) {
      fail(OMSYS_READ_FAILED, "the vertex property 'fixed' has " + std::to_string(bp->n_elements()) +
                                  " values for " + std::to_string(m.n_vertices()) + " vertices");
    }
    if (ascii_ply && (fixed_from_chars<unsigned char>(bp, out) || fixed_from_chars<signed char>(bp, out))) {
      return true;
    }
    const bool ok = fixed_from<bool>(bp, out) || fixed_from<unsigned char>(bp, out) ||
                    fixed_from<signed char>(bp, out) || fixed_from<char>(bp, out) || fixed_from<short>(bp, out) ||
                    fixed_from<unsigned short>(bp, out) || fixed_from<int>(bp, out) ||
                    fixed_from<unsigned int>(bp, out) || fixed_from<long>(bp, out) ||
                    fixed_from<unsigned long>(bp, out) || fixed_from<float>(bp, out) || fixed_from<double>(bp, out);
    if (!ok) {
      fail(OMSYS_READ_FAILED,
           "the vertex property 'fixed' is not a number (type " + bp->internal_type_name() + ")");
    }
    return true;
  }
  return false;
}

/// Copies a freshly read mesh into the flat arrays, walking every face's halfedge cycle with
/// bounds checks (the order of OpenMesh's face-vertex circulator).
void extract(OmsysMesh &h, bool ascii_ply) {
  Mesh &m = h.mesh;
  const std::size_t nv = m.n_vertices(), nh = m.n_halfedges(), nf = m.n_faces();
  if (nv > std::numeric_limits<uint32_t>::max()) fail(OMSYS_READ_FAILED, "too many vertices for 32-bit indices");
  h.points.resize(3 * nv);
  for (std::size_t i = 0; i < nv; ++i) {
    const auto &p = m.point(Mesh::VertexHandle(static_cast<int>(i)));
    h.points[3 * i] = p[0];
    h.points[3 * i + 1] = p[1];
    h.points[3 * i + 2] = p[2];
  }
  h.offsets.assign(1, 0);
  h.offsets.reserve(nf + 1);
  h.indices.clear();
  for (std::size_t f = 0; f < nf; ++f) {
    const Mesh::FaceHandle fh(static_cast<int>(f));
    const Mesh::HalfedgeHandle start = m.halfedge_handle(fh);
    if (start.idx() < 0 || static_cast<std::size_t>(start.idx()) >= nh) {
      fail(OMSYS_READ_FAILED, "face " + std::to_string(f) + " has no valid halfedge (corrupt topology)");
    }
    Mesh::HalfedgeHandle heh = start;
    std::size_t steps = 0;
    do {
      if (m.face_handle(heh) != fh) {
        fail(OMSYS_READ_FAILED, "face " + std::to_string(f) + ": its halfedge cycle leaves the face (corrupt topology)");
      }
      const Mesh::VertexHandle vh = m.to_vertex_handle(heh);
      if (vh.idx() < 0 || static_cast<std::size_t>(vh.idx()) >= nv) {
        fail(OMSYS_READ_FAILED, "face " + std::to_string(f) + " names vertex " + std::to_string(vh.idx()) + " of " +
                                    std::to_string(nv) + " (corrupt topology)");
      }
      h.indices.push_back(static_cast<uint32_t>(vh.idx()));
      heh = m.next_halfedge_handle(heh);
      if (heh.idx() < 0 || static_cast<std::size_t>(heh.idx()) >= nh || ++steps > nh) {
        fail(OMSYS_READ_FAILED, "face " + std::to_string(f) + ": its halfedge cycle does not close (corrupt topology)");
      }
    } while (heh != start);
    if (h.indices.size() > std::numeric_limits<uint32_t>::max()) fail(OMSYS_READ_FAILED, "too many face indices");
    h.offsets.push_back(static_cast<uint32_t>(h.indices.size()));
  }

  h.fixed.assign(nv, 0);
  const bool has_property = read_fixed_property(m, h.fixed, ascii_ply);
  bool any_locked = false;
  if (h.info.has_vertex_status && m.has_vertex_status()) {
    for (std::size_t i = 0; i < nv; ++i) {
      const auto &st = m.status(Mesh::VertexHandle(static_cast<int>(i)));
      if (st.deleted()) fail(OMSYS_READ_FAILED, "vertex " + std::to_string(i) + " is marked deleted (the file was written without garbage_collection())");
      if (st.locked()) {
        h.fixed[i] = 1;
        any_locked = true;
      }
    }
  }
  if (m.has_face_status()) {
    for (std::size_t f = 0; f < nf; ++f) {
      if (m.status(Mesh::FaceHandle(static_cast<int>(f))).deleted()) {
        fail(OMSYS_READ_FAILED, "face " + std::to_string(f) + " is marked deleted (the file was written without garbage_collection())");
      }
    }
  }
  h.info.has_fixed_property = has_property ? 1 : 0;
  h.has_fixed = has_property || any_locked;
  if (!h.has_fixed) h.fixed.clear();
}

const char *reason_text(OmsysDropReason r) {
  switch (r) {
    case OMSYS_DROP_TOO_FEW_VERTICES: return "fewer than 3 vertices";
    case OMSYS_DROP_INVALID_INDEX: return "a vertex index out of range";
    case OMSYS_DROP_REPEATED_VERTEX: return "a repeated vertex";
    case OMSYS_DROP_NON_MANIFOLD: return "non-manifold or duplicated";
  }
  return "unknown";
}

/// The counts read against the counts declared; fails with OMSYS_INCOMPLETE on a difference.
void check_complete(OmsysMesh &h) {
  const OmsysReadInfo &in = h.info;
  std::ostringstream msg;
  bool bad = false;
  if (in.declared_vertices != kUndeclared && in.declared_vertices != h.mesh.n_vertices()) {
    msg << "the file declares " << in.declared_vertices << " vertices, OpenMesh read " << h.mesh.n_vertices() << "; ";
    bad = true;
  }
  if (in.declared_faces != kUndeclared && in.declared_faces != in.face_records) {
    msg << "the file declares " << in.declared_faces << " faces, OpenMesh read " << in.face_records << "; ";
    bad = true;
  }
  if (!h.dropped.empty()) {
    msg << h.dropped.size() << " face(s) not added:";
    for (std::size_t i = 0; i < h.dropped.size() && i < 10; ++i) {
      msg << (i ? "," : "") << " face " << h.dropped[i].record << " (" << reason_text(h.dropped[i].reason) << ")";
    }
    if (h.dropped.size() > 10) msg << ", ...";
    msg << "; ";
    bad = true;
  }
  if (bad) {
    std::string s = msg.str();
    s.resize(s.size() - 2);
    fail(OMSYS_INCOMPLETE, s);
  }
}

void read_impl(OmsysMesh &h, const uint8_t *data, std::size_t len, const char *format) {
  const Format fmt = parse_format(format);
  if (data == nullptr && len != 0) fail(OMSYS_INVALID_ARGUMENT, "the data is a null pointer");
  h.mesh = Mesh();
  h.points.clear();
  h.offsets.assign(1, 0);
  h.indices.clear();
  h.fixed.clear();
  h.has_fixed = false;
  h.info = OmsysReadInfo{};
  h.has_info = false;
  h.dropped.clear();

  Mesh &m = h.mesh;
  OpenMesh::IO::Options opt = OpenMesh::IO::Options::Custom;
  if (fmt == Format::Om) {
    // OM may carry status: locked vertices are fixed, deleted elements are refused.
    m.request_vertex_status();
    m.request_face_status();
    opt += OpenMesh::IO::Options::Status;
  }
  RecordingImporter imp(m);
  // OpenMesh's readers loop on stale values after a failed read, and its PLY header parser
  // loops forever on a header cut short: only data they read to the end is passed on.
  switch (fmt) {
    case Format::Ply: omsys::check_ply(data, len); break;
    case Format::Off: omsys::check_off(data, len); break;
    case Format::Om:
      omsys::check_om(data, len);
      om_declared(data, imp);
      break;
    case Format::Obj: break;
  }
  if (fmt == Format::Obj) obj_declared(data, len, imp);

  std::string bytes(reinterpret_cast<const char *>(data), len);
  std::istringstream is(bytes, std::ios::in | std::ios::binary);
  // Numbers as prevalidate.cpp checked them, whatever global locale the host program set.
  is.imbue(std::locale::classic());
  // As OpenMesh's own file reader does: operator>> in the binary restore of bool properties
  // must not skip bytes that look like whitespace.
  if (fmt == Format::Om) is.unsetf(std::ios::skipws);
  bool ok;
  std::string openmesh_says;
  {
    std::lock_guard<std::mutex> lock(io_mutex());
    QuietOpenMesh quiet;
    ok = OpenMesh::IO::IOManager().read(is, extension(fmt), imp, opt);
    openmesh_says = quiet.text();
  }
  const std::string detail = openmesh_says.empty() ? "" : " (OpenMesh: " + openmesh_says + ")";
  if (!ok) fail(OMSYS_READ_FAILED, "OpenMesh cannot read the data as " + std::string(extension(fmt) + 1) + detail);
  // The PLY reader stops quietly at a malformed number or the end of the data.
  if (fmt == Format::Ply && is.fail()) {
    fail(OMSYS_READ_FAILED, "the PLY data ends early or holds a malformed value" + detail);
  }
  // OM ends with an end-of-chunks marker; the reader also stops quietly at the end of the data,
  // which loses every chunk cut off (the fixed flags, the status).
  if (fmt == Format::Om && is.eof()) {
    fail(OMSYS_READ_FAILED, "the OM data ends before its end-of-chunks marker (truncated)" + detail);
  }
  if (!imp.bad_handle.empty()) fail(OMSYS_READ_FAILED, "corrupt file: " + imp.bad_handle);

  h.info.declared_vertices = imp.declared_vertices;
  h.info.declared_faces = imp.declared_faces;
  h.info.vertex_records = imp.vertex_records;
  h.info.face_records = imp.face_records;
  h.info.dropped_faces = imp.dropped.size();
  h.info.binary = opt.check(OpenMesh::IO::Options::Binary) ? 1 : 0;
  h.info.has_vertex_status = (fmt == Format::Om && opt.check(OpenMesh::IO::Options::Status)) ? 1 : 0;
  h.dropped = std::move(imp.dropped);
  h.has_info = true;
  check_complete(h);
  extract(h, fmt == Format::Ply && !h.info.binary);
}

void set_impl(OmsysMesh &h, const double *points, std::size_t nv, const uint32_t *offsets, std::size_t nf,
              const uint32_t *indices, std::size_t nidx, const uint8_t *fixed) {
  if ((points == nullptr && nv != 0) || offsets == nullptr || (indices == nullptr && nidx != 0)) {
    fail(OMSYS_INVALID_ARGUMENT, "a null array");
  }
  if (nv > static_cast<std::size_t>(std::numeric_limits<int>::max() / 2)) {
    fail(OMSYS_INVALID_MESH, "too many vertices for OpenMesh's handles");
  }
  if (offsets[0] != 0 || offsets[nf] != nidx) {
    fail(OMSYS_INVALID_ARGUMENT, "the face offsets must start at 0 and end at the number of face indices");
  }
  for (std::size_t i = 0; i < 3 * nv; ++i) {
    if (!std::isfinite(points[i])) {
      fail(OMSYS_INVALID_MESH, "vertex " + std::to_string(i / 3) + " has a coordinate that is not finite");
    }
  }
  Mesh m;
  for (std::size_t i = 0; i < nv; ++i) m.add_vertex(Mesh::Point(points[3 * i], points[3 * i + 1], points[3 * i + 2]));
  std::vector<Mesh::VertexHandle> vs;
  std::lock_guard<std::mutex> lock(io_mutex());  // add_face reports on omerr
  QuietOpenMesh quiet;
  for (std::size_t f = 0; f < nf; ++f) {
    if (offsets[f + 1] < offsets[f] || offsets[f + 1] > nidx) {
      fail(OMSYS_INVALID_ARGUMENT, "the face offsets decrease or pass the end at face " + std::to_string(f));
    }
    const std::size_t n = offsets[f + 1] - offsets[f];
    if (n < 3) fail(OMSYS_INVALID_MESH, "face " + std::to_string(f) + " has fewer than 3 vertices");
    vs.clear();
    for (std::size_t k = offsets[f]; k < offsets[f + 1]; ++k) {
      if (indices[k] >= nv) {
        fail(OMSYS_INVALID_MESH, "face " + std::to_string(f) + " names vertex " + std::to_string(indices[k]) + " of " +
                                     std::to_string(nv));
      }
      const Mesh::VertexHandle vh(static_cast<int>(indices[k]));
      for (const auto &u : vs) {
        if (u == vh) fail(OMSYS_INVALID_MESH, "face " + std::to_string(f) + " repeats vertex " + std::to_string(indices[k]));
      }
      vs.push_back(vh);
    }
    if (!m.add_face(vs).is_valid()) {
      const std::string says = quiet.text();
      fail(OMSYS_INVALID_MESH, "OpenMesh cannot add face " + std::to_string(f) +
                                   ": it is non-manifold or repeats an edge of another face" +
                                   (says.empty() ? "" : " (OpenMesh: " + says + ")"));
    }
  }
  h.mesh = std::move(m);
  h.points.assign(points, points + 3 * nv);
  h.offsets.assign(offsets, offsets + nf + 1);
  h.indices.assign(indices, indices + nidx);
  h.has_fixed = fixed != nullptr;
  if (fixed != nullptr) {
    h.fixed.assign(nv, 0);
    for (std::size_t i = 0; i < nv; ++i) h.fixed[i] = fixed[i] ? 1 : 0;
  } else {
    h.fixed.clear();
  }
  h.has_info = false;
  h.dropped.clear();
}

template <class T>
void add_fixed_property(Mesh &m, const std::vector<uint8_t> &fixed) {
  OpenMesh::VPropHandleT<T> prop;
  m.add_property(prop, "fixed");
  m.property(prop).set_persistent(true);
  for (std::size_t i = 0; i < m.n_vertices(); ++i) m.property(prop, Mesh::VertexHandle(static_cast<int>(i))) = fixed[i];
}

void write_impl(OmsysMesh &h, const char *format, const OmsysWriteOptions *options) {
  const Format fmt = parse_format(format);
  OpenMesh::IO::Options opt = OpenMesh::IO::Options::Default;
  if (options != nullptr && options->binary && fmt == Format::Ply) {
    opt += OpenMesh::IO::Options::Binary;
    opt += OpenMesh::IO::Options::LSB;
  }
  // Always written from a copy: the flags go into properties that must not linger in the mesh.
  Mesh m = h.mesh;
  if (h.has_fixed) {
    if (fmt == Format::Obj || fmt == Format::Off) {
      fail(OMSYS_INVALID_ARGUMENT, std::string(extension(fmt) + 1) + " cannot carry the fixed flags (use ply or om)");
    }
    // uchar in OM; int in PLY, whose ASCII writer puts a uchar out as a raw byte.
    if (fmt == Format::Om) {
      add_fixed_property<unsigned char>(m, h.fixed);
    } else {
      add_fixed_property<int>(m, h.fixed);
    }
    opt += OpenMesh::IO::Options::Custom;
    if (fmt == Format::Om) {
      // OpenMesh tools (and quadopt's C++ adapter) read locked vertices as fixed.
      m.request_vertex_status();
      for (std::size_t i = 0; i < m.n_vertices(); ++i) {
        m.status(Mesh::VertexHandle(static_cast<int>(i))).set_locked(h.fixed[i] != 0);
      }
      opt += OpenMesh::IO::Options::Status;
    }
  }
  std::ostringstream os(std::ios::out | std::ios::binary);
  bool ok;
  std::string openmesh_says;
  {
    std::lock_guard<std::mutex> lock(io_mutex());
    QuietOpenMesh quiet;
    ok = OpenMesh::IO::write_mesh(m, os, extension(fmt), opt, 17);
    openmesh_says = quiet.text();
  }
  if (!ok || !os) {
    fail(OMSYS_WRITE_FAILED, "OpenMesh cannot write the mesh as " + std::string(extension(fmt) + 1) +
                                 (openmesh_says.empty() ? "" : " (OpenMesh: " + openmesh_says + ")"));
  }
  h.output = os.str();
}

/// Runs `body`, turning every exception into a status and the handle's message.
template <class F>
OmsysStatus guarded(OmsysMesh *h, F body) {
  if (h == nullptr) return OMSYS_INVALID_ARGUMENT;
  try {
    h->error.clear();
    body();
    return OMSYS_OK;
  } catch (const Failure &f) {
    try {
      h->error = f.message;
    } catch (...) {
    }
    return f.status;
  } catch (const std::bad_alloc &) {
    try {
      h->error = "out of memory";
    } catch (...) {
    }
    return OMSYS_OUT_OF_MEMORY;
  } catch (const std::exception &e) {
    try {
      h->error = std::string("OpenMesh threw: ") + e.what();
    } catch (...) {
    }
    return OMSYS_INTERNAL;
  } catch (...) {
    try {
      h->error = "OpenMesh threw an unknown exception";
    } catch (...) {
    }
    return OMSYS_INTERNAL;
  }
}

}  // namespace

extern "C" {

OmsysMesh *omsys_mesh_new(void) {
  try {
    return new OmsysMesh();
  } catch (...) {
    return nullptr;
  }
}

void omsys_mesh_free(OmsysMesh *mesh) { delete mesh; }

const char *omsys_mesh_error(const OmsysMesh *mesh) {
  if (mesh == nullptr) return "the mesh is a null pointer";
  return mesh->error.c_str();
}

OmsysStatus omsys_read(OmsysMesh *mesh, const uint8_t *data, size_t len, const char *format) {
  return guarded(mesh, [&] { read_impl(*mesh, data, len, format); });
}

OmsysStatus omsys_read_info(const OmsysMesh *mesh, OmsysReadInfo *info) {
  if (mesh == nullptr || info == nullptr || !mesh->has_info) return OMSYS_INVALID_ARGUMENT;
  *info = mesh->info;
  return OMSYS_OK;
}

OmsysStatus omsys_dropped_face(const OmsysMesh *mesh, size_t i, uint64_t *record, OmsysDropReason *reason) {
  if (mesh == nullptr || record == nullptr || reason == nullptr || i >= mesh->dropped.size()) {
    return OMSYS_INVALID_ARGUMENT;
  }
  *record = mesh->dropped[i].record;
  *reason = mesh->dropped[i].reason;
  return OMSYS_OK;
}

OmsysStatus omsys_mesh_counts(const OmsysMesh *mesh, OmsysCounts *counts) {
  if (mesh == nullptr || counts == nullptr) return OMSYS_INVALID_ARGUMENT;
  counts->vertices = mesh->points.size() / 3;
  counts->faces = mesh->offsets.size() - 1;
  counts->face_indices = mesh->indices.size();
  counts->has_fixed = mesh->has_fixed ? 1 : 0;
  return OMSYS_OK;
}

OmsysStatus omsys_mesh_get(const OmsysMesh *mesh, double *points, size_t points_len, uint32_t *face_offsets,
                           size_t face_offsets_len, uint32_t *face_indices, size_t face_indices_len,
                           uint8_t *fixed, size_t fixed_len) {
  if (mesh == nullptr) return OMSYS_INVALID_ARGUMENT;
  const bool sizes_ok = points_len == mesh->points.size() && face_offsets_len == mesh->offsets.size() &&
                        face_indices_len == mesh->indices.size() && fixed_len == mesh->fixed.size();
  if (!sizes_ok || (points == nullptr && points_len) || face_offsets == nullptr ||
      (face_indices == nullptr && face_indices_len) || (fixed == nullptr && fixed_len)) {
    return OMSYS_INVALID_ARGUMENT;
  }
  if (points_len) std::memcpy(points, mesh->points.data(), points_len * sizeof(double));
  std::memcpy(face_offsets, mesh->offsets.data(), face_offsets_len * sizeof(uint32_t));
  if (face_indices_len) std::memcpy(face_indices, mesh->indices.data(), face_indices_len * sizeof(uint32_t));
  if (fixed_len) std::memcpy(fixed, mesh->fixed.data(), fixed_len);
  return OMSYS_OK;
}

OmsysStatus omsys_mesh_set(OmsysMesh *mesh, const double *points, size_t vertex_count, const uint32_t *face_offsets,
                           size_t face_count, const uint32_t *face_indices, size_t face_indices_len,
                           const uint8_t *fixed) {
  return guarded(mesh, [&] {
    set_impl(*mesh, points, vertex_count, face_offsets, face_count, face_indices, face_indices_len, fixed);
  });
}

OmsysStatus omsys_write(OmsysMesh *mesh, const char *format, const OmsysWriteOptions *options) {
  return guarded(mesh, [&] { write_impl(*mesh, format, options); });
}

OmsysStatus omsys_output(const OmsysMesh *mesh, const uint8_t **data, size_t *len) {
  if (mesh == nullptr || data == nullptr || len == nullptr) return OMSYS_INVALID_ARGUMENT;
  *data = reinterpret_cast<const uint8_t *>(mesh->output.data());
  *len = mesh->output.size();
  return OMSYS_OK;
}

}  // extern "C"
