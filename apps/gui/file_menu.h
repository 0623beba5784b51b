#pragma once
// The window's File menu: Open…, Open map… (a saved .mmap.h5), Open sample golf swing, Open recent,
// Add clip to the map…, Export motion…, Export map… and Quit. It runs the file dialogs (they start
// in the folder of the last file opened), keeps the recent files, and hands what the user chose to
// the window as signals. Both lists live in QSettings ("recentFiles", "lastDir"), shared with the
// next session.
#include <QObject>
#include <QString>
#include <QStringList>

class QAction;
class QMainWindow;
class QMenu;

namespace motionmap::studio {

class FileMenu : public QObject {
  Q_OBJECT
 public:
  /// Recent files kept.
  static constexpr int kMaxRecent = 8;

  /// Adds the menu to `window`'s menu bar (its dialogs are modal over `window`; Quit closes it).
  explicit FileMenu(QMainWindow* window);

  /// Remembers a file opened or added: first of the recent files (an absolute path), and its
  /// folder is where the dialogs start.
  void remember(const QString& path);
  /// Newest first.
  QStringList recentFiles() const;
  QString lastDir() const { return m_lastDir; }

  /// Disabled until there is a synthesized motion.
  QAction* exportMotionAction() const { return m_exportMotion; }
  /// Disabled until there is a map.
  QAction* exportMapAction() const { return m_exportMap; }

 signals:
  /// Open…, Open map… or a recent file (a clip, or a map file: MainWindow::openFile tells).
  void openRequested(const QString& path);
  void sampleRequested();
  /// Add clip to the map…: the files chosen, in order.
  void addRequested(const QStringList& paths);
  void exportMotionRequested(const QString& path);
  void exportMapRequested(const QString& path);

 private:
  void updateRecentMenu();

  QMainWindow* m_window;
  QMenu* m_recentMenu = nullptr;
  QAction* m_exportMotion = nullptr;
  QAction* m_exportMap = nullptr;
  QString m_lastDir;
};

}  // namespace motionmap::studio
