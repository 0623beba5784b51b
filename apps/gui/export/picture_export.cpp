#include "export/picture_export.h"

#include <QDir>
#include <QFileInfo>
#include <QImageWriter>
#include <QPainter>

#include "map/map_view.h"
#include "motionmap/core/error.h"
#include "scene/skeleton_view.h"

namespace motionmap::studio {

QImage renderPicture(SkeletonView* view3d, MapView* map, PictureKind kind) {
  if (kind == PictureKind::View3D) return view3d->renderImage();
  // A grab paints the map widget now, pointer included, whether or not it is on screen.
  const QImage mapImage = map->grab().toImage();
  if (kind == PictureKind::Map) return mapImage;
  const QImage left = view3d->renderImage();
  QImage both(left.width() + mapImage.width(), std::max(left.height(), mapImage.height()),
              QImage::Format_RGB32);
  both.fill(Qt::white);
  QPainter painter(&both);
  // Device pixels side by side: with their ratios set to 1 neither image is scaled when drawn.
  for (auto [image, x] : {std::pair(left, 0), std::pair(mapImage, left.width())}) {
    image.setDevicePixelRatio(1.0);
    painter.drawImage(QPoint(x, 0), image);
  }
  return both;
}

void savePicture(const QImage& image, const QString& path) {
  const QFileInfo info(path);
  if (image.isNull()) throw Error("nothing to write to " + path.toStdString() + " (empty picture)");
  if (!info.absoluteDir().exists())
    throw Error("cannot write " + path.toStdString() + ": the folder " +
                info.absolutePath().toStdString() + " does not exist");
  QByteArray format = info.suffix().toLower().toLatin1();
  if (!QImageWriter::supportedImageFormats().contains(format)) format = "png";
  QImageWriter writer(path, format);
  if (!writer.write(image)) {
    QString why = writer.errorString();
    // QImageWriter says "Device not writable" for a file it could not open; say which.
    if (writer.error() == QImageWriter::DeviceError && info.exists() && !info.isWritable())
      why = QStringLiteral("the file is read-only");
    else if (writer.error() == QImageWriter::DeviceError &&
             !QFileInfo(info.absolutePath()).isWritable())
      why = QStringLiteral("the folder is not writable");
    throw Error("cannot write " + path.toStdString() + ": " + why.toStdString());
  }
}

}  // namespace motionmap::studio
