#include "export/export_names.h"

#include <QFileInfo>
#include <QRegularExpression>

namespace motionmap::studio {

namespace {
QString clipOrDefault(const ExportNaming& naming) {
  return naming.clip.isEmpty() ? QStringLiteral("motion") : naming.clip;
}
/// "64_08" or "64_08-synth": the motion playing.
QString motionName(const ExportNaming& naming) {
  return clipOrDefault(naming) + (naming.synthesized ? QStringLiteral("-synth") : QString());
}
/// A take's name as part of a file name: "Take 1" → "Take_1" ("take" when nothing is left).
QString takeTag(const QString& take) {
  QString tag = take.trimmed();
  tag.replace(QRegularExpression("[^A-Za-z0-9_-]+"), "_");
  tag.remove(QRegularExpression("^_+|_+$"));
  return tag.isEmpty() ? QStringLiteral("take") : tag;
}
QString frameTag(int frame) {
  return QStringLiteral("frame%1").arg(frame, 4, 10, QLatin1Char('0'));
}
}  // namespace

QString clipBaseName(const std::string& path) {
  QString name = QFileInfo(QString::fromStdString(path)).completeBaseName();
  // Sample clips are named "sample:swing"; a suggested name must be a plain file name anywhere.
  for (QChar& c : name) {
    if (!c.isLetterOrNumber() && c != QLatin1Char('.') && c != QLatin1Char('_') &&
        c != QLatin1Char('-'))
      c = QLatin1Char('-');
  }
  return name;
}

QString mapFileName(const ExportNaming& naming, const QString& suffix) {
  const QString method = naming.method.isEmpty() ? QStringLiteral("map") : naming.method;
  return clipOrDefault(naming) + "-" + method + "." + suffix;
}

QString motionFileName(const ExportNaming& naming) {
  return clipOrDefault(naming) + "-" +
         (naming.take.isEmpty() ? QStringLiteral("synth") : takeTag(naming.take)) + ".bvh";
}

QString pictureFileName(const ExportNaming& naming, PictureKind kind) {
  const QString frame = frameTag(naming.frame);
  switch (kind) {
    case PictureKind::View3D:
      return motionName(naming) + "-3d-" + frame + ".png";
    case PictureKind::Map: {
      const QString method = naming.method.isEmpty() ? QStringLiteral("map") : naming.method;
      return clipOrDefault(naming) + "-" + method + (naming.synthesized ? "-synth-" : "-") + frame +
             ".png";
    }
    case PictureKind::Both:
      break;
  }
  return motionName(naming) + "-" + frame + ".png";
}

QString animationName(const ExportNaming& naming) {
  if (naming.synthesized) return motionName(naming);
  const QString method = naming.method.isEmpty() ? QStringLiteral("map") : naming.method;
  return clipOrDefault(naming) + "-" + method;
}

}  // namespace motionmap::studio
