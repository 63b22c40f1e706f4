// SPDX-License-Identifier: GPL-3.0-or-later
//
// filter_quadopt.h: a MeshLab filter plugin running quadopt, the quad-mesh quality optimizer,
// on the current mesh (Filters > Remeshing, Simplification and Reconstruction / Polygonal;
// pymeshlab: apply_coord_quadopt_quad_quality).
#ifndef QUADOPT_MESHLAB_FILTER_QUADOPT_H
#define QUADOPT_MESHLAB_FILTER_QUADOPT_H

#include <common/plugins/interfaces/filter_plugin.h>

class QuadoptFilterPlugin : public QObject, public FilterPlugin {
  Q_OBJECT
  MESHLAB_PLUGIN_IID_EXPORTER(FILTER_PLUGIN_IID)
  Q_INTERFACES(FilterPlugin)

 public:
  enum { FP_QUADOPT };

  QuadoptFilterPlugin();

  QString pluginName() const override;
  QString vendor() const override;
  QString filterName(ActionIDType filter) const override;
  QString pythonFilterName(ActionIDType filter) const override;
  QString filterInfo(ActionIDType filter) const override;
  FilterClass getClass(const QAction *action) const override;
  FilterArity filterArity(const QAction *action) const override;
  int getPreConditions(const QAction *action) const override;
  int postCondition(const QAction *action) const override;
  RichParameterList initParameterList(const QAction *action, const MeshModel &m) override;
  std::map<std::string, QVariant> applyFilter(const QAction *action, const RichParameterList &parameters,
                                              MeshDocument &md, unsigned int &postConditionMask,
                                              vcg::CallBackPos *cb) override;

 private:
  std::map<std::string, QVariant> optimize(const RichParameterList &parameters, MeshDocument &md,
                                           vcg::CallBackPos *cb);
};

#endif  // QUADOPT_MESHLAB_FILTER_QUADOPT_H
