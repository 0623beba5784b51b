#pragma once
// The key poses of the clip playing on the map shown (computed here or saved): `count` frames
// picked by pipeline::select_key_poses from the clip's trajectory on the map (its rows in time
// order, pipeline::clip_rows), as pipeline::clip_key_rows picks them, on a worker thread, and
// each frame as a stick figure to draw (render::sheet_pose). No widgets: KeyPoseStrip shows them.
// refresh() is cheap when nothing changed (the source, its map, the clip and the count are
// compared), so the window may call it with every frame shown; it computes only while active.
#include <functional>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <QObject>
#include <QString>

#include "common/background_job.h"
#include "motionmap/core/rotation.h"
#include "motionmap/render/pose_sheet.h"
#include "motionmap/skeleton/skeleton.h"

namespace motionmap::studio {

class MapSource;
struct MapResult;

class KeyPoses : public QObject {
  Q_OBJECT
 public:
  static constexpr int kDefaultCount = 8;
  static constexpr int kMinCount = 2;
  static constexpr int kMaxCount = 40;

  /// `source` gives the map source shown (it may change: refresh() notices).
  explicit KeyPoses(std::function<const MapSource*()> source, QObject* parent = nullptr);
  ~KeyPoses() override;

  /// How many key poses (clamped to [kMinCount, kMaxCount]); recomputed when active.
  void setCount(int count);
  int count() const { return m_count; }
  /// Whether key poses are wanted (their strip is shown): computed only then, at once on
  /// becoming active when the clip or the map changed meanwhile.
  void setActive(bool active);
  bool isActive() const { return m_active; }
  /// Recomputes when the source, its map, the clip playing or the count changed since the last
  /// computation (clears the poses and starts the worker); else does nothing.
  void refresh();

  /// The worker is picking them.
  bool isComputing() const { return m_job.running(); }
  /// The clip the key poses are of (−1: none).
  int clip() const { return m_clip; }
  /// The key poses' frames of the clip, increasing (empty while computing or when there are
  /// none: message() says why).
  const std::vector<int>& frames() const { return m_frames; }
  /// Each frame's figure (same order), with its caption "frame F\nT s".
  const std::vector<render::SheetPose>& poses() const { return m_poses; }
  /// The up axis the figures stand on.
  Axis upAxis() const { return m_up; }
  /// Why there are no key poses (empty when there are, or while they are computed).
  const QString& message() const { return m_message; }
  /// The index of `frame` among frames() (−1: not a key pose).
  int indexOf(int frame) const;

 signals:
  /// The poses, the message or isComputing() changed.
  void changed();

 private:
  // What the poses were computed for: a change of any part recomputes them.
  struct Key {
    const MapSource* source = nullptr;
    const Eigen::MatrixXd* points = nullptr;
    Eigen::Index rows = 0;
    const std::vector<int>* clipOf = nullptr;
    int clip = -1;
    const Clip* data = nullptr;
    int frames = 0;
    int count = 0;
    bool operator==(const Key&) const = default;
  };
  Key currentKey() const;
  void start();
  void finished(const std::vector<int>& keys, const std::vector<int>& frameOfRow);

  std::function<const MapSource*()> m_source;
  int m_count = kDefaultCount;
  bool m_active = false;
  bool m_valid = false;  ///< m_key is what the poses (or message) describe
  Key m_key;
  /// The computed map the key is of, held so that its address is not another map's later.
  std::shared_ptr<const MapResult> m_map;
  int m_clip = -1;
  std::vector<int> m_frames;
  std::vector<render::SheetPose> m_poses;
  Axis m_up = Axis::Y;
  QString m_message;
  BackgroundJob m_job;
};

}  // namespace motionmap::studio
