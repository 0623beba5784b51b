#include "motionmap/mapfile/saved_map.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <system_error>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/core/sha256.h"
#include "motionmap/core/stats.h"
#include "motionmap/io/load.h"
#include "motionmap/synth/blend_state.h"

namespace motionmap::mapfile {

namespace {

namespace fs = std::filesystem;

// Samples closer than this fraction of the map's extent share a map point (as in the blender).
constexpr double kMergeFraction = 1e-9;

// "lib.mmap.h5: clip 3 (walk.bvh)" for messages.
std::string clip_label(const MapFile& file, int c) {
  return (file.path.empty() ? std::string("map") : file.path) + ": clip " + std::to_string(c) +
         " (" + file.clips[std::size_t(c)].path + ")";
}

// The first difference between a clip's joints and the map's recorded skeleton, or "".
std::string skeleton_difference(const Skeleton& s, const SkeletonRecord& r) {
  if (s.joints.size() != r.names.size()) {
    return "it has " + std::to_string(s.joints.size()) + " joints, the map's skeleton " +
           std::to_string(r.names.size());
  }
  for (std::size_t j = 0; j < r.names.size(); ++j) {
    const Joint& joint = s.joints[j];
    if (joint.name != r.names[j] || joint.parent != r.parents[j] ||
        static_cast<int>(joint.end_sites.size()) != r.end_sites[j]) {
      return "joint " + std::to_string(j) + " is '" + joint.name + "' where the map has '" +
             r.names[j] + "'" +
             (joint.name == r.names[j] ? " with another parent or End Site count" : "");
    }
  }
  return {};
}

// Whether load() reads the clip at `path` as an .amc at its recorded frame time.
bool is_amc(const std::string& path, const ClipRecord& record) {
  const std::string ext = fs::path(path).extension().string();
  return (ext == ".amc" || ext == ".AMC") && record.frame_time > 0.0;
}

}  // namespace

SavedMap::SavedMap(MapFile file, int cached_clips)
    : m_file(std::move(file)), m_index(m_file.coordinates), m_capacity(std::max(1, cached_clips)) {
  const int n = m_file.num_samples();
  if (n < 1 || m_file.clips.empty())
    throw ParameterError((m_file.path.empty() ? "map" : m_file.path) + ": the map has no samples");
  // The blender's median step: consecutive samples of a clip, steps above the merge tolerance.
  const double tol = kMergeFraction * (m_index.upper() - m_index.lower()).norm();
  std::vector<double> steps;
  steps.reserve(std::size_t(n));
  for (int i = 0; i + 1 < n; ++i) {
    if (m_file.clip_of[std::size_t(i)] != m_file.clip_of[std::size_t(i) + 1] ||
        m_file.frame_of[std::size_t(i) + 1] <= m_file.frame_of[std::size_t(i)])
      continue;
    const double step =
        (m_file.coordinates.row(i + 1).head<2>() - m_file.coordinates.row(i).head<2>()).norm();
    if (std::isfinite(step) && step > tol && step != 0.0) steps.push_back(step);
  }
  m_median_step = steps.empty() ? 0.0 : upper_median(std::move(steps));
  try {
    m_gplvm = embed::gplvm_map(m_file.model, m_file.coordinates);
  } catch (const ParameterError& e) {
    throw ParameterError((m_file.path.empty() ? "map" : m_file.path) + ": " + e.what());
  }
}

double SavedMap::reach_distance(double reach) const {
  return synth::reach_radius(reach, m_median_step, (m_index.upper() - m_index.lower()).maxCoeff());
}

SavedMap::~SavedMap() = default;

std::string SavedMap::resolve_path(int c) const {
  if (c < 0 || c >= num_clips()) {
    throw ParameterError((m_file.path.empty() ? std::string("map") : m_file.path) + ": clip " +
                         std::to_string(c) + " is out of range [0, " + std::to_string(num_clips()) +
                         ")");
  }
  const fs::path recorded(m_file.clips[std::size_t(c)].path);
  std::error_code ec;
  if (recorded.is_absolute() || fs::exists(recorded, ec) || m_file.path.empty())
    return recorded.string();
  const fs::path beside = fs::path(m_file.path).parent_path() / recorded;
  return fs::exists(beside, ec) ? beside.string() : recorded.string();
}

std::shared_ptr<const Clip> SavedMap::load(int c) const {
  const ClipRecord& record = m_file.clips[std::size_t(c)];
  const std::string path = resolve_path(c);
  const std::string what = clip_label(m_file, c);
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    throw Error(what + ": the clip file " + path +
                " is missing (expected the file the map was made from, SHA-256 " + record.sha256 +
                "; paths are taken as given to `motionmap map`, relative to the current folder or "
                "to the map file's)");
  }
  io::LoadOptions options;
  if (is_amc(path, record)) options.fps = 1.0 / record.frame_time;
  options.sha256 = true;  // of the bytes parsed: what is checked is what is used
  const auto changed = [&](const std::string& hash) {
    return Error(what + ": the clip file " + path +
                 " has changed since the map was made (SHA-256 " + hash + ", the map expects " +
                 record.sha256 +
                 "); its frames no longer match the map's points — map the clips again with "
                 "`motionmap map … --save`");
  };
  std::shared_ptr<Clip> clip;
  try {
    clip = std::make_shared<Clip>(io::load_clip(path, options));
  } catch (const Error&) {
    // A clip that no longer parses is, first of all, not the clip the map was made from.
    if (const std::string hash = sha256_file(path); hash != record.sha256) throw changed(hash);
    throw;
  }
  if (clip->sha256 != record.sha256) throw changed(clip->sha256);
  clip->path = record.path;
  if (clip->motion.num_frames != record.frames) {
    throw Error(what + ": the clip file " + path + " has " +
                std::to_string(clip->motion.num_frames) + " frames, the map expects " +
                std::to_string(record.frames));
  }
  if (std::abs(clip->motion.frame_time - record.frame_time) > 1e-9 * record.frame_time) {
    throw Error(what + ": the clip file " + path + " has a frame time of " +
                format_number(clip->motion.frame_time) + " s, the map expects " +
                format_number(record.frame_time) + " s");
  }
  if (m_file.options.features.joints == features::JointSelection::All) {
    if (const std::string why = skeleton_difference(clip->skeleton, m_file.skeleton);
        !why.empty()) {
      throw Error(what + ": the clip file " + path +
                  " does not have the skeleton the map recorded (" + why + ")");
    }
  }
  return clip;
}

