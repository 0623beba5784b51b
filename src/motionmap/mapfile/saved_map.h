#pragma once
// A saved map opened for use: its file, a 2-D index over its points, and its clips loaded on
// demand — each checked against the SHA-256 the map file recorded, a few kept in a cache — so
// that a map of 10⁶ frames opens in the time it takes to read its coordinates, and a hover, a
// click or a blended pose costs a lookup plus, at most, loading the clips it touches. What
// MotionMap Studio opens with File → Open map, and what `motionmap pose/synth --map
// lib.mmap.h5` blend from. No Qt.
//
//   using namespace motionmap::mapfile;
//   SavedMap map(read_map_file("lib.mmap.h5", {.model = false}));
//   const auto hit = map.index().nearest({0.3, -1.2});  // the sample under a point
//   std::shared_ptr<const motionmap::Clip> clip = map.clip(map.file().clip_of[hit.sample]);
//   const auto pose = map.pose_at({0.3, -1.2});         // blended from the K nearest
//
// Clip paths are resolved as `motionmap map` was given them: relative paths against the current
// folder, and when no file is there, against the map file's folder (a library moved together
// with its map). A clip whose file is missing, unreadable, changed since the map was made (another
// SHA-256) or no longer the clip the map recorded (frame count, frame time, skeleton) is an Error
// naming the map file, the clip file and what was expected — never a pose of other data.
#include <cstddef>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "motionmap/mapfile/map_file.h"
#include "motionmap/mapfile/point_index.h"
#include "motionmap/skeleton/skeleton.h"
#include "motionmap/synth/blender.h"

namespace motionmap::mapfile {

/// A pose blended from the samples nearest a map point (SavedMap::pose_at).
struct SavedPose {
  Motion pose;  ///< one frame of the clips' skeleton, as MapBlender::pose
  /// The motion root of the blend: the joint that faces heading 0 at the floor origin in `pose`
  /// (the map's, as synth::MapBlender::motion_root() of make_blender(); see SavedMap::pose_at).
  int root = 0;
  /// The motion root's ancestors, folded into it (synth::root_ancestors; at rest in `pose`).
  std::vector<int> ancestors;
  std::vector<Neighbor> around;  ///< the samples blended (nearest first) with their distances
  std::vector<double> weights;   ///< one per entry of `around`, summing to 1
  /// The nearest sample is farther than SavedMap::reach_distance(): the point is outside the
  /// data and the pose is (mostly) that of its nearest samples.
  bool outside = false;
};

/// A SavedMap is the synth::ClipSource of a blender over the map (make_blender()).
class SavedMap : public synth::ClipSource {
 public:
  /// Default number of loaded clips kept (least recently used dropped first).
  static constexpr int kDefaultCachedClips = 8;

  /// Takes `file` (as read_map_file returns it) and indexes its coordinates (PointIndex).
  /// `cached_clips` ≥ 1 clips stay loaded. @throws ParameterError for a map with no samples, or a
  /// gplvm map whose GP does not belong to its coordinates and features (embed::GplvmMap).
  explicit SavedMap(MapFile file, int cached_clips = kDefaultCachedClips);
  ~SavedMap() override;

  const MapFile& file() const { return m_file; }
  const PointIndex& index() const { return m_index; }
  int num_clips() const { return static_cast<int>(m_file.clips.size()); }

  /// Where clip `c`'s file is looked for: its recorded path when that exists (or is absolute),
  /// else the same relative path under the map file's folder.
  std::string resolve_path(int c) const;
  /// Clip `c` of the map, loaded on demand (io::load_clip; an .amc at the recorded frame time)
  /// and checked: the file's SHA-256, its frame count and frame time, and — for maps of one
  /// skeleton — its joint hierarchy. Kept in the cache. Thread-safe.
  /// @throws Error naming the map file, the clip file and what was expected; ParameterError for
  ///   c out of range.
  std::shared_ptr<const Clip> clip(int c) const override;
  /// Whether clip `c` is in the cache now (clip(c) then costs no file access).
  bool is_loaded(int c) const;
  /// Clip loads from files so far (cache misses, and clips_summary()'s reads), for tests and
  /// benchmarks.
  int loads() const;

  /// Every clip of the map, loaded and checked (not cached), in the map's order: what a
  /// synth::MapBlender given every clip blends (the kriging mode). @throws as clip().
  std::vector<Clip> load_all_clips(const Control& control = {}) const;
  /// The samples of the map as a FeatureSet for synth::MapBlender: clip_of, frame_of and
  /// segment_starts from the file (no X, no D).
  features::FeatureSet samples() const;
  /// What a blender reading the clips on demand needs of all of them (synth::summarize_clips):
  /// the frame counts and times the file records, and the motion root and moving joints it
  /// recorded when the map was made (MapFile::blend); a map without that record (made before
  /// MotionMap recorded it, or a map of placed clips) has every clip read once for it, on the
  /// pool's threads and not cached. @throws as clip() (the first clip's error); ParameterError
  /// for clips of different hierarchies; Cancelled.
  synth::ClipsSummary clips_summary(const Control& control = {}) const;

