#pragma once
// The window's exports, without the window: a take's motion as BVH, the map (CSV or a plot), a
// picture of the views, an animation of the motion playing (with a progress dialog), and a
// screenshot of the whole window. Errors come back as failed(message) (the window shows them),
// what was written as wrote(summary) for the status line.
#include <functional>
#include <optional>

#include <QImage>
#include <QObject>
#include <QString>

#include "export/animation_export.h"
#include "export/export_names.h"
#include "export/picture_export.h"
#include "motionmap/embed/embed.h"
#include "motionmap/skeleton/skeleton.h"

namespace motionmap::studio {

class MapController;
class MapView;
class Playback;
class SkeletonView;
class TakesController;

class ExportController : public QObject {
  Q_OBJECT
 public:
  /// Exports what `window` shows (its views `skeletonView` and `mapView`, the clock `playback`,
  /// the takes of `takes`, the maps of `maps`); `playing` gives the motion playing (nullptr:
  /// none). All must outlive this.
  ExportController(QWidget* window, SkeletonView* skeletonView, MapView* mapView,
                   Playback* playback, TakesController* takes, const MapController* maps,
                   std::function<const Motion*()> playing);

  /// Writes the motion of the take at `row` as BVH; it then counts as exported.
  bool exportTake(int row, const QString& path);
  /// Writes every take not exported yet into `folder` as "<take name>.bvh" (a name already
  /// there gets " 2", " 3", …). Stops at the first failure (reported by failed()).
  /// @return whether every such take was written.
  bool exportUnexported(const QString& folder);
  /// Writes the map shown (map_export.h: CSV, PNG, SVG, PDF).
  bool exportMap(const QString& path);
  /// The window as one image (the GL view through its own rendering: a grab may leave it blank).
  QImage screenshot();
  QImage renderPicture(PictureKind kind);
  /// Shows `frame` of the motion playing (pausing playback) and renders it.
  QImage renderFrameImage(int frame, PictureKind kind);
  bool exportPicture(const QString& path, PictureKind kind);
  /// Writes the motion playing as an animation (MainWindow::exportAnimation).
  bool exportAnimation(const AnimationSettings& settings);
  /// The names, frames and rate the export dialogs start from: the clip `shown`, the map's
  /// `method`, whether a synthesized motion plays, the current take, the playback's in/out range.
  ExportContext context(const Clip* shown, std::optional<embed::Method> method,
                        bool synthesized) const;

 signals:
  void failed(const QString& message);
  /// A file was written: what to say in the status line.
  void wrote(const QString& summary);
  /// A take was written into `folder` (the next export dialog starts there).
  void exportedTo(const QString& folder);

 private:
  /// Runs `work`; false, with the error it threw reported, when it throws.
  bool attempt(const std::function<void()>& work);

  QWidget* m_window;
  SkeletonView* m_skeletonView;
  MapView* m_mapView;
  Playback* m_playback;
  TakesController* m_takes;
  const MapController* m_maps;
  std::function<const Motion*()> m_playing;
};

}  // namespace motionmap::studio
