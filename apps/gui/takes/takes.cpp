#include "takes/takes.h"

#include <algorithm>
#include <cmath>

namespace motionmap::studio {

namespace {

double distanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                         const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length2 = ab.squaredNorm();
  if (length2 == 0.0) return (p - a).norm();
  const double t = std::clamp((p - a).dot(ab) / length2, 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

/// Douglas–Peucker on points[first..last]: marks the points kept in `keep`.
void simplify(const std::vector<Eigen::Vector2d>& points, int first, int last, double tolerance,
              std::vector<char>& keep) {
  if (last - first < 2) return;
  int farthest = -1;
  double worst = tolerance;
  for (int i = first + 1; i < last; ++i) {
    const double d = distanceToSegment(points[std::size_t(i)], points[std::size_t(first)],
                                       points[std::size_t(last)]);
    if (d > worst) {
      worst = d;
      farthest = i;
    }
  }
  if (farthest < 0) return;
  keep[std::size_t(farthest)] = 1;
  simplify(points, first, farthest, tolerance, keep);
  simplify(points, farthest, last, tolerance, keep);
}

}  // namespace

std::vector<int> controlPoints(const synth::MapPath& path, int maxPoints) {
  const auto& points = path.points;
  const int n = int(points.size());
  if (n < 2) return {};
  Eigen::Vector2d lo = points.front(), hi = points.front();
  for (const auto& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  double tolerance = 0.015 * (hi - lo).norm();
  maxPoints = std::max(maxPoints, 2);
  for (;;) {
    std::vector<char> keep(std::size_t(n), 0);
    keep.front() = keep.back() = 1;
    simplify(points, 0, n - 1, tolerance, keep);
    std::vector<int> kept;
    for (int i = 0; i < n; ++i)
      if (keep[std::size_t(i)]) kept.push_back(i);
    // A zero-sized path (all points equal) keeps its two ends at the first pass.
    if (int(kept.size()) <= maxPoints || tolerance <= 0.0) return kept;
    tolerance *= 1.5;
  }
}

synth::MapPath deformPath(const synth::MapPath& path, const std::vector<int>& controls, int control,
                          const Eigen::Vector2d& to) {
  synth::MapPath moved = path;
  if (control < 0 || control >= int(controls.size())) return moved;
  const int at = controls[std::size_t(control)];
  const Eigen::Vector2d delta = to - path.points[std::size_t(at)];
  // The neighbouring control points stay; at the path's ends the end point is the limit.
  const int before = control > 0 ? controls[std::size_t(control - 1)] : at;
  const int after = control + 1 < int(controls.size()) ? controls[std::size_t(control + 1)] : at;
  for (int i = before + 1; i < at; ++i)
    moved.points[std::size_t(i)] += delta * (double(i - before) / double(at - before));
  moved.points[std::size_t(at)] = to;
  for (int i = at + 1; i < after; ++i)
    moved.points[std::size_t(i)] += delta * (double(after - i) / double(after - at));
  return moved;
}

TakeList::TakeList(QObject* parent) : QAbstractListModel(parent) {}

int TakeList::rowCount(const QModelIndex& parent) const {
  return parent.isValid() ? 0 : count();
}

QVariant TakeList::data(const QModelIndex& index, int role) const {
  if (!index.isValid() || index.row() >= count()) return {};
  const Take& take = at(index.row());
  switch (role) {
    case Qt::DisplayRole: {
      const int frames = take.result ? take.result->motion.num_frames : 0;
      return tr("%1 — %2 frames%3")
          .arg(take.name)
          .arg(frames)
          .arg(take.exported ? QString() : tr(" (not exported)"));
    }
    case Qt::EditRole:
      return take.name;
    case Qt::ToolTipRole:
      return tr("%1: %2 path points, %3 control points; sketched on the map %4.\n"
                "Double-click to rename, select to play, Delete to remove.")
          .arg(take.name)
          .arg(take.path.points.size())
          .arg(take.controls.size())
          .arg(QString::fromStdString(take.mapKey));
    default:
      return {};
  }
}

Qt::ItemFlags TakeList::flags(const QModelIndex& index) const {
  if (!index.isValid()) return Qt::NoItemFlags;
  return Qt::ItemIsSelectable | Qt::ItemIsEnabled | Qt::ItemIsEditable;
}

bool TakeList::setData(const QModelIndex& index, const QVariant& value, int role) {
  if (!index.isValid() || role != Qt::EditRole) return false;
  const QString name = value.toString().trimmed();
  if (name.isEmpty() || name == at(index.row()).name) return false;
  emit renameRequested(index.row(), name);
  return true;
}

int TakeList::rowOf(int id) const {
  for (int row = 0; row < count(); ++row)
    if (at(row).id == id) return row;
  return -1;
}

void TakeList::insert(int row, Take take) {
  row = std::clamp(row, 0, count());
  beginInsertRows({}, row, row);
  m_takes.insert(m_takes.begin() + row, std::move(take));
  endInsertRows();
  if (m_current >= row) ++m_current;
  emit changed();
}

Take TakeList::remove(int row) {
  m_removing = true;
  beginRemoveRows({}, row, row);
  Take take = std::move(m_takes[std::size_t(row)]);
  m_takes.erase(m_takes.begin() + row);
  endRemoveRows();
  m_removing = false;
  if (m_current == row) {
    m_current = -1;  // the clip plays again
    emit currentMotionChanged();
  } else if (m_current > row) {
    --m_current;
  }
  emit changed();
  return take;
}

void TakeList::rename(int row, const QString& name) {
  m_takes[std::size_t(row)].name = name;
  emit dataChanged(index(row), index(row));
  emit changed();
}

void TakeList::setMotion(int row, synth::MapPath path,
                         std::shared_ptr<const synth::SynthResult> result, bool exported) {
  Take& take = m_takes[std::size_t(row)];
  take.path = std::move(path);
  take.result = std::move(result);
  take.exported = exported;
  emit dataChanged(index(row), index(row));
  if (row == m_current) emit currentMotionChanged();
  emit changed();
}

void TakeList::setKeys(int row, TakeKeys keys, std::vector<int> controls) {
  Take& take = m_takes[std::size_t(row)];
  take.keys = std::move(keys);
  take.controls = std::move(controls);
}

void TakeList::setExported(int row, bool exported) {
  m_takes[std::size_t(row)].exported = exported;
  emit dataChanged(index(row), index(row));
  emit changed();
}

void TakeList::clear() {
  m_removing = true;
  beginResetModel();
  m_takes.clear();
  endResetModel();
  m_removing = false;
  const bool hadCurrent = m_current >= 0;
  m_current = -1;
  if (hadCurrent) emit currentMotionChanged();
  emit changed();
}

void TakeList::setCurrent(int row) {
  if (row < -1 || row >= count() || row == m_current) return;
  m_current = row;
  emit currentMotionChanged();
  emit changed();
}

QStringList TakeList::unexportedNames() const {
  QStringList names;
  for (const Take& take : m_takes)
    if (!take.exported) names << take.name;
  return names;
}

}  // namespace motionmap::studio
