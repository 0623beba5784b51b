#include "app/help_dialogs.h"

#include <QAction>
#include <QApplication>
#include <QDialogButtonBox>
#include <QHeaderView>
#include <QLabel>
#include <QMainWindow>
#include <QMenu>
#include <QMenuBar>
#include <QMessageBox>
#include <QSet>
#include <QTableWidget>
#include <QVBoxLayout>

// Versions as the build found them (apps/gui/CMakeLists.txt); empty when CMake did not say.
#ifndef MOTIONMAP_VERSION
#define MOTIONMAP_VERSION ""
#endif
#ifndef MOTIONMAP_EIGEN_VERSION
#define MOTIONMAP_EIGEN_VERSION ""
#endif
#ifndef MOTIONMAP_SPECTRA_VERSION
#define MOTIONMAP_SPECTRA_VERSION ""
#endif
#ifndef MOTIONMAP_NANOFLANN_VERSION
#define MOTIONMAP_NANOFLANN_VERSION ""
#endif
#ifndef MOTIONMAP_HDF5_VERSION
#define MOTIONMAP_HDF5_VERSION ""
#endif

namespace motionmap::studio {

QAction* explain(QAction* action, const QString& help) {
  action->setToolTip(help);
  action->setStatusTip(help);
  return action;
}

QString plainText(const QString& text) {
  QString plain = text;
  plain.replace(QLatin1String("&&"), QChar(0x1));  // a literal & survives
  plain.remove(QLatin1Char('&'));
  plain.replace(QChar(0x1), QLatin1Char('&'));
  return plain;
}

void showMenuToolTips(QMainWindow* window) {
  for (QMenu* menu : window->findChildren<QMenu*>()) menu->setToolTipsVisible(true);
}

namespace {

QString keysOf(const QAction* action) {
  QStringList keys;
  for (const QKeySequence& k : action->shortcuts()) keys << k.toString(QKeySequence::NativeText);
  return keys.join(QStringLiteral(", "));
}

/// The menu's entries with shortcuts, submenus' after their own, in menu order.
void collect(const QMenu* menu, const QString& where, std::vector<ShortcutRow>& rows,
             QSet<const QAction*>& seen) {
  for (const QAction* action : menu->actions()) {
    if (action->isSeparator()) continue;
    if (const QMenu* sub = action->menu()) {
      collect(sub, where + QStringLiteral(" → ") + plainText(sub->title()), rows, seen);
      continue;
    }
    if (action->shortcuts().isEmpty() || seen.contains(action)) continue;
    seen.insert(action);
    rows.push_back({keysOf(action), plainText(action->text()), where});
  }
}

}  // namespace

std::vector<ShortcutRow> shortcutRows(const QMainWindow* window) {
  std::vector<ShortcutRow> rows;
  QSet<const QAction*> seen;
  if (const auto* bar = qobject_cast<const QMenuBar*>(window->menuWidget())) {
    for (const QAction* top : bar->actions()) {
      if (const QMenu* menu = top->menu()) collect(menu, plainText(menu->title()), rows, seen);
    }
  }
  // Actions on the window or on one of its widgets (a view's own keys), not in a menu.
  for (const QAction* action : window->findChildren<QAction*>()) {
    if (action->shortcuts().isEmpty() || seen.contains(action) || action->isSeparator()) continue;
    seen.insert(action);
    QString where = QObject::tr("Window");
    if (const auto* widget = qobject_cast<const QWidget*>(action->parent());
        widget && widget != window && !widget->accessibleName().isEmpty())
      where = widget->accessibleName();
    rows.push_back({keysOf(action), plainText(action->text()), where});
  }
  return rows;
}

std::vector<ShortcutRow> gestureRows() {
  const QString map = QObject::tr("Map view");
  const QString view3d = QObject::tr("3-D view");
  const QString bar = QObject::tr("Transport bar");
  const QString window = QObject::tr("Window");
  return {
      {QObject::tr("Hover"), QObject::tr("Names the frame under the mouse (within 12 px)"), map},
      {QObject::tr("Click"), QObject::tr("Jumps to the frame nearest the click"), map},
      {QObject::tr("Drag"), QObject::tr("Shows the pose blended at the point under the mouse"),
       map},
      {QObject::tr("Shift+drag, or drag in sketch mode"),
       QObject::tr("Sketches a path; on release the motion along it is synthesized and played"),
       map},
      {QObject::tr("Ctrl+click"),
       QObject::tr("Places a key pose (the frame there, or the map point); two keys make an "
                   "in-between take. Ctrl+click a key of the current in-between take removes it, "
                   "dragging a key moves it"),
       map},
      {QObject::tr("Wheel (magnifier on)"), QObject::tr("Changes the magnifier's power"), map},
      {QObject::tr("Wheel"), QObject::tr("Zooms around the mouse (magnifier off)"), map},
      {QObject::tr("Middle drag, or Space+drag"),
       QObject::tr("Pans the map (Space pressed and released alone still plays / pauses)"), map},
      {QObject::tr("Right drag / Shift+right drag"),
       QObject::tr("Selects the frames in a box / a lasso: listed per clip in the Selection "
                   "panel, to play one after another or export (a clip list, CSV); a right click "
                   "clears it"),
       map},
      {QObject::tr("Double-click, or Home (map focused and zoomed)"),
       QObject::tr("Shows the whole map again (also View → Whole map, Ctrl+0)"), map},
      {QObject::tr("Click a value in the Legend"),
       QObject::tr("Hides or shows the frames of that value of the label colouring the map "
                   "(View → Colour by): hidden frames are not drawn, hovered or selected"),
       map},
      {QObject::tr("Ctrl+click a value in the Legend"),
       QObject::tr("Shows that value alone; again, every value"), map},
      {QObject::tr("Left drag"), QObject::tr("Orbits the camera"), view3d},
      {QObject::tr("Drag a joint"),
       QObject::tr("Poses the body from the map so that the joint follows the mouse (a map "
                   "computed here)"),
       view3d},
      {QObject::tr("Shift+click a joint"),
       QObject::tr("Pins or unpins it: a joint drag holds pinned joints where they are"), view3d},
      {QObject::tr("Middle or right drag"), QObject::tr("Pans the camera"), view3d},
      {QObject::tr("Wheel"), QObject::tr("Zooms"), view3d},
      {QObject::tr("Hover a joint"), QObject::tr("Names the joint (within 12 px)"), view3d},
      {QObject::tr("Click a joint"),
       QObject::tr(
           "Selects it (as in the Joints panel): highlighted, with its trail over the clip"),
       view3d},
      {QObject::tr("Home (3-D view focused)"),
       QObject::tr("Resets the camera (the window's Home goes to the first frame otherwise)"),
       view3d},
      {QObject::tr("Delete (Takes list focused)"), QObject::tr("Removes the selected take"),
       QObject::tr("Takes panel")},
      {QObject::tr("F2 or double-click (Takes list)"), QObject::tr("Renames the selected take"),
       QObject::tr("Takes panel")},
      {QObject::tr("Drag a control point"),
       QObject::tr("Reshapes the current take's path; on release its motion is synthesized again"),
       map},
      {QObject::tr("Drag the slider"), QObject::tr("Scrubs through the motion"), bar},
      {QObject::tr("Click the frame or time field, type, Enter"),
       QObject::tr("Goes to that frame, or to the frame nearest that time; the keys go back to "
                   "the window"),
       bar},
      {QObject::tr("Esc in the frame or time field"),
       QObject::tr("Leaves the field without changing the frame"), bar},
      {QObject::tr("Drop files"),
       QObject::tr("Opens the first, adds the others to its map (with Ctrl: all join the open "
                   "map)"),
       window},
  };
}

ShortcutsDialog::ShortcutsDialog(const QMainWindow* window, QWidget* parent)
    : QDialog(parent), m_table(new QTableWidget(this)) {
  setWindowTitle(tr("Keyboard and mouse — MotionMap Studio"));
  std::vector<ShortcutRow> rows = shortcutRows(window);
  const std::size_t keyRows = rows.size();
  for (ShortcutRow& row : gestureRows()) rows.push_back(std::move(row));
  m_table->setColumnCount(3);
  m_table->setHorizontalHeaderLabels({tr("Key or gesture"), tr("What"), tr("Where")});
  m_table->setRowCount(int(rows.size()));
  m_table->setEditTriggers(QAbstractItemView::NoEditTriggers);
  m_table->setSelectionBehavior(QAbstractItemView::SelectRows);
  m_table->verticalHeader()->hide();
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const QString cells[] = {rows[r].keys, rows[r].what, rows[r].where};
    for (int c = 0; c < 3; ++c) {
      auto* item = new QTableWidgetItem(cells[c]);
      if (c == 0) {
        QFont font = item->font();
        font.setBold(r < keyRows);  // keys bold, gestures plain
        item->setFont(font);
      }
      m_table->setItem(int(r), c, item);
    }
  }
  // Keys and places as wide as they are; the descriptions take the rest and wrap.
  m_table->setWordWrap(true);
  QHeaderView* header = m_table->horizontalHeader();
  header->setSectionResizeMode(0, QHeaderView::ResizeToContents);
  header->setSectionResizeMode(1, QHeaderView::Stretch);
  header->setSectionResizeMode(2, QHeaderView::ResizeToContents);
  m_table->verticalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
  auto* note = new QLabel(
      tr("Window keys work as soon as the window is active, whichever part has the focus, except "
         "while typing in a number field."));
  note->setWordWrap(true);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Close);
  connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
  auto* layout = new QVBoxLayout(this);
  layout->addWidget(note);
  layout->addWidget(m_table, 1);
  layout->addWidget(buttons);
  resize(820, 640);
}

