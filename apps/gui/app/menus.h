#pragma once
// The window's Motion and View menus. Motion chooses the map's method (one checked entry) and
// asks for the parameter dialogs and the clip back; the window answers its signals. View toggles
// how the two views show things (the camera following the root, sketch mode, the magnifier, the
// shading of trustworthy blends); nothing else depends on those.
#include <QObject>

#include "motionmap/embed/embed.h"

class QActionGroup;
class QMainWindow;
class QMenu;

namespace motionmap::studio {

class MapView;
class SkeletonView;

class MotionMenu : public QObject {
  Q_OBJECT
 public:
  /// Adds the Motion menu to `window`'s menu bar, with `method` checked.
  MotionMenu(QMainWindow* window, embed::Method method);
  /// Checks `method`'s entry (emits nothing).
  void setMethod(embed::Method method);

 signals:
  void methodChosen(motionmap::embed::Method method);
  /// Parameters…
  void parametersRequested();
  /// Synthesis…
  void synthesisRequested();
  /// Retime Keys…
  void retimeKeysRequested();
  /// Show clip: back from a synthesized motion to the clip.
  void showClipRequested();

 private:
  QActionGroup* m_methods;
};

/// Adds the View menu to `window`'s menu bar, its entries bound to `skeleton` and `map`.
QMenu* addViewMenu(QMainWindow* window, SkeletonView* skeleton, MapView* map);

}  // namespace motionmap::studio
