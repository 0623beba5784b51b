#include "menus.h"

#include <QAction>
#include <QActionGroup>
#include <QMainWindow>
#include <QMenu>
#include <QMenuBar>

#include "map_view.h"
#include "parameters.h"
#include "skeleton_view.h"

namespace motionmap::studio {

MotionMenu::MotionMenu(QMainWindow* window, embed::Method method)
    : QObject(window), m_methods(new QActionGroup(this)) {
  QMenu* motion = window->menuBar()->addMenu(tr("&Motion"));
  for (embed::Method m : embed::all_methods()) {
    QAction* action = motion->addAction(methodLabel(m));
    action->setCheckable(true);
    action->setChecked(m == method);
    action->setData(int(m));
    m_methods->addAction(action);
    connect(action, &QAction::triggered, this, [this, m] { emit methodChosen(m); });
  }
  motion->addSeparator();
  motion->addAction(tr("&Parameters…"), this, &MotionMenu::parametersRequested);
  motion->addAction(tr("S&ynthesis…"), this, &MotionMenu::synthesisRequested);
  motion->addAction(tr("Show &clip"), this, &MotionMenu::showClipRequested);
}

void MotionMenu::setMethod(embed::Method method) {
  for (QAction* a : m_methods->actions()) a->setChecked(a->data().toInt() == int(method));
}

QMenu* addViewMenu(QMainWindow* window, SkeletonView* skeleton, MapView* map) {
  QMenu* view = window->menuBar()->addMenu(QMainWindow::tr("&View"));
  QAction* follow = view->addAction(QMainWindow::tr("&Follow root"));
  follow->setCheckable(true);
  follow->setChecked(true);
  QObject::connect(follow, &QAction::toggled, skeleton, &SkeletonView::setFollowRoot);
  QAction* sketch = view->addAction(QMainWindow::tr("&Sketch mode (drag draws a path)"));
  sketch->setCheckable(true);
  sketch->setShortcut(QKeySequence(QMainWindow::tr("S")));
  QObject::connect(sketch, &QAction::toggled, map, &MapView::setSketchMode);
  QAction* lens = view->addAction(QMainWindow::tr("&Magnifier (wheel: power)"));
  lens->setCheckable(true);
  lens->setShortcut(QKeySequence(QMainWindow::tr("M")));
  QObject::connect(lens, &QAction::toggled, map, &MapView::setLensEnabled);
  QAction* shading = view->addAction(QMainWindow::tr("Shade &trustworthy blends"));
  shading->setCheckable(true);
  shading->setToolTip(QMainWindow::tr(
      "Green where a map point is within 5 % of the map's size of a frame: a drag there blends "
      "frames close to it. The same meaning at any frame rate; a key in the plot says so"));
  QObject::connect(shading, &QAction::toggled, map, &MapView::setShadingVisible);
  return view;
}

}  // namespace motionmap::studio
