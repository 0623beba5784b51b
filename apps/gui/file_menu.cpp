#include "file_menu.h"

#include <QAction>
#include <QFileDialog>
#include <QFileInfo>
#include <QMainWindow>
#include <QMenu>
#include <QMenuBar>
#include <QSettings>

#include "help_dialogs.h"

namespace motionmap::studio {

FileMenu::FileMenu(QMainWindow* window) : QObject(window), m_window(window) {
  m_lastDir = QSettings().value("lastDir").toString();
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
  m_exportMotion = file->addAction(tr("&Export motion…"), QKeySequence(tr("Ctrl+E")), this, [this] {
    const QString path =
        QFileDialog::getSaveFileName(m_window, tr("Export motion"), m_lastDir, tr("BVH (*.bvh)"));
    if (!path.isEmpty()) emit exportMotionRequested(path);
  });
  explain(m_exportMotion, tr("Writes the synthesized motion as BVH"));
  m_exportMotion->setEnabled(false);
  m_exportMap = file->addAction(tr("Export &map…"), QKeySequence(tr("Ctrl+Shift+E")), this, [this] {
    const QString path = QFileDialog::getSaveFileName(
        m_window, tr("Export map"), m_lastDir,
        tr("PNG image (*.png);;SVG drawing (*.svg);;CSV table (*.csv)"));
    if (!path.isEmpty()) emit exportMapRequested(path);
  });
  explain(m_exportMap, tr("Writes the map shown as PNG, SVG or CSV"));
  m_exportMap->setEnabled(false);
  file->addSeparator();
  explain(file->addAction(tr("&Quit"), QKeySequence::Quit, window, &QWidget::close),
          tr("Closes the window (asks first about a synthesized motion not exported)"));
  updateRecentMenu();
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

}  // namespace motionmap::studio
