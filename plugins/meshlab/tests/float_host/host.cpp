// SPDX-License-Identifier: GPL-3.0-or-later
//
// host.cpp: a minimal MeshLab application for the float (desktop) build of the plugin. It links
// a float libmeshlab-common, as the meshlab executable does, loads the plugin through MeshLab's
// PluginManager (the plugin built with QUADOPT_MESHLAB_COMMON=NONE resolves MeshLab's symbols
// from this executable), reads an OBJ with vcglib's reader (faux edges as MeshLab's own reader
// sets them), runs the filter and writes the result: one line per vertex (x y z, as floats
// printed exactly), then one line per triangle (its quality).
//
//   host PLUGIN IN.obj OUT.txt [cancel]
//
// With `cancel` the progress callback returns false at its first call: the filter must fail
// with "cancelled" and leave the mesh as read (OUT.txt is written all the same). Exit status 0
// when the filter ran, 2 when it failed (its message on stderr), 1 on a usage or set-up error.
#include <common/mlexception.h>
#include <common/plugins/interfaces/filter_plugin.h>
#include <common/plugins/plugin_manager.h>
#include <wrap/io_trimesh/import_obj.h>

#include <cstdio>
#include <cstring>
#include <string>

namespace {
bool cancel = false;
bool progress(const int, const char *) { return !cancel; }
}  // namespace

int main(int argc, char **argv) {
  if (argc < 4 || argc > 5 || (argc == 5 && std::strcmp(argv[4], "cancel") != 0)) {
    std::fprintf(stderr, "usage: host PLUGIN IN.obj OUT.txt [cancel]\n");
    return 1;
  }
  cancel = argc == 5;
  try {
    PluginManager pm;
    MeshLabPlugin *p = pm.loadPlugin(QString::fromLocal8Bit(argv[1]));
    FilterPlugin *fp = dynamic_cast<FilterPlugin *>(p);
    if (fp == nullptr || fp->actions().empty()) {
      std::fprintf(stderr, "host: %s is not a filter plugin\n", argv[1]);
      return 1;
    }
    QAction *action = fp->actions().front();
    MeshDocument md;
    MeshModel *mm = md.addNewMesh(QString(), "mesh");
    vcg::tri::io::ImporterOBJ<CMeshO>::Info info;
    if (vcg::tri::io::ImporterOBJ<CMeshO>::Open(mm->cm, argv[2], info) != 0) {
      std::fprintf(stderr, "host: cannot read %s\n", argv[2]);
      return 1;
    }
    GLLogStream log;
    fp->setLog(&log);
    RichParameterList params = fp->initParameterList(action, md);
    unsigned int mask = 0;
    int rc = 0;
    try {
      fp->applyFilter(action, params, md, mask, progress);
      for (const auto &line : log.logStringList()) std::printf("%s\n", qUtf8Printable(line.second));
    } catch (const MLException &e) {
      std::fprintf(stderr, "%s\n", e.what());
      rc = 2;
    }
    FILE *out = std::fopen(argv[3], "w");
    if (out == nullptr) return 1;
    const bool quality = mm->hasDataMask(MeshModel::MM_FACEQUALITY);
    for (const auto &v : mm->cm.vert) {
      std::fprintf(out, "%.9g %.9g %.9g\n", double(v.cP()[0]), double(v.cP()[1]), double(v.cP()[2]));
    }
    for (const auto &f : mm->cm.face) std::fprintf(out, "%.9g\n", quality ? double(f.cQ()) : -9.0);
    std::fclose(out);
    return rc;
  } catch (const std::exception &e) {
    std::fprintf(stderr, "host: %s\n", e.what());
    return 1;
  }
}