std::shared_ptr<const Clip> SavedMap::clip(int c) const {
  if (c < 0 || c >= num_clips()) resolve_path(c);  // throws the range error
  {
    const std::lock_guard lock(m_mutex);
    const auto hit = std::find_if(m_cache.begin(), m_cache.end(),
                                  [c](const auto& entry) { return entry.first == c; });
    if (hit != m_cache.end()) {
      std::rotate(hit, hit + 1, m_cache.end());  // most recently used last
      return m_cache.back().second;
    }
  }
  std::shared_ptr<const Clip> loaded = load(c);  // outside the lock: other clips stay available
  const std::lock_guard lock(m_mutex);
  ++m_loads;
  const auto again = std::find_if(m_cache.begin(), m_cache.end(),
                                  [c](const auto& entry) { return entry.first == c; });
  if (again != m_cache.end()) return again->second;
  if (static_cast<int>(m_cache.size()) >= m_capacity) m_cache.erase(m_cache.begin());
  m_cache.emplace_back(c, loaded);
  return loaded;
}

bool SavedMap::is_loaded(int c) const {
  const std::lock_guard lock(m_mutex);
  return std::any_of(m_cache.begin(), m_cache.end(),
                     [c](const auto& entry) { return entry.first == c; });
}

int SavedMap::loads() const {
  const std::lock_guard lock(m_mutex);
  return m_loads;
}

std::vector<Clip> SavedMap::load_all_clips(const Control& control) const {
  std::vector<Clip> clips;
  clips.reserve(m_file.clips.size());
  for (int c = 0; c < num_clips(); ++c) {
    control.stage("loading clips", double(c) / num_clips(), double(c + 1) / num_clips()).check();
    clips.push_back(*load(c));
  }
  return clips;
}

features::FeatureSet SavedMap::samples() const {
  features::FeatureSet set;
  set.clip_of = m_file.clip_of;
  set.frame_of = m_file.frame_of;
  for (const ClipRecord& r : m_file.clips) set.segment_starts.push_back(r.first_sample);
  return set;
}

