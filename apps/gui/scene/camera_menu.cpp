#include "scene/camera_menu.h"

#include <QAction>
#include <QMenu>

#include "scene/skeleton_view.h"

namespace motionmap::studio {

QMenu* addCameraMenu(QMenu* view, SkeletonView* skeleton) {
  QMenu* camera = view->addMenu(QMenu::tr("&Camera"));
  camera->setToolTipsVisible(true);
  const auto add = [&](const QString& text, const QString& keys, const QString& tip, auto slot) {
    QAction* action = camera->addAction(text);
    if (!keys.isEmpty()) action->setShortcut(QKeySequence(keys));
    // Window-wide, like the menus' other shortcuts: no click into the view needed first.
    action->setShortcutContext(Qt::WindowShortcut);
    action->setToolTip(tip);
    action->setObjectName(text);
    QObject::connect(action, &QAction::triggered, skeleton, slot);
    return action;
  };
  add(QMenu::tr("&Frame character"), QStringLiteral("F"),
      QMenu::tr("Centre the current pose and zoom until it fills the 3-D view"),
      [skeleton] { skeleton->frameCharacter(); })
      ->setObjectName("frameCharacter");
  add(QMenu::tr("&Reset camera (Home on the 3-D view)"), QString(),
      QMenu::tr("Default angle, no pan, and the whole clip's volume framed"),
      [skeleton] { skeleton->resetCamera(); })
      ->setObjectName("resetCamera");
  camera->addSeparator();
  add(QMenu::tr("F&ront"), QStringLiteral("Ctrl+1"), QMenu::tr("Look from +Z, level"), [skeleton] {
    skeleton->applyCameraPreset(CameraPreset::Front);
  })->setObjectName("cameraFront");
  add(QMenu::tr("&Side"), QStringLiteral("Ctrl+3"), QMenu::tr("Look from +X, level"), [skeleton] {
    skeleton->applyCameraPreset(CameraPreset::Side);
  })->setObjectName("cameraSide");
  add(QMenu::tr("&Top"), QStringLiteral("Ctrl+7"), QMenu::tr("Look straight down"), [skeleton] {
    skeleton->applyCameraPreset(CameraPreset::Top);
  })->setObjectName("cameraTop");
  return camera;
}

}  // namespace motionmap::studio
