#include "explore/saved_clips.h"

#include <QFileInfo>
#include <QMessageBox>
#include <QProgressDialog>
#include <QPushButton>

#include "motionmap/mapfile/saved_map.h"

namespace motionmap::studio {

std::optional<std::vector<Clip>> loadSavedClips(const mapfile::SavedMap& map, QWidget* parent) {
  const int n = int(map.file().clips.size());
  std::optional<QProgressDialog> progress;
  if (parent) {
    progress.emplace(QObject::tr("Loading the map's clips…"), QObject::tr("Cancel"), 0, n, parent);
    progress->setWindowModality(Qt::WindowModal);
    progress->setMinimumDuration(300);
  }
  std::vector<Clip> clips;
  clips.reserve(std::size_t(n));
  for (int c = 0; c < n; ++c) {
    if (progress) {
      progress->setValue(c);
      progress->setLabelText(
          QObject::tr("Loading clip %1 of %2 (%3)…")
              .arg(c + 1)
              .arg(n)
              .arg(QFileInfo(QString::fromStdString(map.file().clips[std::size_t(c)].path))
                       .fileName()));
      if (progress->wasCanceled()) return std::nullopt;
    }
    clips.push_back(*map.clip(c));  // checked against the map file (hash, frames, skeleton)
  }
  return clips;
}

QString recomputeQuestion(const mapfile::SavedMap& map, const QString& method) {
  const mapfile::MapFile& file = map.file();
  return QObject::tr(
             "%1 is shown as it was made (%2). A %3 map, or other parameters, need its %4 "
             "clips mapped again here: load them and compute it?")
      .arg(QFileInfo(QString::fromStdString(file.path)).fileName(),
           QString::fromStdString(file.parameters), method)
      .arg(file.clips.size());
}

bool askRecompute(QWidget* parent, const mapfile::SavedMap& map, const QString& method) {
  QMessageBox box(QMessageBox::Question, QObject::tr("Recompute from clips"),
                  recomputeQuestion(map, method), QMessageBox::Cancel, parent);
  QPushButton* recompute =
      box.addButton(QObject::tr("Recompute from clips…"), QMessageBox::AcceptRole);
  box.setDefaultButton(recompute);
  box.exec();
  return box.clickedButton() == recompute;
}

}  // namespace motionmap::studio
