// SPDX-License-Identifier: GPL-3.0-or-later
//
// filter_quadopt.cpp: the filter. It reads the current mesh's polygons (triangles joined by
// faux edges, see polygons.h), runs quadopt through its C++ header (quadopt.hpp, over the C ABI
// of the static library linked into this plugin), and writes back the vertices that moved and
// each face's scaled Jacobian as MeshLab's per-face quality.
//
// Errors: everything that can fail runs inside one try block in applyFilter(); whatever it
// throws (quadopt::Error carrying the C ABI's status, a refused mesh, std::bad_alloc, anything)
// is caught there, logged, and reported to MeshLab as an MLException, the failure channel
// MeshLab's filter interface defines (the desktop application shows it and logs it, pymeshlab
// raises it as pymeshlab.PyMeshLabException). No other exception leaves the plugin, and a Rust
// panic never crosses the C ABI (it is QUADOPT_STATUS_PANIC). The mesh is written only after
// quadopt has succeeded, so a failed or cancelled run leaves it as it was.
#include "filter_quadopt.h"

#include "polygons.h"

#include <common/mlexception.h>
#include <quadopt.hpp>
#include <quadopt/planar.hpp>
#include <vcg/complex/algorithms/update/bounding.h>
#include <vcg/complex/algorithms/update/normal.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <new>
#include <string>
#include <utility>
#include <vector>

namespace {

// The choices of the enum parameters, in the order the dialog and pymeshlab's indices use.
const QStringList kPresets = {"fast", "balanced", "best"};
const quadopt::Effort kEfforts[] = {quadopt::Effort::Fast, quadopt::Effort::Balanced, quadopt::Effort::Best};
const QStringList kBoundaries = {"auto", "fixed", "slide", "snap"};
const quadopt::Boundary kBoundaryModes[] = {quadopt::Boundary::Auto, quadopt::Boundary::Fixed,
                                            quadopt::Boundary::Slide, quadopt::Boundary::Snap};

// Parameter names (pymeshlab's keyword arguments are the same).
const char *const kPreset = "preset";
const char *const kBoundary = "boundary";
const char *const kFeatureAngle = "feature_angle";
const char *const kKeepSelected = "keep_selected_fixed";
const char *const kMaxSweeps = "max_sweeps";

// quadopt's defaults; the parameters start from them. quadopt_options_init() cannot fail for a
// struct of this header's size, but a failure would only cost the defaults, never the plugin.
QuadoptOptions defaults() {
  QuadoptOptions o{};
  if (quadopt_options_init(&o, sizeof o) != QUADOPT_STATUS_OK) {
    o.feature_angle_deg = 45;
    o.max_iterations = 1000;
    o.effort = QUADOPT_EFFORT_BALANCED;
    o.boundary = QUADOPT_BOUNDARY_AUTO;
  }
  return o;
}

template <class T, std::size_t N>
int index_of(const T (&values)[N], std::uint32_t raw, int fallback) {
  for (std::size_t i = 0; i < N; ++i) {
    if (static_cast<std::uint32_t>(values[i]) == raw) return static_cast<int>(i);
  }
  return fallback;
}

std::string fixed3(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4f", v);
  return buf;
}

std::string line(const char *what, const quadopt::Quality &q) {
  return std::string(what) + "min " + fixed3(q.min) + ", avg " + fixed3(q.avg) + ", max " + fixed3(q.max) + "; " +
         std::to_string(q.inverted) + " inverted";
}

int as_int(std::size_t n) {
  return static_cast<int>(std::min<std::size_t>(n, static_cast<std::size_t>(std::numeric_limits<int>::max())));
}

bool same_bits(double a, double b) { return quadopt::planar::same_bits(a, b); }

}  // namespace

QuadoptFilterPlugin::QuadoptFilterPlugin() {
  typeList = {FP_QUADOPT};
  for (ActionIDType t : types()) actionList.push_back(new QAction(filterName(t), this));
}

