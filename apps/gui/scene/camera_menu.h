#pragma once
// View → Camera: framing, reset and the front/side/top presets of the 3-D view.
class QMenu;

namespace motionmap::studio {

class SkeletonView;

/// Adds the Camera submenu to `view` (the View menu): Frame character (F, window-wide), Reset
/// camera (Home while the 3-D view has the keyboard focus; the menu entry shows no shortcut, the
/// window's Home goes to the first frame), Front (Ctrl+1), Side (Ctrl+3), Top (Ctrl+7), each
/// acting on `skeleton`. Returns the submenu.
QMenu* addCameraMenu(QMenu* view, SkeletonView* skeleton);

}  // namespace motionmap::studio
