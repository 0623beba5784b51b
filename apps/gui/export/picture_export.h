#pragma once
// File → Export picture: the 3-D view, the map view or both side by side as an image, rendered
// from the views themselves (the GL framebuffer, or the QPainter fallback, for the 3-D view; a
// widget grab for the map with its pointer), and written as PNG with errors that say why.
//
//   savePicture(renderPicture(skeletonView, mapView, PictureKind::Both), "64_08-frame0190.png");
#include <QImage>
#include <QString>

#include "export/export_names.h"

namespace motionmap::studio {

class MapView;
class SkeletonView;

/// The picture of `kind` at the views' current sizes (device pixels): View3D is
/// SkeletonView::renderImage(), Map the map view's grab, Both the two side by side (3-D view
/// left, map right, tops aligned; width = the sum of theirs, height = the larger, the rest white).
QImage renderPicture(SkeletonView* view3d, MapView* map, PictureKind kind);

/// Writes `image` to `path` (format from the suffix; PNG when it has none that Qt writes).
/// @throws Error naming the path and why: a folder that does not exist, or the writer's reason
///         (e.g. permission denied).
void savePicture(const QImage& image, const QString& path);

}  // namespace motionmap::studio