synth::ClipsSummary SavedMap::clips_summary(const Control& control) const {
  if (!m_file.blend) {
    // Not recorded: read every clip once, on the pool's threads (not cached).
    return synth::summarize_clips(
        num_clips(),
        [this](int c) {
          std::shared_ptr<const Clip> clip = load(c);
          const std::lock_guard lock(m_mutex);
          ++m_loads;
          return clip;
        },
        samples(), control);
  }
  synth::ClipsSummary out;
  for (int c = 0; c < num_clips(); ++c) {
    out.frames.push_back(m_file.clips[std::size_t(c)].frames);
    out.frame_times.push_back(loaded_frame_time(c));
  }
  out.motion_root = m_file.blend->motion_root;
  out.moving = m_file.blend->moving;
  control.check();
  return out;
}

synth::MapBlender make_blender(std::shared_ptr<const SavedMap> map,
                               const synth::BlendOptions& options, const Control& control) {
  if (!map) throw ParameterError("make_blender: no map given");
  if (options.mode == synth::BlendMode::Kriging) {
    throw ParameterError(
        "blend: kriging blends every sample of the map; load every clip (load_all_clips) and "
        "give them to synth::MapBlender");
  }
  const synth::ClipsSummary summary = map->clips_summary(control.part(0.0, 0.5));
  const features::FeatureSet samples = map->samples();
  const Eigen::MatrixXd& coords = map->file().coordinates;
  synth::BlendOptions with_gp = options;
  if (!with_gp.gplvm) with_gp.gplvm = map->gplvm();
  return synth::MapBlender(std::move(map), summary, samples, coords, with_gp,
                           control.part(0.5, 1.0));
}

std::vector<int> SavedMap::clips_near(const Eigen::Vector2d& p, int neighbors) const {
  std::vector<int> out;
  for (const Neighbor& n : m_index.nearest(p, std::max(1, neighbors))) {
    const int c = m_file.clip_of[std::size_t(n.sample)];
    if (std::find(out.begin(), out.end(), c) == out.end()) out.push_back(c);
  }
  bool based = true;
  if (m_file.blend) {
    const std::lock_guard lock(m_mutex);
    based = m_base != nullptr;
  }
  // pose_at reads the first sample's clip first, once (blend_base).
  if (!based && std::find(out.begin(), out.end(), m_file.clip_of[0]) == out.end())
    out.insert(out.begin(), m_file.clip_of[0]);
  return out;
}

double SavedMap::loaded_frame_time(int c) const {
  // An .amc's is computed from the recorded one, as load() computes it.
  const ClipRecord& r = m_file.clips[std::size_t(c)];
  return is_amc(resolve_path(c), r) ? 1.0 / (1.0 / r.frame_time) : r.frame_time;
}

std::shared_ptr<const SavedMap::BlendBase> SavedMap::blend_base() const {
  {
    const std::lock_guard lock(m_mutex);
    if (m_base) return m_base;
  }
  // As synth::MapBlender made from this map (make_blender) keeps them.
  const std::shared_ptr<const Clip> first = clip(m_file.clip_of[0]);
  const int J = first->motion.num_joints;
  const BlendRecord& record = *m_file.blend;
  const std::string map_name = m_file.path.empty() ? std::string("map") : m_file.path;
  synth::check_blend_joints(record.motion_root, record.moving, J, map_name + ": the blend record",
                            first->path);
  auto base = std::make_shared<BlendBase>();
  base->skeleton = first->skeleton;
  base->fixed_translations.resize(std::size_t(J));
  for (int j = 0; j < J; ++j)
    base->fixed_translations[std::size_t(j)] = first->motion.translation(m_file.frame_of[0], j);
  base->frame_time = loaded_frame_time(0);
  const std::lock_guard lock(m_mutex);
  if (!m_base) m_base = std::move(base);
  return m_base;
}

