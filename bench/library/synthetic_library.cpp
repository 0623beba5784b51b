#include "synthetic_library.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "motionmap/core/error.h"
#include "motionmap/core/files.h"
#include "motionmap/core/parallel.h"
#include "motionmap/features/diagnostics.h"
#include "motionmap/features/point_cloud.h"
#include "motionmap/io/bvh.h"
#include "motionmap/io/load.h"
#include "motionmap/skeleton/forward_kinematics.h"

namespace motionmap::bench {

using Eigen::Quaterniond;
using Eigen::Vector3d;

// ---- Random numbers --------------------------------------------------------------------------

std::uint64_t Random::next() {
  // SplitMix64 (Steele, Lea, Flood 2014): a 64-bit counter through a bijective mixer.
  std::uint64_t z = (m_state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

double Random::uniform() {
  return static_cast<double>(next() >> 11) * 0x1.0p-53;
}

int Random::index(int n) {
  return static_cast<int>(next() % static_cast<std::uint64_t>(n));
}

std::uint64_t clip_seed(std::uint64_t seed, std::int64_t index) {
  Random mix(seed ^ (0xD1B54A32D192ED03ull * static_cast<std::uint64_t>(index + 1)));
  mix.next();
  return mix.next();
}

namespace {

// A smooth signal in [−1, 1]: three sinusoids of random amplitude, period and phase, normalised
// by the sum of their amplitudes.
struct SmoothSignal {
  double amplitude[3], omega[3], phase[3];

  SmoothSignal(Random& random, double min_period, double max_period) {
    double total = 0.0;
    for (int k = 0; k < 3; ++k) {
      amplitude[k] = random.uniform(0.5, 1.0);
      omega[k] = 2.0 * kPi / random.uniform(min_period, max_period);
      phase[k] = random.uniform(0.0, 2.0 * kPi);
      total += amplitude[k];
    }
    for (double& a : amplitude) a /= total;
  }
  double operator()(double t) const {
    return amplitude[0] * std::sin(omega[0] * t + phase[0]) +
           amplitude[1] * std::sin(omega[1] * t + phase[1]) +
           amplitude[2] * std::sin(omega[2] * t + phase[2]);
  }
};

// The reflection M across the plane normal to `lateral`.
Vector3d reflect(const Vector3d& v, Axis lateral) {
  Vector3d r = v;
  r[static_cast<int>(lateral)] = -r[static_cast<int>(lateral)];
  return r;
}

// M·R·M as a quaternion: w and the lateral component kept, the other two negated.
Quaterniond reflect(const Quaterniond& q, Axis lateral) {
  const int a = static_cast<int>(lateral);
  Quaterniond r(q.w(), -q.x(), -q.y(), -q.z());
  r.vec()[a] = q.vec()[a];
  return r;
}

// World transforms of the rest pose (identity rotations, translations = offsets).
WorldPose rest_pose(const Skeleton& skeleton) {
  Motion rest;
  rest.resize(1, skeleton.num_joints());
  for (int j = 0; j < skeleton.num_joints(); ++j)
    rest.translation(0, j) = skeleton.joints[j].offset;
  return forward_kinematics(skeleton, rest, 0);
}

bool has_position_channels(const Joint& joint) {
  return std::any_of(joint.channels.begin(), joint.channels.end(),
                     [](ChannelType c) { return !is_rotation(c); });
}
bool has_rotation_channels(const Joint& joint) {
  return std::any_of(joint.channels.begin(), joint.channels.end(),
                     [](ChannelType c) { return is_rotation(c); });
}

// The name of `name`'s left↔right partner by CMU's conventions, or "" if it has none.
std::string partner_name(const std::string& name) {
  auto starts = [&](const char* prefix) { return name.rfind(prefix, 0) == 0; };
  if (starts("Left")) return "Right" + name.substr(4);
  if (starts("Right")) return "Left" + name.substr(5);
  if (name.size() >= 2 && (name[0] == 'L' || name[0] == 'R') && name[1] >= 'A' && name[1] <= 'Z') {
    return (name[0] == 'L' ? "R" : "L") + name.substr(1);
  }
  return "";
}

void check_partners(std::span<const int> partners, int joints, const char* who) {
  if (static_cast<int>(partners.size()) != joints) {
    throw ParameterError(std::string(who) + ": " + std::to_string(partners.size()) +
                         " partners for " + std::to_string(joints) + " joints");
  }
}

// Up is Y throughout: CMU's files, and every clip this generator is meant for.
constexpr Axis kUp = Axis::Y;

}  // namespace

// ---- Mirroring -------------------------------------------------------------------------------

std::vector<int> mirror_partners(const Skeleton& skeleton) {
  const int n = skeleton.num_joints();
  std::vector<int> partners(n);
  for (int j = 0; j < n; ++j) {
    const std::string other = partner_name(skeleton.joints[j].name);
    const int p = other.empty() ? -1 : skeleton.find(other);
    partners[j] = p >= 0 ? p : j;
  }
  for (int j = 0; j < n; ++j) {
    const Joint& joint = skeleton.joints[j];
    const Joint& partner = skeleton.joints[partners[j]];
    const int parent_partner = joint.parent < 0 ? -1 : partners[joint.parent];
    if (partner.parent != parent_partner || partner.end_sites.size() != joint.end_sites.size()) {
      throw ParameterError("mirror_partners: joint '" + joint.name + "' and its partner '" +
                           partner.name +
                           "' are not mirror images in the hierarchy (parents or End Sites "
                           "differ)");
    }
  }
  return partners;
}

Axis lateral_axis(const Skeleton& skeleton, std::span<const int> partners) {
  check_partners(partners, skeleton.num_joints(), "lateral_axis");
  const WorldPose rest = rest_pose(skeleton);
  Vector3d spread = Vector3d::Zero();
  bool pairs = false;
  for (int j = 0; j < skeleton.num_joints(); ++j) {
    if (partners[j] == j) continue;
    pairs = true;
    spread += (rest.positions[j] - rest.positions[partners[j]]).cwiseAbs();
  }
  if (!pairs || spread.maxCoeff() <= 0.0) {
    throw ParameterError("lateral_axis: the skeleton has no left/right joint pair apart at rest");
  }
  int axis = 0;
  spread.maxCoeff(&axis);
  return static_cast<Axis>(axis);
}

Skeleton mirror_skeleton(const Skeleton& skeleton, std::span<const int> partners, Axis lateral) {
  check_partners(partners, skeleton.num_joints(), "mirror_skeleton");
  Skeleton out = skeleton;
  for (int j = 0; j < skeleton.num_joints(); ++j) {
    const Joint& from = skeleton.joints[partners[j]];
    out.joints[j].offset = reflect(from.offset, lateral);
    for (std::size_t e = 0; e < from.end_sites.size(); ++e) {
      out.joints[j].end_sites[e] = reflect(from.end_sites[e], lateral);
    }
  }
  return out;
}

Motion mirror_motion(const Motion& motion, std::span<const int> partners, Axis lateral) {
  const int joints = motion.num_joints;
  check_partners(partners, joints, "mirror_motion");
  Motion out = motion;
  for (int f = 0; f < motion.num_frames; ++f) {
    for (int j = 0; j < joints; ++j) {
      out.rotation(f, j) = reflect(motion.rotation(f, partners[j]), lateral);
      out.translation(f, j) = reflect(motion.translation(f, partners[j]), lateral);
    }
  }
  return out;
}

// ---- Time warps ------------------------------------------------------------------------------

Motion resample(const Motion& motion, std::span<const double> at) {
  const int n = motion.num_frames;
  if (n < 2) throw ParameterError("resample: the motion has " + std::to_string(n) + " frames");
  Motion out;
  out.frame_time = motion.frame_time;
  out.resize(static_cast<int>(at.size()), motion.num_joints);
  for (int i = 0; i < out.num_frames; ++i) {
    const double u = at[i];
    if (!(u >= 0.0 && u <= n - 1)) {
      throw ParameterError("resample: position " + std::to_string(u) + " is outside [0, " +
                           std::to_string(n - 1) + "]");
    }
    const int k = std::min(static_cast<int>(u), n - 2);
    const double a = u - k;
    for (int j = 0; j < motion.num_joints; ++j) {
      out.rotation(i, j) = motion.rotation(k, j).slerp(a, motion.rotation(k + 1, j)).normalized();
      out.translation(i, j) =
          (1.0 - a) * motion.translation(k, j) + a * motion.translation(k + 1, j);
    }
  }
  return out;
}

std::vector<double> time_warp(Random& random, double start, double end, int max_frames,
                              double max_rate, double step, double frame_time) {
  if (!(max_rate >= 1.0) || !(step > 0.0) || !(end >= start) || max_frames < 1 ||
      !(frame_time > 0.0)) {
    throw ParameterError("time_warp: expected max_rate ≥ 1, step > 0, end ≥ start, max_frames ≥ 1");
  }
  const SmoothSignal signal(random, 1.0, 4.0);
  const double log_rate = std::log(max_rate);
  std::vector<double> u;
  double x = start;
  for (int i = 0; i < max_frames && x <= end; ++i) {
    u.push_back(x);
    x += std::exp(log_rate * signal(i * frame_time)) * step;
  }
  return u;
}

// ---- Sources ---------------------------------------------------------------------------------

std::vector<Source> load_sources(const std::string& directory, std::vector<std::string>* notes) {
  namespace fs = std::filesystem;
  std::error_code ec;
  std::vector<std::string> paths;
  for (fs::directory_iterator it(directory, ec), end; !ec && it != end; it.increment(ec)) {
    if (it->is_regular_file() && it->path().extension() == ".bvh") {
      paths.push_back(it->path().string());
    }
  }
  if (ec) throw Error(directory + ": cannot list the directory: " + ec.message());
  std::sort(paths.begin(), paths.end());

  auto note = [&](const std::string& s) {
    if (notes) notes->push_back(s);
  };
  std::vector<Source> sources;
  for (const std::string& path : paths) {
    Clip clip = io::load_clip(path);
    const std::string name = base_name(path);
    if (!sources.empty() && !clip.skeleton.same_hierarchy(sources.front().clip.skeleton)) {
      note(name + ": skipped: its joint hierarchy differs from " +
           base_name(sources.front().clip.path) + "'s");
      continue;
    }
    const auto bind = features::check_leading_bind_pose(
        features::heading_local_points(clip.skeleton, clip.motion, kUp));
    if (bind.detected) {
      note(name + ": frame 0 is a bind pose; left out");
      Motion& m = clip.motion;
      const auto joints = static_cast<std::ptrdiff_t>(m.num_joints);
      m.rotations.erase(m.rotations.begin(), m.rotations.begin() + joints);
      m.translations.erase(m.translations.begin(), m.translations.begin() + joints);
      --m.num_frames;
    }
    if (clip.motion.num_frames < 3) {
      note(name + ": skipped: fewer than 3 frames");
      continue;
    }
    Source s;
    try {
      s.partners = mirror_partners(clip.skeleton);
      for (int j = 0; j < clip.skeleton.num_joints(); ++j) {
        s.can_mirror = s.can_mirror || s.partners[j] != j;
      }
      if (s.can_mirror) s.lateral = lateral_axis(clip.skeleton, s.partners);
    } catch (const ParameterError& e) {
      note(name + ": not mirrored: " + e.what());
      s.can_mirror = false;
    }
    if (!s.can_mirror) s.partners.clear();
    const WorldPose rest = rest_pose(clip.skeleton);
    double lowest = std::numeric_limits<double>::infinity();
    for (const Vector3d& p : rest.positions) lowest = std::min(lowest, p.y());
    for (const Vector3d& p : rest.end_sites) lowest = std::min(lowest, p.y());
    // A root on the floor (Bandai's joint_Root, the hips' ground projection, which carries the
    // motion in some of its takes): the height of the first joint of its chain above the floor.
    int hip = motion_root(clip.skeleton, clip.motion);
    while (!(rest.positions[hip].y() - lowest > 0.0)) {
      int child = -1, children = 0;
      for (int j = hip + 1; j < clip.skeleton.num_joints(); ++j) {
        if (clip.skeleton.joints[j].parent == hip) {
          child = j;
          ++children;
        }
      }
      if (children != 1) break;
      hip = child;
    }
    s.hip_height = rest.positions[hip].y() - lowest;
    if (!(s.hip_height > 0.0)) {
      note(name +
           ": skipped: neither its root nor a joint of its chain is above its lowest joint "
           "at rest");
      continue;
    }
    s.clip = std::move(clip);
    sources.push_back(std::move(s));
  }
  if (sources.empty()) throw Error(directory + ": no usable .bvh clip");
  return sources;
}

// ---- The library -----------------------------------------------------------------------------

void LibraryOptions::validate() const {
  auto fail = [](const std::string& what) { throw ParameterError(what); };
  if (frames < 1) fail("frames: " + std::to_string(frames) + " (expected ≥ 1)");
  if (clip_frames < 1) fail("clip_frames: " + std::to_string(clip_frames) + " (expected ≥ 1)");
  if (!(max_rate >= 1.0 && max_rate <= 4.0)) {
    fail("max_rate: " + std::to_string(max_rate) + " (expected in [1, 4])");
  }
  if (!(mirror_probability >= 0.0 && mirror_probability <= 1.0)) {
    fail("mirror_probability: " + std::to_string(mirror_probability) + " (expected in [0, 1])");
  }
  if (!(noise_degrees >= 0.0 && noise_degrees <= 45.0)) {
    fail("noise_degrees: " + std::to_string(noise_degrees) + " (expected in [0, 45])");
  }
  if (!(noise_translation >= 0.0 && noise_translation <= 1.0)) {
    fail("noise_translation: " + std::to_string(noise_translation) + " (expected in [0, 1])");
  }
  if (segment_min < 1 || segment_max < segment_min) {
    fail("segment frames: " + std::to_string(segment_min) + ":" + std::to_string(segment_max) +
         " (expected 1 ≤ min ≤ max)");
  }
  if (blend_frames < 0) fail("blend_frames: " + std::to_string(blend_frames) + " (expected ≥ 0)");
  if (decimals > 15) fail("decimals: " + std::to_string(decimals) + " (expected ≤ 15)");
}

namespace {

// Moves every root of `seg` by the rigid motion x ↦ Y·(x − from) + to, Y the turn by `yaw` about
// the up axis (the roots' transforms are world transforms).
void move_roots(const Skeleton& skeleton, Motion& seg, double yaw, const Vector3d& from,
                const Vector3d& to) {
  const Quaterniond turn(Eigen::AngleAxisd(yaw, Vector3d::Unit(static_cast<int>(kUp))));
  for (int j : skeleton.roots()) {
    for (int f = 0; f < seg.num_frames; ++f) {
      seg.rotation(f, j) = (turn * seg.rotation(f, j)).normalized();
      seg.translation(f, j) = turn * (seg.translation(f, j) - from) + to;
    }
  }
}

Vector3d on_floor(Vector3d v) {
  v[static_cast<int>(kUp)] = 0.0;
  return v;
}

}  // namespace

SyntheticClip make_clip(std::span<const Source> sources, const LibraryOptions& options,
                        std::int64_t index, int frames) {
  options.validate();
  if (frames < 1) throw ParameterError("make_clip: frames " + std::to_string(frames));
  if (sources.empty()) throw ParameterError("make_clip: no sources");
  Random random(clip_seed(options.seed, index));
  const int target_index = random.index(static_cast<int>(sources.size()));
  const Source& target = sources[target_index];
  const Skeleton& skeleton = target.clip.skeleton;
  const int joints = skeleton.num_joints();

  SyntheticClip result;
  result.clip.skeleton = skeleton;
  Motion& out = result.clip.motion;
  out.frame_time = target.clip.motion.frame_time;
  out.resize(frames, joints);

  const double first_heading = random.uniform(-kPi, kPi);
  int done = 0;
  while (done < frames) {
    // 1. A window of a source, time-warped.
    const int s = random.index(static_cast<int>(sources.size()));
    const Source& source = sources[s];
    const Motion& src = source.clip.motion;
    const double last = src.num_frames - 1;
    const double start = random.uniform(0.0, 0.5 * last);
    const int wanted =
        options.segment_min + random.index(options.segment_max - options.segment_min + 1);
    const std::vector<double> at =
        time_warp(random, start, last, std::min(wanted, frames - done), options.max_rate,
                  out.frame_time / src.frame_time, out.frame_time);
    Motion seg = resample(src, at);

    // 2. Mirrored or not (drawn even when the source cannot be mirrored, so that one source
    //    without pairs does not shift every later draw).
    const bool mirrored = random.uniform() < options.mirror_probability && source.can_mirror;
    if (mirrored) seg = mirror_motion(seg, source.partners, source.lateral);

    // 3. On the output skeleton: its offsets, the root's travel scaled to its size.
    const double scale = target.hip_height / source.hip_height;
    for (int j = 0; j < joints; ++j) {
      const bool animated = has_position_channels(skeleton.joints[j]);
      for (int f = 0; f < seg.num_frames; ++f) {
        seg.translation(f, j) =
            animated ? Vector3d(scale * seg.translation(f, j)) : skeleton.joints[j].offset;
      }
    }

    // 4. Turned and moved to go on from the previous segment (the first: a random heading, from
    //    the origin), then blended into it.
    const int root = motion_root(skeleton, seg);
    const WorldPose first = forward_kinematics(skeleton, seg, 0);
    const double heading = features::heading_angle(first.rotations[root], kUp);
    const Vector3d from = on_floor(first.positions[root]);
    if (done == 0) {
      move_roots(skeleton, seg, wrap_angle(first_heading - heading), from, Vector3d::Zero());
    } else {
      const WorldPose prev = forward_kinematics(skeleton, out, done - 1);
      Vector3d to = on_floor(prev.positions[root]);
      if (done >= 2)
        to += to - on_floor(forward_kinematics(skeleton, out, done - 2).positions[root]);
      move_roots(skeleton, seg,
                 wrap_angle(features::heading_angle(prev.rotations[root], kUp) - heading), from,
                 to);
      // Offset blending: frame i carries (1 − w_i) of the step between the previous last frame
      // and this segment's first, w rising smoothly to 1 over blend_frames frames. w_0 > 0, so
      // no frame repeats the previous one.
      std::vector<Quaterniond> delta(joints);
      for (int j = 0; j < joints; ++j) {
        delta[j] = seg.rotation(0, j).conjugate() * out.rotation(done - 1, j);
      }
      Vector3d lift = Vector3d::Zero();
      lift[static_cast<int>(kUp)] = prev.positions[root][static_cast<int>(kUp)] -
                                    first.positions[root][static_cast<int>(kUp)];
      const int blend = std::min(options.blend_frames, seg.num_frames);
      for (int i = 0; i < blend; ++i) {
        const double x = (i + 1.0) / (options.blend_frames + 1.0);
        const double keep = 1.0 - x * x * (3.0 - 2.0 * x);
        for (int j = 0; j < joints; ++j) {
          seg.rotation(i, j) =
              (seg.rotation(i, j) * Quaterniond::Identity().slerp(keep, delta[j])).normalized();
        }
        for (int j : skeleton.roots()) seg.translation(i, j) += keep * lift;
      }
    }

    std::copy(seg.rotations.begin(), seg.rotations.end(),
              out.rotations.begin() + static_cast<std::ptrdiff_t>(done) * joints);
    std::copy(seg.translations.begin(), seg.translations.end(),
              out.translations.begin() + static_cast<std::ptrdiff_t>(done) * joints);
    result.segments.push_back({done, seg.num_frames, s, at.front(), at.back(), mirrored});
    done += seg.num_frames;
  }

  // 5. Small smooth noise over the whole clip: a rotation vector of three smooth signals (periods
  //    0.5–3 s) on every rotated joint, a smooth offset on every translated one.
  const double angle = deg_to_rad(options.noise_degrees);
  const double shift = options.noise_translation * target.hip_height;
  for (int j = 0; j < joints; ++j) {
    const Joint& joint = skeleton.joints[j];
    const bool rotated = has_rotation_channels(joint), moved = has_position_channels(joint);
    if (!rotated && !moved) continue;
    const SmoothSignal r[3] = {{random, 0.5, 3.0}, {random, 0.5, 3.0}, {random, 0.5, 3.0}};
    const SmoothSignal t[3] = {{random, 0.5, 3.0}, {random, 0.5, 3.0}, {random, 0.5, 3.0}};
    for (int f = 0; f < frames; ++f) {
      const double time = f * out.frame_time;
      if (rotated && angle > 0.0) {
        const Vector3d v = angle * Vector3d(r[0](time), r[1](time), r[2](time));
        const double norm = v.norm();
        if (norm > 0.0) {
          out.rotation(f, j) =
              (out.rotation(f, j) * Quaterniond(Eigen::AngleAxisd(norm, v / norm))).normalized();
        }
      }
      if (moved && shift > 0.0) {
        out.translation(f, j) += shift * Vector3d(t[0](time), t[1](time), t[2](time));
      }
    }
  }
  return result;
}

void round_values(std::vector<double>& values, int decimals) {
  if (decimals < 0) return;
  const double scale = std::pow(10.0, decimals);
  // n / 10^d is the double nearest to the decimal n·10^-d, so the writer's shortest round-trip
  // form prints it with at most d decimals. Adding 0.0 turns −0 into 0.
  for (double& v : values) v = std::round(v * scale) / scale + 0.0;
}

std::vector<std::string> write_library(
    std::span<const Source> sources, const LibraryOptions& options, const std::string& directory,
    const std::function<void(std::int64_t, std::int64_t)>& progress) {
  options.validate();
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(directory, ec);
  if (ec) throw Error(directory + ": cannot create the directory: " + ec.message());

  const std::int64_t count = (options.frames + options.clip_frames - 1) / options.clip_frames;
  if (count > std::numeric_limits<int>::max()) {
    throw ParameterError("frames / clip_frames: too many files (" + std::to_string(count) + ")");
  }
  const std::size_t width = std::max<std::size_t>(5, std::to_string(count - 1).size());
  auto frames_of = [&](std::int64_t i) {
    return static_cast<int>(
        std::min<std::int64_t>(options.clip_frames, options.frames - i * options.clip_frames));
  };
  std::vector<std::string> names(count), paths(count);
  for (std::int64_t i = 0; i < count; ++i) {
    std::string number = std::to_string(i);
    names[i] = "clip_" + std::string(width - std::min<std::size_t>(width, number.size()), '0') +
               number + ".bvh";
    paths[i] = (fs::path(directory) / names[i]).string();
  }

  // Clips are independent (clip i depends on (seed, i) only), so they are made in parallel; the
  // manifest lines are kept per clip and written in order.
  std::vector<std::string> manifest(count);
  parallel_chunks(
      static_cast<int>(count),
      [&](int i, int) {
        const SyntheticClip clip = make_clip(sources, options, i, frames_of(i));
        io::BvhDocument doc = io::from_motion(clip.clip.skeleton, clip.clip.motion);
        round_values(doc.values, options.decimals);
        io::write_bvh(doc, paths[i]);
        std::ostringstream lines;
        char buf[256];
        for (const Segment& s : clip.segments) {
          std::snprintf(buf, sizeof buf, "%s %d %d %s %.3f %.3f %s\n", names[i].c_str(),
                        s.first_frame, s.frames, base_name(sources[s.source].clip.path).c_str(),
                        s.source_begin, s.source_end, s.mirrored ? "mirrored" : "-");
          lines << buf;
        }
        manifest[i] = lines.str();
      },
      [&](int done) {
        if (progress) progress(done, count);
      });

  const std::string manifest_path = (fs::path(directory) / "manifest.txt").string();
  std::ofstream file(manifest_path, std::ios::binary);
  file << "# motionmap-make-library: frames=" << options.frames
       << " clip_frames=" << options.clip_frames << " seed=" << options.seed
       << " max_rate=" << options.max_rate << " mirror_probability=" << options.mirror_probability
       << " noise_degrees=" << options.noise_degrees
       << " noise_translation=" << options.noise_translation
       << " segment_frames=" << options.segment_min << ":" << options.segment_max
       << " blend_frames=" << options.blend_frames << " decimals=" << options.decimals << "\n";
  file << "# sources:";
  for (const Source& s : sources) {
    file << " " << base_name(s.clip.path) << " (" << s.clip.motion.num_frames << " frames)";
  }
  file << "\n# file first_frame frames source source_begin source_end mirrored\n";
  for (const std::string& lines : manifest) file << lines;
  file.close();
  if (!file) throw Error(manifest_path + ": cannot write the file");
  return paths;
}

}  // namespace motionmap::bench