  /// The median map distance between consecutive samples of a clip (non-zero ones; 0 if none),
  /// as synth::MapBlender::median_step() computes it for the same map.
  double median_step() const { return m_median_step; }
  /// synth::reach_radius(reach, median_step(), the map's size): beyond it from every sample a
  /// point is outside the data, as for a synth::MapBlender of the same map.
  double reach_distance(double reach = 3.0) const;

  /// A gplvm map's GP over its coordinates (embed::gplvm_map of its model; read_map_file reads
  /// a gplvm map's model even without ReadOptions::model): its blends' weights and its rule of
  /// where it is valid, which make_blender() gives the blender. Null for other maps.
  const std::shared_ptr<const embed::GplvmMap>& gplvm() const { return m_gplvm; }

  /// The pose at map point `p` blended from its `neighbors` nearest samples with Franke–Little
  /// inverse-distance weights (R = the distance of the (neighbors + 1)-th nearest; a sample at p
  /// takes all the weight) — synth::BlendMode::Idw's weights, found by the index — and blended
  /// by synth::blend_states from the samples' states read from their clips (loaded on demand),
  /// as the blender of the whole map blends them: with the map's motion root and moving joints
  /// (MapFile::blend) and its first sample's translations for the other joints, so that the pose
  /// equals, bit for bit, make_blender(map, idw with K = neighbors).pose() of the same weights
  /// (samples in the order of `around`). Only those clips are read, and the first time also the
  /// first sample's, so a pose costs O(log N) plus their loading when not cached. A map without
  /// the blend record (clips of several hierarchies, placed clips, an older file) blends with
  /// the motion root and moving joints of these samples' clips (synth::summarize_clips of them)
  /// and the nearest sample's translations instead, reading no other clip. The blender's idw
  /// merges samples that share a map point (within 1e-9 of the map's extent) and takes the K
  /// nearest points; this takes the K nearest samples: the same where no two samples of the
  /// neighbourhood share a point. A point outside the data is not moved to its edge (`outside`
  /// says so); the pose is then mostly its nearest samples'.
  /// @throws ParameterError for a non-finite p or neighbors < 1, clips of different hierarchies
  ///   or a blend record that does not fit them; NumericalError for a non-finite value in a
  ///   sample blended; as clip().
  SavedPose pose_at(const Eigen::Vector2d& p, int neighbors = 12, Axis up = Axis::Y) const;

  /// The clips pose_at(p, neighbors) reads (of its `neighbors` nearest samples, and before the
  /// first pose of a map with a blend record the first sample's), each once, in order of first
  /// use: what a caller that must not wait for files loads first (is_loaded()).
  std::vector<int> clips_near(const Eigen::Vector2d& p, int neighbors = 12) const;

 private:
  std::shared_ptr<const Clip> load(int c) const;
  /// Clip c's frame time as load() gives it, from its record (without reading the clip).
  double loaded_frame_time(int c) const;
  /// What every blend of a map with a blend record keeps (as make_blender's blender): the
  /// skeleton of the first sample's clip, that sample's translations and
  /// the frame time of clip 0.
  struct BlendBase {
    Skeleton skeleton;
    std::vector<Eigen::Vector3d> fixed_translations;
    double frame_time = 0.0;
  };
  /// The map's BlendBase, read from the first sample's clip the first time. @throws as clip().
  std::shared_ptr<const BlendBase> blend_base() const;

  MapFile m_file;
  PointIndex m_index;
  double m_median_step = 0.0;
  std::shared_ptr<const embed::GplvmMap> m_gplvm;
  int m_capacity;
  mutable std::mutex m_mutex;
  mutable std::vector<std::pair<int, std::shared_ptr<const Clip>>> m_cache;  ///< most recent last
  mutable int m_loads = 0;
  mutable std::shared_ptr<const BlendBase> m_base;  ///< under m_mutex; null until blend_base()
};

/// A blender over `map`'s samples that reads the clips on demand (synth::MapBlender's ClipSource
/// constructor with clips_summary()): a pose reads only the clips of the samples it blends (and
/// the first clip, for the skeleton), and blends exactly as a blender given every clip. The
/// blender keeps the states of the samples it read, not their clips, and a synthesis reads each
/// block of frames' samples together, each clip once, so the default cache is enough. @throws as
/// clips_summary() and synth::MapBlender (the kriging mode is refused: it blends every sample; use
/// load_all_clips()). A gplvm map's blender gets its GP (SavedMap::gplvm()) unless `options` has
/// one: the map's validity is then the GP's, and the gp mode blends with it.
synth::MapBlender make_blender(std::shared_ptr<const SavedMap> map,
                               const synth::BlendOptions& options, const Control& control = {});

}  // namespace motionmap::mapfile
