#pragma once
// The Help menu (Keyboard and mouse… F1, About MotionMap Studio…, About Qt…) and what it shows.
// The shortcut list is read from the window's own QActions when the dialog opens (every menu
// entry or window action with a shortcut, under its menu), so it cannot go stale when an entry or
// a key changes; the mouse gestures, which are no actions, are one table here (gestureRows).
//
// Every action of Studio explains itself: explain() gives it a tooltip (menus show tooltips, see
// showMenuToolTips) and the same status-bar tip. The rule the tests check: every action's
// tooltip says more than its menu text.
#include <QDialog>
#include <QString>
#include <vector>

class QAction;
class QMainWindow;
class QMenu;
class QTableWidget;
class QWidget;

namespace motionmap::studio {

/// Sets `action`'s tooltip and status tip to `help`; returns `action`.
QAction* explain(QAction* action, const QString& help);

/// An entry's text as shown: mnemonics (&) removed, && kept as &.
QString plainText(const QString& text);

/// Shows the tooltips of every menu of `window` (QMenu::setToolTipsVisible). The window calls it
/// once its menus are built.
void showMenuToolTips(QMainWindow* window);

/// One line of the shortcut list.
struct ShortcutRow {
  QString keys;   ///< the shortcuts, as the platform writes them ("Shift+Right, F5")
  QString what;   ///< the entry's text, or what the gesture does
  QString where;  ///< "Playback", "View → Camera", "Map view", …
};

/// Every action of `window` with a shortcut: menu entries in menu-bar order (submenus as
/// "View → Camera"), then actions outside the menus (where: their widget's accessibleName,
/// else "Window").
std::vector<ShortcutRow> shortcutRows(const QMainWindow* window);
/// The mouse gestures and the number fields' keys (keys: the gesture; where: the view).
std::vector<ShortcutRow> gestureRows();

/// Help → Keyboard and mouse…: shortcutRows, then gestureRows, in one table.
class ShortcutsDialog : public QDialog {
  Q_OBJECT
 public:
  explicit ShortcutsDialog(const QMainWindow* window, QWidget* parent = nullptr);
  /// Columns: keys or gesture, what, where.
  QTableWidget* table() const { return m_table; }

 private:
  QTableWidget* m_table;
};

/// The version of MotionMap (the CMake project version).
QString studioVersion();
/// About's text (rich text): the version, what the app does, and the libraries it was built
/// with (Qt at build and at run time, Eigen, Spectra, nanoflann, HDF5) and the compiler.
QString aboutText();

/// Adds the Help menu to `window`'s menu bar.
QMenu* addHelpMenu(QMainWindow* window);

}  // namespace motionmap::studio