QString studioVersion() {
  return QStringLiteral(MOTIONMAP_VERSION);
}

QString aboutText() {
  auto version = [](const char* v) {
    const QString s = QString::fromUtf8(v);
    return s.isEmpty() ? QObject::tr("(version not known to the build)") : s;
  };
  return QObject::tr(
             "<h3>MotionMap Studio %1</h3>"
             "<p>Every frame of a motion-capture clip as a point on a 2-D map: play it, "
             "drag on the map to blend a pose, sketch a path to synthesize a motion.</p>"
             "<p>Built with Qt %2 (running on Qt %3), Eigen %4, Spectra %5, nanoflann "
             "%6, HDF5 %7; compiler %8.</p>")
      .arg(studioVersion(), QStringLiteral(QT_VERSION_STR), QString::fromUtf8(qVersion()),
           version(MOTIONMAP_EIGEN_VERSION), version(MOTIONMAP_SPECTRA_VERSION),
           version(MOTIONMAP_NANOFLANN_VERSION), version(MOTIONMAP_HDF5_VERSION),
#if defined(__clang__)
           QStringLiteral("Clang " __clang_version__)
#elif defined(__GNUC__)
           QStringLiteral("GCC " __VERSION__)
#else
           QObject::tr("unknown")
#endif
      );
}

QMenu* addHelpMenu(QMainWindow* window) {
  QMenu* help = window->menuBar()->addMenu(QObject::tr("&Help"));
  QAction* keys = help->addAction(QObject::tr("&Keyboard and mouse…"), window, [window] {
    // Not modal: the list can stay open beside the window.
    auto* dialog = new ShortcutsDialog(window, window);
    dialog->setAttribute(Qt::WA_DeleteOnClose);
    dialog->show();
  });
  keys->setShortcut(QKeySequence(Qt::Key_F1));
  explain(keys, QObject::tr("Lists every keyboard shortcut of the window and the mouse gestures"));
  explain(help->addAction(QObject::tr("&About MotionMap Studio…"), window,
                          [window] {
                            QMessageBox::about(window, QObject::tr("About MotionMap Studio"),
                                               aboutText());
                          }),
          QObject::tr("The version of MotionMap Studio and of the libraries it was built with"));
  explain(help->addAction(QObject::tr("About &Qt…"), qApp, &QApplication::aboutQt),
          QObject::tr("The version and licence of the Qt toolkit the window runs on"));
  return help;
}

}  // namespace motionmap::studio
