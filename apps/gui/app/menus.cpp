#include "app/menus.h"

#include <QAction>
#include <QActionGroup>
#include <QMainWindow>
#include <QMenu>
#include <QMenuBar>

#include "app/help_dialogs.h"
#include "common/parameters.h"
#include "map/map_view.h"
#include "scene/skeleton_view.h"

namespace motionmap::studio {

namespace {
/// What each method's map shows, for its entry's tooltip.
QString methodHelp(embed::Method method) {
  switch (method) {
    case embed::Method::Pca:
      return MotionMenu::tr("PCA: the two directions in which the frames' features vary most");
    case embed::Method::Svd:
      return MotionMenu::tr("SVD: PCA without centring the features");
    case embed::Method::Mds:
      return MotionMenu::tr("MDS: keeps the distances between all pairs of frames");
    case embed::Method::Isomap:
      return MotionMenu::tr(
          "Isomap: keeps the distances along the k-nearest-neighbour graph of the frames");
    case embed::Method::LaplacianEigenmap:
      return MotionMenu::tr("Laplacian eigenmap: keeps neighbouring frames close together");
    case embed::Method::Lle:
      return MotionMenu::tr(
          "Locally linear embedding: keeps each frame the same blend of its neighbours");
    case embed::Method::Umap:
      return MotionMenu::tr(
          "UMAP: keeps each frame's nearest neighbours together, apart from the rest");
    case embed::Method::Gplvm:
      return MotionMenu::tr(
          "GP-LVM: the latent points from which a Gaussian process best predicts the poses "
          "(an optimisation, slower than the others; sparse above 1 000 frames)");
  }
  return {};
}
}  // namespace

MotionMenu::MotionMenu(QMainWindow* window, embed::Method method)
    : QObject(window), m_methods(new QActionGroup(this)) {
  QMenu* motion = window->menuBar()->addMenu(tr("&Motion"));
  int key = Qt::Key_1;  // 1–8 pick the methods, in the menu's order
  for (embed::Method m : embed::all_methods()) {
    QAction* action = motion->addAction(methodLabel(m));
    if (key <= Qt::Key_9) action->setShortcut(QKeySequence(key++));
    explain(action, methodHelp(m) + tr(" (computed once, then cached)"));
    action->setCheckable(true);
    action->setChecked(m == method);
    action->setData(int(m));
    m_methods->addAction(action);
    connect(action, &QAction::triggered, this, [this, m] { emit methodChosen(m); });
  }
  motion->addSeparator();
  explain(motion->addAction(tr("&Parameters…"), this, &MotionMenu::parametersRequested),
          tr("The map's parameters: k, the LE heat, the features, the distance and the joints "
             "left out"));
  explain(motion->addAction(tr("S&ynthesis…"), this, &MotionMenu::synthesisRequested),
          tr("How a drag blends poses and how a sketch becomes a motion"));
  explain(motion->addAction(tr("&Retime Keys…"), this, &MotionMenu::retimeKeysRequested),
          tr("The times of the current in-between take's keys (Ctrl-click frames on the map to "
             "place keys)"));
  explain(motion->addAction(tr("Show &clip"), this, &MotionMenu::showClipRequested),
          tr("Back from a synthesized motion to the clip"));
}

void MotionMenu::setMethod(embed::Method method) {
  for (QAction* a : m_methods->actions()) a->setChecked(a->data().toInt() == int(method));
}

QMenu* addViewMenu(QMainWindow* window, SkeletonView* skeleton, MapView* map) {
  QMenu* view = window->menuBar()->addMenu(QMainWindow::tr("&View"));
  QAction* follow = view->addAction(QMainWindow::tr("&Follow root"));
  explain(follow, QMainWindow::tr("The 3-D view's camera follows the motion's root"));
  follow->setCheckable(true);
  follow->setChecked(true);
  QObject::connect(follow, &QAction::toggled, skeleton, &SkeletonView::setFollowRoot);
  QAction* sketch = view->addAction(QMainWindow::tr("&Sketch mode (drag draws a path)"));
  sketch->setCheckable(true);
  explain(sketch, QMainWindow::tr("A plain drag on the map sketches a path (as Shift-drag does) "
                                  "instead of blending a pose"));
  sketch->setShortcut(QKeySequence(QMainWindow::tr("S")));
  QObject::connect(sketch, &QAction::toggled, map, &MapView::setSketchMode);
  QAction* lens = view->addAction(QMainWindow::tr("&Magnifier (wheel: power)"));
  lens->setCheckable(true);
  explain(lens, QMainWindow::tr("A fisheye lens under the mouse that spreads dense stretches of "
                                "the map; the wheel changes its power"));
  lens->setShortcut(QKeySequence(QMainWindow::tr("M")));
  QObject::connect(lens, &QAction::toggled, map, &MapView::setLensEnabled);
  QAction* shading = view->addAction(QMainWindow::tr("Shade &trustworthy blends"));
  shading->setObjectName(QStringLiteral("shadeTrustworthyBlends"));  // motionmap-studio --shade
  shading->setCheckable(true);
  explain(shading, QMainWindow::tr("Green where a map point is within 5 % of the map's size of a "
                                   "frame: a drag there blends frames close to it. The same "
                                   "meaning at any frame rate; a key in the plot says so"));
  QObject::connect(shading, &QAction::toggled, map, &MapView::setShadingVisible);
  QAction* whole = view->addAction(QMainWindow::tr("Whole &map (reset zoom)"));
  explain(whole, QMainWindow::tr("Shows the whole map again after zooming (wheel) or panning "
                                 "(middle drag, Space+drag); also Home on the map, or a "
                                 "double-click"));
  whole->setShortcut(QKeySequence(Qt::CTRL | Qt::Key_0));
  QObject::connect(whole, &QAction::triggered, map, &MapView::resetView);
  view->addSeparator();
  QAction* full = view->addAction(QMainWindow::tr("F&ull screen"));
  full->setCheckable(true);
  full->setShortcut(QKeySequence(Qt::Key_F11));
  explain(full, QMainWindow::tr("Shows the window on the whole screen, or back as it was"));
  // From the window's state, so a window the window manager took out of full screen stays right.
  QObject::connect(full, &QAction::triggered, window, [window, full] {
    window->setWindowState(window->windowState() ^ Qt::WindowFullScreen);
    full->setChecked(window->windowState().testFlag(Qt::WindowFullScreen));
  });
  return view;
}

}  // namespace motionmap::studio