SavedPose SavedMap::pose_at(const Eigen::Vector2d& p, int neighbors, Axis up) const {
  if (!p.allFinite()) {
    throw ParameterError("map point (" + format_number(p.x()) + ", " + format_number(p.y()) +
                         ") is not finite");
  }
  if (neighbors < 1)
    throw ParameterError("neighbors: " + std::to_string(neighbors) + " is not in [1, #samples]");
  SavedPose out;
  std::vector<Neighbor> found = m_index.nearest(p, neighbors + 1);
  if (found.empty()) throw ParameterError("map: no finite sample to blend");
  // synth::MapBlender's idw weights: R is the (K+1)-th distance (with no (K+1)-th sample, twice
  // the farthest).
  const bool has_far = static_cast<int>(found.size()) > neighbors;
  const double R = has_far ? found.back().distance
                           : 2.0 * found.back().distance + std::numeric_limits<double>::min();
  if (has_far) found.pop_back();
  out.outside = found.front().distance > reach_distance();
  const std::size_t count = found.size();
  std::vector<double> distances(count), w(count);
  for (std::size_t i = 0; i < count; ++i) distances[i] = found[i].distance;
  synth::franke_little_weights(distances.data(), static_cast<int>(count), R, w.data());

  // The blended samples' clips (loaded on demand, the first sample's first when the map's base is
  // not read yet).
  const std::shared_ptr<const BlendBase> base = m_file.blend ? blend_base() : nullptr;
  std::vector<std::shared_ptr<const Clip>> clips(count);
  for (std::size_t i = 0; i < count; ++i)
    clips[i] = clip(m_file.clip_of[std::size_t(found[i].sample)]);
  const int nearest_frame = m_file.frame_of[std::size_t(found.front().sample)];

  // The joints and translations of the map's blend (as make_blender's blender has them), or,
  // without the map's record, of these samples' clips: as a blender over just those clips.
  int root = 0;
  std::vector<int> moving;
  std::vector<Eigen::Vector3d> fixed;
  const Skeleton* skeleton = nullptr;
  double frame_time = 0.0;
  if (base) {
    root = m_file.blend->motion_root;
    moving = m_file.blend->moving;
    fixed = base->fixed_translations;
    skeleton = &base->skeleton;
    frame_time = base->frame_time;
  } else {
    std::vector<std::shared_ptr<const Clip>> distinct;
    features::FeatureSet set;
    for (std::size_t i = 0; i < count; ++i) {
      auto it = std::find(distinct.begin(), distinct.end(), clips[i]);
      if (it == distinct.end()) it = distinct.insert(distinct.end(), clips[i]);
      set.clip_of.push_back(static_cast<int>(it - distinct.begin()));
      set.frame_of.push_back(m_file.frame_of[std::size_t(found[i].sample)]);
    }
    const synth::ClipsSummary summary = synth::summarize_clips(
        static_cast<int>(distinct.size()), [&](int c) { return distinct[std::size_t(c)]; }, set);
    root = summary.motion_root;
    moving = summary.moving;
    const Motion& m0 = clips.front()->motion;
    fixed.resize(std::size_t(m0.num_joints));
    for (int j = 0; j < m0.num_joints; ++j)
      fixed[std::size_t(j)] = m0.translation(nearest_frame, j);
    skeleton = &clips.front()->skeleton;
    frame_time = m0.frame_time;
  }

  const std::vector<int> ancestors = synth::root_ancestors(*skeleton, root);

  // Each sample's state, read from its clip, and their blend.
  std::vector<synth::SampleState> states(count);
  std::vector<synth::SampleStateView> views(count);
  for (std::size_t i = 0; i < count; ++i) {
    const Clip& c = *clips[i];
    if (!c.skeleton.same_hierarchy(*skeleton)) {
      throw ParameterError(c.path +
                           ": its joint hierarchy differs from the map's first clip's; clips "
                           "blended together must share one");
    }
    states[i] = synth::clip_sample_state(c, m_file.frame_of[std::size_t(found[i].sample)], root, up,
                                         moving, ancestors);
    views[i] = states[i].view();
  }
  const synth::BlendedFrame blended =
      synth::blend_states(views, w, fixed, moving, root, up, ancestors);
  out.pose.frame_time = frame_time;
  out.pose.resize(1, static_cast<int>(fixed.size()));
  out.pose.rotations = blended.rotations;
  out.pose.translations = blended.translations;
  out.root = root;
  out.ancestors = ancestors;
  out.around = std::move(found);
  out.weights = std::move(w);
  return out;
}

}  // namespace motionmap::mapfile