QString QuadoptFilterPlugin::pluginName() const { return "FilterQuadopt"; }

QString QuadoptFilterPlugin::vendor() const { return "quadopt"; }

QString QuadoptFilterPlugin::filterName(ActionIDType filter) const {
  return filter == FP_QUADOPT ? QString("Quad Mesh Quality Optimization (quadopt)") : QString();
}

QString QuadoptFilterPlugin::pythonFilterName(ActionIDType filter) const {
  return filter == FP_QUADOPT ? QString("apply_coord_quadopt_quad_quality") : QString();
}

QString QuadoptFilterPlugin::filterInfo(ActionIDType filter) const {
  if (filter != FP_QUADOPT) return QString();
  return QString(
             "Raises the quality of a quad or quad-dominant mesh by moving its vertices, never its connectivity: "
             "every face's <b>scaled Jacobian</b> (Verdict's definition) goes up, and no face ends worse than "
             "it started. A planar mesh is optimized in its plane; a mesh on a curved surface stays on the input "
             "surface, open or closed, its boundary and sharp edges (dihedral angle above the feature angle) kept "
             "as curves its vertices slide along, their corners fixed.<br>"
             "Input: the mesh as MeshLab holds polygons (triangles joined by faux edges): quads, and triangles "
             "kept as triangles. A polygon of five or more sides is an error, and a plain triangle mesh is "
             "refused. Output: the moved vertices, each face's scaled Jacobian in the per-face quality "
             "(Colorize by face quality shows it), and the report in the log.<br>"
             "quadopt %1: embedded polygon smoothing with untangling, guarded moves and a max-min stage.<br>"
             "See: <i>M. N. Akram, H. Si, L. Chen</i>, <b>\"An Embedded Polygon Strategy for Quality "
             "Improvement of 2D Quadrilateral Meshes with Boundaries\"</b>, 2021.")
      .arg(quadopt_version());
}

QuadoptFilterPlugin::FilterClass QuadoptFilterPlugin::getClass(const QAction *) const {
  return FilterClass(Remeshing + Polygonal);
}

FilterPlugin::FilterArity QuadoptFilterPlugin::filterArity(const QAction *) const { return SINGLE_MESH; }

int QuadoptFilterPlugin::getPreConditions(const QAction *) const { return MeshModel::MM_FACENUMBER; }

int QuadoptFilterPlugin::postCondition(const QAction *) const {
  return MeshModel::MM_VERTCOORD | MeshModel::MM_VERTNORMAL | MeshModel::MM_FACENORMAL | MeshModel::MM_FACEQUALITY;
}

RichParameterList QuadoptFilterPlugin::initParameterList(const QAction *action, const MeshModel &) {
  RichParameterList list;
  if (ID(action) != FP_QUADOPT) return list;
  const QuadoptOptions d = defaults();
  list.addParam(RichEnum(kPreset, index_of(kEfforts, d.effort, 1), kPresets, "Preset",
                         "How much work to spend on quality: <i>fast</i> (a few guarded sweeps with untangling, no "
                         "max-min stage), <i>balanced</i> (quadopt's default) or <i>best</i> (the highest quality, "
                         "at more time)."));
  list.addParam(RichEnum(kBoundary, index_of(kBoundaryModes, d.boundary, 0), kBoundaries, "Boundary",
                         "How boundary (and, on a curved surface, feature-curve) vertices move: <i>auto</i> (the "
                         "better of slide and snap, per vertex and sweep; the default), <i>fixed</i> (never), "
                         "<i>slide</i> (along the original polyline) or <i>snap</i> (bisect, then project back)."));
  list.addParam(RichFloat(kFeatureAngle, static_cast<Scalarm>(d.feature_angle_deg), "Feature angle (degrees)",
                          "Boundary vertices turning by more than this are corners and never move; on a curved "
                          "surface, also the dihedral angle above which an edge is sharp (a feature curve). In "
                          "[0, 180]."));
  list.addParam(RichBool(kKeepSelected, false, "Keep selected vertices fixed",
                         "The selected vertices never move: they keep their coordinates bit for bit."));
  list.addParam(RichInt(kMaxSweeps, static_cast<int>(std::min<std::uint32_t>(
                                        d.max_iterations, static_cast<std::uint32_t>(std::numeric_limits<int>::max()))),
                        "Sweep cap", "The largest number of smoothing sweeps, in every preset (>= 1)."));
  return list;
}

