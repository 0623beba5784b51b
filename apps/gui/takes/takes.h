#pragma once
// Takes: every sketch the user draws on the map becomes a take — its path, the motion synthesized
// along it, a name and the map it was sketched on — kept in a list model (no widgets) that the
// takes dock shows and the undo commands change. A take's path has control points (a simplified
// subset of its points, Douglas–Peucker) that can be dragged; deformPath says how the points
// between them follow.
//
//   TakeList takes;
//   takes.insert(takes.count(), Take{.name = takes.nextName(), .path = sketch, ...});
//   takes.setCurrent(0);  // currentMotionChanged(): the window plays takes.at(0).result->motion
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <QAbstractListModel>
#include <QString>

#include "map/map_controller.h"
#include "motionmap/synth/inbetween.h"
#include "motionmap/synth/path.h"
#include "motionmap/synth/synthesize.h"

namespace motionmap::studio {

/// Most control points a take's path gets (Douglas–Peucker's tolerance grows until it fits).
constexpr int kMaxControlPoints = 24;

/// The control points of `path`: indices into path.points, first and last included, increasing,
/// chosen by Douglas–Peucker with a tolerance of 1.5 % of the path's bounding-box diagonal
/// (raised until at most `maxPoints` remain). Empty for a path of fewer than 2 points.
std::vector<int> controlPoints(const synth::MapPath& path, int maxPoints = kMaxControlPoints);

/// `path` with control point `control` (an index into `controls`) moved to `to`: that point moves
/// by the whole offset and the points between it and its neighbouring control points by a share
/// falling linearly (by index) to 0 at them, so the sketch's detail and times are kept and the
/// other control points stay where they were.
synth::MapPath deformPath(const synth::MapPath& path, const std::vector<int>& controls, int control,
                          const Eigen::Vector2d& to);

/// An in-between take's keys and timing (see synth::inbetween).
struct TakeKeys {
  std::vector<synth::Key> keys;
  /// Frames between consecutive keys; −1: the keys' times, or the samples' own speed.
  int framesBetween = -1;
};

/// One sketch (or set of key poses) and its motion.
struct Take {
  int id = -1;  ///< unique in its list (rows change, ids do not)
  QString name;
  synth::MapPath path;  ///< the path the motion follows (as sketched, or edited)
  /// controlPoints(path), fixed when sketched; an in-between take's: its keys' frames.
  std::vector<int> controls;
  /// An in-between take's keys (keys.keys empty: a sketch). Its path is then the route its frames
  /// follow, a point per frame.
  TakeKeys keys;
  std::shared_ptr<const synth::SynthResult> result;
  std::shared_ptr<const MapResult> map;  ///< the map it was sketched on (its blender's skeleton)
  std::string mapKey;                    ///< MapController::cacheKey of that map, for display
  bool exported = false;                 ///< written as BVH since its motion last changed
};

/// The takes, as a list model of their names (editable: an edit asks for a rename, so that it can
/// be undone) with the current take, the one playing.
class TakeList : public QAbstractListModel {
  Q_OBJECT
 public:
  explicit TakeList(QObject* parent = nullptr);

  int rowCount(const QModelIndex& parent = {}) const override;
  QVariant data(const QModelIndex& index, int role) const override;
  Qt::ItemFlags flags(const QModelIndex& index) const override;
  /// An edited name: emits renameRequested (the change itself goes through the undo stack).
  bool setData(const QModelIndex& index, const QVariant& value, int role) override;

  int count() const { return int(m_takes.size()); }
  const Take& at(int row) const { return m_takes[std::size_t(row)]; }
  /// The row of the take `id`, or −1.
  int rowOf(int id) const;
  /// A new id and the next default name ("Take 1", "Take 2", … never reused in this list).
  int newId() { return m_nextId++; }
  QString nextName() const { return tr("Take %1").arg(m_nextId + 1); }

  void insert(int row, Take take);
  Take remove(int row);
  void rename(int row, const QString& name);
  /// A new path and motion for `row` (an edit, or its undo); it counts as not exported.
  void setMotion(int row, synth::MapPath path, std::shared_ptr<const synth::SynthResult> result,
                 bool exported);
  /// New keys and control points for `row` (an in-between take's edit, or its undo), set before
  /// its setMotion.
  void setKeys(int row, TakeKeys keys, std::vector<int> controls);
  void setExported(int row, bool exported);
  void clear();
  /// A take is being removed (views moving their current row then are not choosing one).
  bool removing() const { return m_removing; }

  /// The take playing (−1: none, the clip plays).
  int current() const { return m_current; }
  void setCurrent(int row);
  const Take* currentTake() const { return m_current >= 0 ? &at(m_current) : nullptr; }

  /// Takes whose motion was not written since it last changed.
  QStringList unexportedNames() const;

 signals:
  void renameRequested(int row, const QString& name);
  /// The current take changed, or its motion did: the window plays it again.
  void currentMotionChanged();
  /// Any change (a take added, removed, renamed, edited, another current one).
  void changed();

 private:
  std::vector<Take> m_takes;
  int m_current = -1;
  int m_nextId = 0;
  bool m_removing = false;
};

}  // namespace motionmap::studio
