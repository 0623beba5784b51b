#include "app/file_menu.h"

#include <QAction>
#include <QDir>
#include <QFileDialog>
#include <QFileInfo>
#include <QMainWindow>
#include <QMenu>
#include <QMenuBar>
#include <QSettings>
#include <QUrl>

#include "app/help_dialogs.h"
#include "export/export_dialogs.h"

namespace motionmap::studio {

FileMenu::FileMenu(QMainWindow* window) : QObject(window), m_window(window) {
  m_lastDir = QSettings().value("lastDir").toString();
  m_exportDir = QSettings().value("lastExportDir").toString();
  const QString clips = tr("Motion capture (*.bvh *.amc);;All files (*)");
  QMenu* file = window->menuBar()->addMenu(tr("&File"));
  explain(file->addAction(tr("&Open…"), QKeySequence::Open, this,
                          [this, clips] {
                            const QString path = QFileDialog::getOpenFileName(
                                m_window, tr("Open clip"), m_lastDir, clips);
                            if (!path.isEmpty()) emit openRequested(path);
                          }),
          tr("Opens a clip (.bvh, or .amc with its .asf) and computes its map"));
  explain(file->addAction(tr("Open &map…"), QKeySequence(tr("Ctrl+M")), this,
                          [this] {
                            const QString path = QFileDialog::getOpenFileName(
                                m_window, tr("Open map file"), m_lastDir,
                                tr("Map files (*.mmap.h5 *.h5 *.hdf5);;All files (*)"));
                            // The window tells maps from clips.
                            if (!path.isEmpty()) emit openRequested(path);
                          }),
          tr("Opens a map saved by `motionmap map --save` without computing it again"));
  explain(file->addAction(tr("Open &sample golf swing"), this, &FileMenu::sampleRequested),
          tr("Opens the built-in golf swing (no file needed)"));
  m_recentMenu = file->addMenu(tr("Open &recent"));
  explain(file->addAction(tr("&Add clip to the map…"), QKeySequence(tr("Ctrl+Shift+O")), this,
                          [this, clips] {
                            const QStringList paths = QFileDialog::getOpenFileNames(
                                m_window, tr("Add clips of the same skeleton"), m_lastDir, clips);
                            if (!paths.isEmpty()) emit addRequested(paths);
                          }),
          tr("Adds clips of the same skeleton to the open clip's map"));
  file->addSeparator();
  // The export dialogs start with a name suggested from what is shown (64_08-synth.bvh, …).
  m_exportMotion = file->addAction(tr("&Export motion…"), QKeySequence(tr("Ctrl+E")), this, [this] {
    const ExportContext c = context();
    const QString path = QFileDialog::getSaveFileName(
        m_window, tr("Export motion"), QDir(c.folder).filePath(motionFileName(c.naming)),
        tr("BVH (*.bvh)"));
    if (path.isEmpty()) return;
    rememberExportDir(QFileInfo(path).absolutePath());
    emit exportMotionRequested(path);
  });
  explain(m_exportMotion, tr("Writes the synthesized motion as BVH"));
  m_exportMotion->setEnabled(false);
  m_exportMap = file->addAction(tr("Export &map…"), QKeySequence(tr("Ctrl+Shift+E")), this, [this] {
    const ExportContext c = context();
    const QString path = QFileDialog::getSaveFileName(
        m_window, tr("Export map"), QDir(c.folder).filePath(mapFileName(c.naming, "png")),
        tr("PNG image (*.png);;SVG drawing (*.svg);;CSV table (*.csv)"));
    if (path.isEmpty()) return;
    rememberExportDir(QFileInfo(path).absolutePath());
    emit exportMapRequested(path);
  });
  explain(m_exportMap, tr("Writes the map shown as PNG, SVG or CSV"));
  m_exportMap->setEnabled(false);
  m_exportPicture =
      file->addAction(tr("Export &picture…"), QKeySequence(tr("Ctrl+Shift+P")), this, [this] {
        PictureDialog dialog(m_window, context());
        if (dialog.exec() != QDialog::Accepted || dialog.path().isEmpty()) return;
        rememberExportDir(QFileInfo(dialog.path()).absolutePath());
        emit exportPictureRequested(dialog.path(), dialog.kind());
      });
  explain(m_exportPicture, tr("Saves the 3-D view, the map or both side by side as PNG"));
  m_exportPicture->setEnabled(false);
  m_exportAnimation =
      file->addAction(tr("Export &animation…"), QKeySequence(tr("Ctrl+Shift+A")), this, [this] {
        AnimationDialog dialog(m_window, context(), ffmpegProgram());
        if (dialog.exec() != QDialog::Accepted) return;
        rememberExportDir(QFileInfo(dialog.settings().folder).absoluteFilePath());
        emit exportAnimationRequested(dialog.settings());
      });
  explain(m_exportAnimation, tr("Writes the playback (3-D view and map) as a PNG image sequence "
                                "and, with ffmpeg, as MP4"));
  m_exportAnimation->setEnabled(false);
  file->addSeparator();
  explain(file->addAction(tr("&Quit"), QKeySequence::Quit, window, &QWidget::close),
          tr("Closes the window (asks first about a synthesized motion not exported)"));
  updateRecentMenu();
}

void FileMenu::setMotionShown(bool shown) {
  m_exportPicture->setEnabled(shown);
  m_exportAnimation->setEnabled(shown);
}

ExportContext FileMenu::context() const {
  ExportContext c = m_context ? m_context() : ExportContext{};
  // Pictures go where the last ones went; before any, beside the clips.
  c.folder = !m_exportDir.isEmpty() ? m_exportDir
             : !m_lastDir.isEmpty() ? m_lastDir
                                    : QDir::currentPath();
  return c;
}

void FileMenu::rememberExportDir(const QString& dir) {
  m_exportDir = dir;
  QSettings().setValue("lastExportDir", dir);
}

QStringList FileMenu::recentFiles() const {
  return QSettings().value("recentFiles").toStringList();
}

void FileMenu::remember(const QString& path) {
  const QFileInfo info(path);
  m_lastDir = info.absolutePath();
  QStringList recent = recentFiles();
  recent.removeAll(info.absoluteFilePath());
  recent.prepend(info.absoluteFilePath());
  while (recent.size() > kMaxRecent) recent.removeLast();
  QSettings settings;
  settings.setValue("recentFiles", recent);
  settings.setValue("lastDir", m_lastDir);
  updateRecentMenu();
}

void FileMenu::updateRecentMenu() {
  m_recentMenu->clear();
  const QStringList recent = recentFiles();
  for (const QString& path : recent) {
    m_recentMenu
        ->addAction(QFileInfo(path).fileName(), this, [this, path] { emit openRequested(path); })
        ->setToolTip(path);
  }
  m_recentMenu->setEnabled(!recent.isEmpty());
}

void FileMenu::openDropped(const QList<QUrl>& urls, bool addAll,
                           const std::function<bool(const QString&)>& open,
                           const std::function<bool(const QString&)>& add) {
  bool adding = addAll;
  for (const QUrl& url : urls) {
    if (!url.isLocalFile()) continue;
    if (!(adding ? add(url.toLocalFile()) : open(url.toLocalFile()))) break;
    adding = true;
  }
}

}  // namespace motionmap::studio
