#include "export/export_controller.h"

#include <QDir>
#include <QFileInfo>
#include <QPainter>
#include <QRegularExpression>

#include "export/map_export.h"
#include "map/map_controller.h"
#include "motionmap/core/error.h"
#include "motionmap/io/bvh.h"
#include "playback/playback.h"
#include "scene/skeleton_view.h"
#include "takes/takes_controller.h"

namespace motionmap::studio {

ExportController::ExportController(QWidget* window, SkeletonView* skeletonView, MapView* mapView,
                                   Playback* playback, TakesController* takes,
                                   const MapController* maps,
                                   std::function<const Motion*()> playing)
    : QObject(window),
      m_window(window),
      m_skeletonView(skeletonView),
      m_mapView(mapView),
      m_playback(playback),
      m_takes(takes),
      m_maps(maps),
      m_playing(std::move(playing)) {}

bool ExportController::attempt(const std::function<void()>& work) {
  try {
    work();
    return true;
  } catch (const std::exception& e) {
    emit failed(QString::fromStdString(e.what()));
    return false;
  }
}

bool ExportController::exportTake(int row, const QString& path) {
  if (row < 0 || row >= m_takes->list().count()) return false;
  const Take& take = m_takes->list().at(row);
  if (!take.result || !take.map) return false;
  return attempt([&] {
    io::write_bvh(io::from_motion(take.map->blender->skeleton(), take.result->motion),
                  path.toStdString());
    emit exportedTo(QFileInfo(path).absolutePath());
    m_takes->list().setExported(row, true);
    emit wrote(tr("Wrote %1").arg(path));
  });
}

bool ExportController::exportUnexported(const QString& folder) {
  const QDir dir(folder);
  for (int row = 0; row < m_takes->list().count(); ++row) {
    const Take& take = m_takes->list().at(row);
    if (take.exported) continue;
    // A file name from the take's name: no separators or characters file systems refuse.
    QString base = take.name;
    base.replace(QRegularExpression(R"([/\\:*?"<>|])"), "_");
    if (base.trimmed().isEmpty()) base = tr("Take");
    QString path = dir.filePath(base + ".bvh");
    for (int n = 2; QFileInfo::exists(path); ++n)
      path = dir.filePath(QString("%1 %2.bvh").arg(base).arg(n));
    if (!exportTake(row, path)) return false;
  }
  return true;
}

bool ExportController::exportMap(const QString& path) {
  const std::shared_ptr<const MapResult> map = m_maps->current();
  if (!map) return false;
  return attempt([&] {
    writeMap(path, *map, *m_maps->clips());
    emit wrote(tr("Wrote %1").arg(path));
  });
}

QImage ExportController::screenshot() {
  QImage image = m_window->grab().toImage();
  // Paint the 3-D view's own rendering over its place: a window grab may leave a GL child blank.
  const QImage view = m_skeletonView->renderImage();
  if (!view.isNull()) {
    QPainter painter(&image);
    painter.drawImage(QRect(m_skeletonView->mapTo(m_window, QPoint(0, 0)), m_skeletonView->size()),
                      view);
  }
  return image;
}

QImage ExportController::renderPicture(PictureKind kind) {
  return studio::renderPicture(m_skeletonView, m_mapView, kind);
}

QImage ExportController::renderFrameImage(int frame, PictureKind kind) {
  m_playback->pause();
  m_playback->setFrame(frame);  // shows the pose and moves the pointer now (frameChanged)
  return renderPicture(kind);
}

bool ExportController::exportPicture(const QString& path, PictureKind kind) {
  return attempt([&] {
    const QImage image = renderPicture(kind);
    savePicture(image, path);
    emit wrote(tr("Wrote %1 (%2 × %3)").arg(path).arg(image.width()).arg(image.height()));
  });
}

bool ExportController::exportAnimation(const AnimationSettings& settings) {
  const Motion* motion = m_playing();
  if (!motion) {
    emit failed(tr("Open a clip first: the animation is the motion playing"));
    return false;
  }
  const bool wasPlaying = m_playback->isPlaying();
  const int frameBefore = m_playback->frame();
  AnimationResult result;
  const bool ok = attempt([&] {
    result = writeAnimationWithProgress(
        m_window, settings, motion->num_frames, 1.0 / motion->frame_time, [&](int frame) {
          // The progress dialog lets events through: a synthesis finishing would swap the motion.
          if (m_playing() != motion)
            throw Error("the motion playing changed during the export (a synthesis finished)");
          return renderFrameImage(frame, PictureKind::Both);
        });
  });
  if (m_playing() == motion) {
    m_playback->setFrame(frameBefore);
    if (wasPlaying) m_playback->play();
  }
  if (ok) emit wrote(animationSummary(result, settings));
  return ok && !result.cancelled;
}

ExportContext ExportController::context(const Clip* shown, std::optional<embed::Method> method,
                                        bool synthesized) const {
  ExportContext c;
  if (shown) c.naming.clip = clipBaseName(shown->path);
  if (method) c.naming.method = QString::fromUtf8(embed::method_name(*method).data());
  c.naming.frame = m_playback->frame();
  c.naming.synthesized = synthesized;
  if (const Take* take = m_takes->list().currentTake()) c.naming.take = take->name;
  if (const Motion* motion = m_playing()) {
    // The playback's in/out range (I / O), else the whole motion playing.
    c.first = m_playback->inPoint().value_or(0);
    c.last = m_playback->outPoint().value_or(motion->num_frames - 1);
    c.fps = 1.0 / motion->frame_time;
  }
  return c;
}

}  // namespace motionmap::studio
