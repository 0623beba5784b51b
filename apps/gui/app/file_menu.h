#pragma once
// The window's File menu: Open…, Open map… (a saved .mmap.h5), Open sample golf swing, Open recent,
// Add clip to the map…, Export motion…, Export map…, Export picture…, Export animation… and Quit.
// It runs the file dialogs (they start in the folder of the last file opened; the export dialogs
// in the folder of the last picture or animation exported, with a name suggested from the clip,
// method and frame shown), keeps the recent files, and hands what the user chose to the window as
// signals. The recent files and folders live in QSettings ("recentFiles", "lastDir",
// "lastExportDir"), shared with the next session.
#include <functional>

#include <QObject>
#include <QString>
#include <QStringList>
#include <QUrl>

#include "export/animation_export.h"
#include "export/export_names.h"

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
  /// Export picture… (Ctrl+Shift+P) and Export animation… (Ctrl+Shift+A): disabled until a motion
  /// is shown (setMotionShown).
  QAction* exportPictureAction() const { return m_exportPicture; }
  QAction* exportAnimationAction() const { return m_exportAnimation; }
  void setMotionShown(bool shown);
  /// What the export dialogs ask of the window when they open: the names to suggest, the folder,
  /// the animation's frames and rate (without a source: no suggestion, the last folder).
  void setContextSource(std::function<ExportContext()> source) { m_context = std::move(source); }
  ExportContext context() const;
  /// The folder the export dialogs start in next time (QSettings "lastExportDir").
  void rememberExportDir(const QString& dir);
  /// Files dropped on the window: the first opens (`open`, replacing the clip) and the others
  /// join its map (`add`); with `addAll` (Ctrl held over an open map) every one joins. Files
  /// that are not local are skipped; the first that fails (false) stops the rest.
  static void openDropped(const QList<QUrl>& urls, bool addAll,
                          const std::function<bool(const QString&)>& open,
                          const std::function<bool(const QString&)>& add);

 signals:
  /// Open…, Open map… or a recent file (a clip, or a map file: MainWindow::openFile tells).
  void openRequested(const QString& path);
  void sampleRequested();
  /// Add clip to the map…: the files chosen, in order.
  void addRequested(const QStringList& paths);
  void exportMotionRequested(const QString& path);
  void exportMapRequested(const QString& path);
  void exportPictureRequested(const QString& path, motionmap::studio::PictureKind kind);
  void exportAnimationRequested(const motionmap::studio::AnimationSettings& settings);

 private:
  void updateRecentMenu();

  QMainWindow* m_window;
  QMenu* m_recentMenu = nullptr;
  QAction* m_exportMotion = nullptr;
  QAction* m_exportMap = nullptr;
  QAction* m_exportPicture = nullptr;
  QAction* m_exportAnimation = nullptr;
  std::function<ExportContext()> m_context;
  QString m_lastDir;
  QString m_exportDir;  ///< where the last picture or animation was exported
};

}  // namespace motionmap::studio