std::map<std::string, QVariant> QuadoptFilterPlugin::applyFilter(const QAction *action,
                                                                 const RichParameterList &parameters,
                                                                 MeshDocument &md, unsigned int &,
                                                                 vcg::CallBackPos *cb) {
  if (ID(action) != FP_QUADOPT) wrongActionCalled(action);
  std::string error;
  try {
    return optimize(parameters, md, cb);
  } catch (const quadopt::Error &e) {
    error = e.status() == QUADOPT_STATUS_CANCELLED ? "cancelled" : e.what();
  } catch (const quadopt_meshlab::MeshError &e) {
    error = e.what();
  } catch (const std::bad_alloc &) {
    error = "not enough memory for this mesh";
  } catch (const std::exception &e) {
    error = e.what();
  } catch (...) {
    error = "an unknown error";
  }
  error = "quadopt: " + error + " (the mesh is unchanged)";
  try {
    log(GLLogStream::WARNING, error);
  } catch (...) {
    // the exception below still says it
  }
  throw MLException(QString::fromStdString(error));
}

std::map<std::string, QVariant> QuadoptFilterPlugin::optimize(const RichParameterList &par, MeshDocument &md,
                                                              vcg::CallBackPos *cb) {
  const auto started = std::chrono::steady_clock::now();
  MeshModel *mm = md.mm();
  if (mm == nullptr) throw quadopt_meshlab::MeshError("there is no current mesh");
  CMeshO &m = mm->cm;

  const int preset = par.getEnum(kPreset);
  const int boundary = par.getEnum(kBoundary);
  if (preset < 0 || preset >= kPresets.size() || boundary < 0 || boundary >= kBoundaries.size()) {
    throw quadopt_meshlab::MeshError("unknown preset or boundary mode");
  }
  const double feature_angle = static_cast<double>(par.getFloat(kFeatureAngle));
  const int sweeps = par.getInt(kMaxSweeps);
  if (sweeps < 1) {
    throw quadopt_meshlab::MeshError("the sweep cap must be at least 1, not " + std::to_string(sweeps));
  }
  quadopt::Options options;
  options.effort(kEfforts[preset])
      .boundary(kBoundaryModes[boundary])
      .feature_angle_deg(feature_angle)
      .max_iterations(static_cast<std::uint32_t>(sweeps));
  // MeshLab's progress bar; a callback returning false cancels (quadopt then writes nothing).
  if (cb != nullptr) {
    options.progress([cb](const quadopt::Progress &p) {
      const std::size_t pct = p.max_iterations > 0 ? std::min<std::size_t>(99, 100 * p.iteration / p.max_iterations) : 0;
      const std::string what = p.iteration == 0 ? std::string("quadopt: untangling")
                                                : "quadopt: sweep " + std::to_string(p.iteration) + " (at most " +
                                                      std::to_string(p.max_iterations) + ")";
      return cb(static_cast<int>(pct), what.c_str());
    });
  }

  const quadopt_meshlab::Polygons poly = quadopt_meshlab::read_polygons(m);
  const std::size_t n = poly.mesh_vertex.size();
  const std::size_t faces = poly.polygon_count();
  std::vector<double> xyz(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto &p = m.vert[poly.mesh_vertex[i]].cP();
    for (int c = 0; c < 3; ++c) xyz[3 * i + c] = static_cast<double>(p[c]);
  }
  std::vector<std::uint8_t> used(n, 0);
  for (std::uint32_t v : poly.faces) {
    if (v != quadopt::no_vertex) used[v] = 1;
  }
  std::vector<std::uint8_t> fixed;
  std::size_t fixed_count = 0;
  if (par.getBool(kKeepSelected)) {
    fixed.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
      if (m.vert[poly.mesh_vertex[i]].IsS()) {
        fixed[i] = 1;
        ++fixed_count;
      }
    }
  }
  const std::uint8_t *fixed_ptr = fixed_count > 0 ? fixed.data() : nullptr;

  // The rule of quadopt's command-line tool and adapters (quadopt/planar.hpp): a mesh in a plane
  // (x, y or z constant, or a tilted one) is optimized in that plane, anything else on its
  // surface in 3D. So the filter gives the command-line tool's result on the same mesh.
  const auto fit = [&]() -> std::pair<bool, quadopt::planar::Frame> {
    try {
      return {true, quadopt::planar::Frame::fit(xyz, used, "MeshLab")};
    } catch (const quadopt::NotPlanar &) {
      return {false, quadopt::planar::Frame()};
    }
  };
  const auto [planar, frame] = fit();

  std::vector<double> before, after;  // 2 or 3 doubles per vertex, as quadopt saw them
  std::vector<double> per_face;
  quadopt::Report r{};
  if (planar) {
    before = frame.to_2d(xyz);
    after = before;
    r = quadopt::optimize(after.data(), 2, n, poly.faces.data(), faces, fixed_ptr, options);
    quadopt::quality(after.data(), 2, n, poly.faces.data(), faces, &per_face);
  } else {
    before = xyz;
    after = xyz;
    r = quadopt::optimize_surface(after.data(), n, poly.faces.data(), faces, fixed_ptr, nullptr, 0, options);
    // On a surface, Verdict's 3D scaled Jacobian: what MeshLab's own quality filters, VTK and
    // ParaView compute, and the report's output_verdict face by face.
    quadopt::verdict_quality(after.data(), n, poly.faces.data(), faces, &per_face);
  }
  if (per_face.size() != faces) throw quadopt_meshlab::MeshError("quadopt returned no per-face quality");

  // Success: now the mesh changes (nothing above has touched it).
  mm->updateDataMask(MeshModel::MM_FACEQUALITY);
  const int dim = planar ? 2 : 3;
  std::size_t moved = 0;
  for (std::size_t i = 0; i < n; ++i) {
    bool changed = false;
    for (int c = 0; c < dim; ++c) changed = changed || !same_bits(after[dim * i + c], before[dim * i + c]);
    if (!changed) continue;  // fixed vertices, corners and vertices that stayed keep their bits
    ++moved;
    auto &p = m.vert[poly.mesh_vertex[i]].P();
    if (planar) {
      double q[3];
      frame.to_3d(&after[2 * i], q);
      for (int c = 0; c < 3; ++c) {
        if (c != frame.axis()) p[c] = static_cast<Scalarm>(q[c]);  // a constant axis stays as it was
      }
    } else {
      for (int c = 0; c < 3; ++c) p[c] = static_cast<Scalarm>(after[3 * i + c]);
    }
  }
  double quality_sum = 0;
  double quality_min = std::numeric_limits<double>::infinity();
  for (std::size_t f = 0; f < faces; ++f) {
    quality_sum += per_face[f];
    quality_min = std::min(quality_min, per_face[f]);
    for (std::size_t t = poly.first[f]; t < poly.first[f + 1]; ++t) {
      m.face[poly.triangles[t]].Q() = static_cast<Scalarm>(per_face[f]);
    }
  }
  // Normals: one per polygon (its triangles' area-weighted sum), as MeshLab gives polygon meshes.
  vcg::tri::UpdateNormal<CMeshO>::PerFace(m);
  for (std::size_t f = 0; f < faces; ++f) {
    Point3m normal(0, 0, 0);
    for (std::size_t t = poly.first[f]; t < poly.first[f + 1]; ++t) normal += m.face[poly.triangles[t]].N();
    if (!(normal.Norm() > 0)) continue;  // a degenerate polygon keeps its triangles' normals
    normal.Normalize();
    for (std::size_t t = poly.first[f]; t < poly.first[f + 1]; ++t) m.face[poly.triangles[t]].N() = normal;
  }
  vcg::tri::UpdateNormal<CMeshO>::PerVertexFromCurrentFaceNormal(m);
  vcg::tri::UpdateNormal<CMeshO>::NormalizePerVertex(m);
  vcg::tri::UpdateBounding<CMeshO>::Box(m);

  const double total =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  const bool surface = quadopt::on_surface(r);
  log(GLLogStream::FILTER,
      std::string("quadopt ") + quadopt_version() + ": " + std::to_string(faces) + " faces (" +
          std::to_string(poly.quads) + " quads, " + std::to_string(poly.plain_triangles) + " triangles), " +
          std::to_string(n) + " vertices, " + (surface ? "on a curved surface" : "planar") + "; preset " +
          kPresets[preset].toStdString() + ", boundary " + kBoundaries[boundary].toStdString() + ", " +
          std::to_string(fixed_count) + " fixed (selected)");
  const char *kind = surface ? "signed against the surface, " : "";
  log(GLLogStream::FILTER, line((std::string("scaled Jacobian before: ") + kind).c_str(), r.input));
  log(GLLogStream::FILTER, line((std::string("scaled Jacobian after:  ") + kind).c_str(), r.output));
  if (surface) {
    log(GLLogStream::FILTER, line("Verdict (3D) before: ", r.input_verdict));
    log(GLLogStream::FILTER, line("Verdict (3D) after:  ", r.output_verdict));
  }
  log(GLLogStream::FILTER, std::to_string(r.iterations) + " sweeps, " + std::to_string(r.untangle_sweeps) +
                               " untangling; quadopt " + fixed3(r.seconds) + " s, filter " + fixed3(total) +
                               " s; " + std::to_string(moved) + " vertices moved");

  std::map<std::string, QVariant> out;
  out["surface"] = QVariant(surface);
  out["quads"] = QVariant(as_int(poly.quads));
  out["triangles"] = QVariant(as_int(poly.plain_triangles));
  out["fixed_vertices"] = QVariant(as_int(fixed_count));
  out["moved_vertices"] = QVariant(as_int(moved));
  out["input_min"] = QVariant(r.input.min);
  out["input_avg"] = QVariant(r.input.avg);
  out["input_max"] = QVariant(r.input.max);
  out["input_inverted"] = QVariant(as_int(r.input.inverted));
  out["output_min"] = QVariant(r.output.min);
  out["output_avg"] = QVariant(r.output.avg);
  out["output_max"] = QVariant(r.output.max);
  out["output_inverted"] = QVariant(as_int(r.output.inverted));
  if (surface) {
    out["input_verdict_min"] = QVariant(r.input_verdict.min);
    out["input_verdict_avg"] = QVariant(r.input_verdict.avg);
    out["output_verdict_min"] = QVariant(r.output_verdict.min);
    out["output_verdict_avg"] = QVariant(r.output_verdict.avg);
    out["max_distance"] = QVariant(r.max_distance);
  }
  out["face_quality_min"] = QVariant(quality_min);
  out["face_quality_avg"] = QVariant(quality_sum / static_cast<double>(faces));
  out["sweeps"] = QVariant(as_int(r.iterations));
  out["effort"] = QVariant(static_cast<int>(r.effort));
  out["seconds"] = QVariant(r.seconds);
  out["filter_seconds"] = QVariant(total);
  return out;
}

MESHLAB_PLUGIN_NAME_EXPORTER(QuadoptFilterPlugin)
