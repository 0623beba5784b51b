#include "explore/selection.h"

#include <algorithm>
#include <cmath>

namespace motionmap::studio {

std::vector<SelectedFrame> framesInside(const QPolygonF& polygon, const MapSource::Samples& samples,
                                        const std::function<bool(int sample)>& shown) {
  std::vector<SelectedFrame> out;
  if (polygon.size() < 3 || !samples.points || !samples.clipOf || !samples.frameOf) return out;
  const Eigen::MatrixXd& xy = *samples.points;
  const QRectF box = polygon.boundingRect();
  const Eigen::Index n = std::min<Eigen::Index>(xy.rows(), Eigen::Index(samples.clipOf->size()));
  for (Eigen::Index i = 0; i < n; ++i) {
    const double x = xy(i, 0), y = xy(i, 1);
    if (!(x >= box.left() && x <= box.right() && y >= box.top() && y <= box.bottom())) continue;
    if (!polygon.containsPoint(QPointF(x, y), Qt::OddEvenFill)) continue;
    if (shown && !shown(int(i))) continue;
    out.push_back({(*samples.clipOf)[std::size_t(i)], (*samples.frameOf)[std::size_t(i)], x, y});
  }
  std::sort(out.begin(), out.end(), [](const SelectedFrame& a, const SelectedFrame& b) {
    return a.clip != b.clip ? a.clip < b.clip : a.frame < b.frame;
  });
  return out;
}

std::vector<FrameRange> frameRanges(const std::vector<SelectedFrame>& frames) {
  std::vector<FrameRange> out;
  for (const SelectedFrame& f : frames) {
    if (!out.empty() && out.back().clip == f.clip && f.frame <= out.back().last + 1) {
      out.back().last = std::max(out.back().last, f.frame);
    } else {
      out.push_back({f.clip, f.frame, f.frame});
    }
  }
  return out;
}

QString rangesText(const std::vector<FrameRange>& ranges, int clip) {
  QStringList parts;
  for (const FrameRange& r : ranges) {
    if (r.clip != clip) continue;
    parts << (r.first == r.last ? QString::number(r.first)
                                : QStringLiteral("%1–%2").arg(r.first).arg(r.last));
  }
  return parts.join(QStringLiteral(", "));
}

QString clipListText(const std::vector<FrameRange>& ranges, const QStringList& files,
                     const QString& from) {
  int frames = 0;
  std::vector<int> clips;
  for (const FrameRange& r : ranges) {
    frames += r.frames();
    if (clips.empty() || clips.back() != r.clip) clips.push_back(r.clip);
  }
  QString text = QStringLiteral(
                     "# MotionMap Studio selection: %1 frames of %2 clips of %3\n"
                     "# map these clips with: motionmap map @THIS_FILE\n")
                     .arg(frames)
                     .arg(clips.size())
                     .arg(from);
  for (const int clip : clips) {
    text += QStringLiteral("# clip %1, frames %2\n").arg(clip + 1).arg(rangesText(ranges, clip));
    text += files.value(clip) + QLatin1Char('\n');
  }
  return text;
}

QString selectionCsv(const std::vector<SelectedFrame>& frames, const QStringList& files) {
  auto quoted = [](QString field) {
    if (!field.contains(QLatin1Char(',')) && !field.contains(QLatin1Char('"')) &&
        !field.contains(QLatin1Char('\n')))
      return field;
    return QLatin1Char('"') + field.replace(QLatin1String("\""), QLatin1String("\"\"")) +
           QLatin1Char('"');
  };
  QString text = QStringLiteral("clip,frame,x,y\n");
  for (const SelectedFrame& f : frames) {
    text += quoted(files.value(f.clip)) + QLatin1Char(',') + QString::number(f.frame) +
            QLatin1Char(',') + QString::number(f.x, 'g', 17) + QLatin1Char(',') +
            QString::number(f.y, 'g', 17) + QLatin1Char('\n');
  }
  return text;
}

}  // namespace motionmap::studio
