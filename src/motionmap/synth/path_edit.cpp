#include "motionmap/synth/path_edit.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <iterator>
#include <optional>
#include <string>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/core/parallel.h"
#include "motionmap/synth/clean_feet.h"
#include "motionmap/synth/detail/outside_route.h"
#include "motionmap/synth/detail/root_motion.h"
#include "motionmap/synth/detail/smoothing.h"

namespace motionmap::synth {

namespace {

// Copies frame `from` of `src` into frame `to` of `dst` (same joints).
void copy_frame(const Motion& src, int from, Motion& dst, int to) {
  const int J = src.num_joints;
  std::copy_n(src.rotations.begin() + static_cast<std::ptrdiff_t>(from) * J, J,
              dst.rotations.begin() + static_cast<std::ptrdiff_t>(to) * J);
  std::copy_n(src.translations.begin() + static_cast<std::ptrdiff_t>(from) * J, J,
              dst.translations.begin() + static_cast<std::ptrdiff_t>(to) * J);
}

// Intervals sorted and merged where they overlap or touch.
std::vector<ContactInterval> merged(std::vector<ContactInterval> iv) {
  std::sort(iv.begin(), iv.end(),
            [](const ContactInterval& a, const ContactInterval& b) { return a.first < b.first; });
  std::vector<ContactInterval> out;
  for (const ContactInterval& c : iv) {
    if (!out.empty() && c.first <= out.back().last + 1) {
      out.back().last = std::max(out.back().last, c.last);
    } else {
      out.push_back(c);
    }
  }
  return out;
}

// How much of a mismatch a window of `count` frames has taken on at each of its frames (0 at the
// first; all of it at the frame after the last): in proportion to how far the root moves (or
// turns) up to that frame, `step(i)` from frame i to i + 1, plus a tenth of its mean step every
// frame. Spread evenly in time, a golf swing edited at the top of its backswing turned 19.5° and
// moved 10.6 cm over 2.2 s, through the address pose where the golfer stands still too, and the
// left foot, held through that, slid 7 cm in 0.15 s onto the turned stance as its heel rose.
template <class Step>
std::vector<double> spread_shares(std::size_t count, Step step) {
  std::vector<double> steps(count);
  double total = 0.0;
  for (std::size_t i = 0; i < count; ++i) total += steps[i] = step(i);
  const double floor = total > 0.0 ? 0.1 * total / static_cast<double>(count) : 1.0;
  std::vector<double> share(count);
  double sum = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    share[i] = sum / (total + floor * static_cast<double>(count));
    sum += steps[i] + floor;
  }
  return share;
}

}  // namespace

void PathEditOptions::validate() const {
  if (!(margin_seconds >= 0.0 && margin_seconds <= 2.0)) {
    throw ParameterError("margin_seconds: " + format_number(margin_seconds) +
                         " is out of range (seconds, must be in [0, 2])");
  }
  if (!(context_seconds >= 0.0 && context_seconds <= 5.0)) {
    throw ParameterError("context_seconds: " + format_number(context_seconds) +
                         " is out of range (seconds, must be in [0, 5])");
  }
}

PathEditResult edit_path(const MapBlender& blender, const SynthResult& previous,
                         const MapPath& path, const PathEditOptions& options,
                         const Control& control) {
  options.validate();
  const SynthOptions& so = previous.options;
  so.validate();
  path.validate();
  const Skeleton& skeleton = blender.skeleton();
  const int J = skeleton.num_joints();
  const int F0 = previous.motion.num_frames;
  const double dt = so.fps > 0.0 ? 1.0 / so.fps : blender.frame_time();
  if (previous.motion.num_joints != J || previous.motion.frame_time != dt ||
      previous.validity.size() != static_cast<std::size_t>(F0) ||
      previous.root_positions.size() != static_cast<std::size_t>(F0) ||
      previous.headings.size() != static_cast<std::size_t>(F0) ||
      previous.heading_offsets.size() != static_cast<std::size_t>(F0) || F0 == 0 ||
      (previous.feet_cleaned && previous.feet_changed.size() != static_cast<std::size_t>(F0)) ||
      (blender.options().mode == BlendMode::Local &&
       previous.stalled.size() != static_cast<std::size_t>(F0))) {
    throw ParameterError(
        "edit_path: the previous result was not made by synthesize() on this blender (its "
        "frames, joints, frame time, root states or stalls do not match)");
  }
  double speed = so.speed;
  if (!path.timed() && speed == 0.0) {
    speed = blender.median_speed();
    if (!(speed > 0.0)) {
      throw ParameterError(
          "speed: the map has no motion to take a default speed from; give one (map units per "
          "second)");
    }
  }
  const std::vector<Eigen::Vector2d> points = blender.path_points(path, dt, speed, kMaxSynthFrames);
  const int F = static_cast<int>(points.size());

  PathEditResult out;
  out.result = previous;
  SynthResult& r = out.result;

  // The frames whose path point changed.
  int r0 = -1, r1 = -1;
  const int common = std::min(F, F0);
  for (int k = 0; k < common; ++k) {
    const Eigen::Vector2d& q = previous.validity[static_cast<std::size_t>(k)].query;
    if (points[static_cast<std::size_t>(k)] != q) {
      if (r0 < 0) r0 = k;
      r1 = k;
    }
  }
  if (F != F0) {
    // A longer or shorter path: the window runs to the new end (its last frames at least).
    r0 = r0 < 0 ? std::max(0, common - 1) : r0;
    r1 = F - 1;
  }
  if (r0 < 0) return out;  // the same path: the same motion
  // A frame's weights read its neighbours' points too (locate_path), and a frame outside the
  // data its whole run's and the blends of the frames on either side of it
  // (detail::OutsideRoutes): the window takes in every run of the previous path or the new one
  // that a changed frame reaches so (a run whose points are all as before keeps its route).
  const int changed0 = r0, changed1 = r1;
  const int reads = std::min(F, blender.path_neighbours(dt));
  r0 = std::max(0, r0 - reads);
  r1 = std::min(F - 1, r1 + reads);
  std::vector<Eigen::Vector2d> previous_points(static_cast<std::size_t>(F0));
  for (int k = 0; k < F0; ++k)
    previous_points[static_cast<std::size_t>(k)] =
        previous.validity[static_cast<std::size_t>(k)].query;
  // The windows of an edit whose blends change over frames [from, to] (below: the smoothing's
  // reach [a, b), the clean-up's [c0, c1) and what it reads [x0, x1), the frames located
  // [w0, w1)).
  const std::vector<double> kernel = detail::smoothing_kernel(so.smooth, dt, F);
  const int half = static_cast<int>(kernel.size() / 2);
  const bool clean = previous.feet_cleaned;
  const double fps = 1.0 / dt;
  const CleanFeetOptions clean_defaults;
  const int fade = static_cast<int>(std::lround(clean_defaults.blend_seconds * fps));
  const int margin =
      clean ? std::max(fade + 1, static_cast<int>(std::lround(options.margin_seconds * fps))) : 0;
  const int context = clean ? static_cast<int>(std::lround(options.context_seconds * fps)) : 0;
  struct Windows {
    int a, b, c0, c1, x0, x1, w0, w1;
  };
  const auto windows_of = [&](int from, int to) {
    Windows w{};
    w.a = std::max(0, from - half);
    w.b = std::min(F, to + half + 1);
    w.c0 = std::max(0, w.a - margin);
    w.c1 = std::min(F, w.b + margin);
    w.x0 = std::max(0, w.c0 - context);
    w.x1 = std::min(F, w.c1 + context);
    w.w0 = std::max(0, w.x0 - half);
    w.w1 = std::min(F, w.x1 + half);
    return w;
  };

  // The frames where a gait's blend stalls (detail::stalled_frames, read from a frame's located
  // pace and the path's points beside it): the previous ones but where a point they read
  // changed, located again there. A run routed around them that such a frame reaches (within
  // stall_spread frames) is remade too. Those frames are located together with the window the
  // edit needs without such runs (one call: each reads the frames around its range too), and
  // kept for the blend (a frame's located weights are the same whatever frames it is located
  // with).
  const int spread = detail::stall_spread(dt);
  const int pad = blender.follow_neighbours(dt);
  std::vector<char> stalled;
  const int s0 = std::max(0, changed0 - reads - 1), s1 = std::min(F, changed1 + reads + 2);
  const Windows least = windows_of(r0, r1);
  const int l0 = std::min(s0, least.w0), l1 = std::max(s1, least.w1);
  std::vector<MapWeights> around;  // frames [l0, l1) located, in the local mode
  if (blender.options().mode == BlendMode::Local) {
    stalled = previous.stalled;
    stalled.resize(static_cast<std::size_t>(F), 0);
    around = blender.locate_path(points, dt, static_cast<std::size_t>(l0),
                                 static_cast<std::size_t>(l1), &r.fits);
    const std::vector<char> again = detail::stalled_frames(
        blender, points, dt, std::span<const MapWeights>(around).subspan(s0 - l0, s1 - s0),
        static_cast<std::size_t>(s0));
    std::copy(again.begin(), again.end(), stalled.begin() + s0);
  }
  const auto routed_runs = detail::outside_runs(blender, points, stalled, spread, pad);
  auto runs = routed_runs;
  for (const auto& run :
       detail::outside_runs(blender, previous_points, previous.stalled, spread, pad))
    runs.push_back(run);
  const int reach = reads + 1 + spread + pad;
  for (const auto& [first, end] : runs) {
    const int a = static_cast<int>(first), b = static_cast<int>(end) - 1;
    if (a - reach > changed1 || b + reach < changed0) continue;
    r0 = std::min(r0, a);
    r1 = std::max(r1, std::min(F - 1, b));
  }
  r.stalled = std::move(stalled);

  const Windows window = windows_of(r0, r1);
  const int a = window.a, b = window.b, c0 = window.c0, c1 = window.c1, x0 = window.x0,
            x1 = window.x1, w0 = window.w0, w1 = window.w1;
  out.blend_first = a;
  out.blend_end = b;
  out.first = a;
  out.end = b;

  // Raw weights of the frames the blends of [x0, x1) read: those located above, the others now.
  control.check();
  std::vector<MapWeights> raw;
  raw.reserve(static_cast<std::size_t>(w1 - w0));
  {
    const auto locate = [&](int from, int to) {
      return blender.locate_path(points, dt, static_cast<std::size_t>(from),
                                 static_cast<std::size_t>(to), &r.fits);
    };
    std::vector<MapWeights> located;
    const int k0 = std::clamp(l0, w0, w1), k1 = std::clamp(l1, k0, w1);
    if (around.empty() || k0 == k1) {
      located = locate(w0, w1);
    } else {
      if (w0 < k0) located = locate(w0, k0);
      located.insert(located.end(), std::make_move_iterator(around.begin() + (k0 - l0)),
                     std::make_move_iterator(around.begin() + (k1 - l0)));
      if (k1 < w1) {
        for (MapWeights& w : locate(k1, w1)) located.push_back(std::move(w));
      }
    }
    const detail::OutsideRoutes outside(blender, points, dt, routed_runs,
                                        static_cast<std::size_t>(w0), static_cast<std::size_t>(w1),
                                        control, located, static_cast<std::size_t>(w0));
    for (std::size_t i = 0; i < located.size(); ++i) {
      outside.apply(static_cast<std::size_t>(w0) + i, located[i]);
      raw.push_back(std::move(located[i]));
    }
  }
  std::vector<MapWeights> weights(static_cast<std::size_t>(x1 - x0));
  parallel_for(x1 - x0, [&](int i) {
    const int k = x0 + i;
    weights[static_cast<std::size_t>(i)] =
        half == 0 ? raw[static_cast<std::size_t>(k - w0)]
                  : detail::smoothed(raw, w0, k, F, kernel, dt, blender);
  });
  if (blender.reads_on_demand()) blender.prefetch(weights);

  // Blend [x0, x1): the root's tilt and height only (its heading and floor position below).
  Motion raw_motion;
  raw_motion.frame_time = dt;
  raw_motion.resize(x1 - x0, J);
  std::vector<Eigen::Vector3d> velocity(static_cast<std::size_t>(x1 - x0));
  std::vector<double> yaw_rate(static_cast<std::size_t>(x1 - x0));
  std::vector<double> sway(static_cast<std::size_t>(x1 - x0));
  std::vector<std::array<double, 2>> shares(static_cast<std::size_t>(x1 - x0));
  std::atomic<bool> shares_known = true;
  parallel_for(x1 - x0, [&](int f) {
    const auto i = static_cast<std::size_t>(f);
    const BlendedFrame bf = blender.blend(weights[i]);
    for (int j = 0; j < J; ++j) {
      raw_motion.rotation(f, j) = bf.rotations[static_cast<std::size_t>(j)];
      raw_motion.translation(f, j) = bf.translations[static_cast<std::size_t>(j)];
    }
    velocity[i] = bf.velocity;
    yaw_rate[i] = bf.yaw_rate;
    sway[i] = bf.heading_offset;
    if (const auto share = blender.contact_share(weights[i])) {
      shares[i] = *share;
    } else {
      shares_known = false;
    }
  });
  control.check();

  // The feet the clean-up holds (a previous result with clean feet: the skeleton has them).
  const std::optional<Feet> feet =
      clean ? std::optional<Feet>(find_feet(skeleton, blender.options().up)) : std::nullopt;

  // Root states: the previous ones outside [a, b); inside, integrated from the previous state at
  // a (as synthesize() does: with clean feet, following the planted feet; the turning from the
  // previous heading less its sway), the mismatch at b spread over the window where the root
  // moves (spread_shares).
  r.root_positions.resize(static_cast<std::size_t>(F));
  r.headings.resize(static_cast<std::size_t>(F));
  r.heading_offsets.resize(static_cast<std::size_t>(F));
  std::copy(sway.begin() + (a - x0), sway.begin() + (b - x0), r.heading_offsets.begin() + a);
  {
    const std::vector<detail::FeetFrame> standing =
        clean && shares_known
            ? detail::feet_frames(skeleton, raw_motion, blender.motion_root(), *feet, shares)
            : std::vector<detail::FeetFrame>{};
    const auto from = static_cast<std::size_t>(a - x0), count = static_cast<std::size_t>(b - a);
    const detail::RootState end = detail::integrate_root(
        {previous.root_positions[static_cast<std::size_t>(a)],
         previous.headings[static_cast<std::size_t>(a)] -
             previous.heading_offsets[static_cast<std::size_t>(a)]},
        std::span(velocity).subspan(from, count), std::span(yaw_rate).subspan(from, count),
        std::span(sway).subspan(from), dt,
        standing.empty() ? std::span<const detail::FeetFrame>() : std::span(standing).subspan(from),
        blender.options().up,
        std::span(r.root_positions).subspan(static_cast<std::size_t>(a), count),
        std::span(r.headings).subspan(static_cast<std::size_t>(a), count));
    if (b < F) {
      const Eigen::Vector3d dx =
          previous.root_positions[static_cast<std::size_t>(b)] - end.position;
      // The heading reached at b: the turning integrated and b's sway (as before the edit).
      const double reached = end.heading + previous.heading_offsets[static_cast<std::size_t>(b)];
      const double dh = wrap_angle(previous.headings[static_cast<std::size_t>(b)] - reached);
      const std::vector<double> travel = spread_shares(count, [&](std::size_t i) {
        const Eigen::Vector3d& to = i + 1 < count ? r.root_positions[a + i + 1] : end.position;
        return (to - r.root_positions[a + i]).norm();
      });
      const std::vector<double> turn = spread_shares(count, [&](std::size_t i) {
        const double to = i + 1 < count ? r.headings[a + i + 1] : reached;
        return std::abs(wrap_angle(to - r.headings[a + i]));
      });
      for (int k = a + 1; k < b; ++k) {
        const auto i = static_cast<std::size_t>(k - a);
        r.root_positions[static_cast<std::size_t>(k)] += travel[i] * dx;
        r.headings[static_cast<std::size_t>(k)] += turn[i] * dh;
      }
    }
  }
  const int root = blender.motion_root();
  const Axis up = blender.options().up;
  for (int k = x0; k < x1; ++k) {
    const auto s = static_cast<std::size_t>(k);
    const Eigen::Vector3d& position =
        (k >= a && k < b) ? r.root_positions[s] : previous.root_positions[s];
    const double heading = (k >= a && k < b) ? r.headings[s] : previous.headings[s];
    Eigen::Quaterniond& q = raw_motion.rotation(k - x0, root);
    q = (axis_rotation(up, heading) * q).normalized();
    raw_motion.translation(k - x0, root) += position;
  }

  // The result's per-frame state.
  if (F != F0) {
    Motion resized;
    resized.frame_time = dt;
    resized.resize(F, J);
    for (int k = 0; k < common; ++k) copy_frame(previous.motion, k, resized, k);
    r.motion = std::move(resized);
    r.validity.resize(static_cast<std::size_t>(F));
    if (!r.contact_shares.empty()) r.contact_shares.resize(static_cast<std::size_t>(F));
    if (!r.feet_changed.empty()) r.feet_changed.resize(static_cast<std::size_t>(F), 0);
  }
  for (int k = a; k < b; ++k) {
    const auto i = static_cast<std::size_t>(k - x0);
    r.validity[static_cast<std::size_t>(k)] = weights[i].validity;
    if (!r.contact_shares.empty()) r.contact_shares[static_cast<std::size_t>(k)] = shares[i];
  }
  if (!shares_known) r.contact_shares.clear();
  r.clamped_frames = 0;
  for (const PointValidity& v : r.validity) r.clamped_frames += v.clamped ? 1 : 0;
  r.routed_frames = detail::routed_outside(routed_runs, r.validity);
  r.notes.clear();
  if (std::string note = detail::stalled_note(r.stalled, r.validity); !note.empty())
    r.notes.push_back(std::move(note));

  if (!clean) {
    for (int k = a; k < b; ++k) copy_frame(raw_motion, k - x0, r.motion, k);
    return out;
  }

  // Feet: clean [x0, x1) with the borders of [c0, c1) given as the previous motion's and fixed,
  // then fade from the previous frames to the new ones over the margins.
  CleanFeetOptions clean_options;
  clean_options.contacts.up = up;
  Motion input = raw_motion;
  if (c0 < a) {
    copy_frame(previous.motion, c0, input, c0 - x0);
    clean_options.fixed_frames.push_back(c0 - x0);
  }
  if (c1 > b && c1 - 1 < F0) {
    copy_frame(previous.motion, c1 - 1, input, c1 - 1 - x0);
    clean_options.fixed_frames.push_back(c1 - 1 - x0);
  }
  std::vector<std::array<double, 2>> input_shares;
  if (shares_known && previous.contact_shares.size() == static_cast<std::size_t>(F0)) {
    input_shares.resize(static_cast<std::size_t>(x1 - x0));
    for (int k = x0; k < x1; ++k) {
      input_shares[static_cast<std::size_t>(k - x0)] =
          (k >= a && k < b) ? shares[static_cast<std::size_t>(k - x0)]
                            : previous.contact_shares[static_cast<std::size_t>(k)];
    }
  }
  // The contacts of the window's blend itself, as a full synthesis finds them in the whole blend
  // (found in `input`, the border frames' held feet would start or cut a contact elsewhere).
  const std::array<FootContacts, 2> contacts =
      input_shares.empty()
          ? detect_contacts(skeleton, raw_motion, *feet, clean_options.contacts)
          : contacts_from_shares(skeleton, raw_motion, *feet, input_shares, clean_options.contacts);
  const CleanFeetResult cleaned =
      clean_feet(skeleton, input, *feet, contacts, clean_options, control);
  out.first = c0;
  out.end = c1;
  for (int k = c0; k < c1; ++k) {
    const int n = k - x0;
    double u = 1.0;  // 1: the new frame; 0: the previous one
    if (k < a) {
      u = static_cast<double>(k - c0) / static_cast<double>(a - c0);
    } else if (k >= b) {
      u = static_cast<double>(c1 - 1 - k) / static_cast<double>(c1 - b);
    }
    const auto at = static_cast<std::size_t>(k);
    const char cleaned_here = cleaned.changed[static_cast<std::size_t>(n)];
    if (k >= F0 || u >= 1.0) {
      copy_frame(cleaned.motion, n, r.motion, k);
      r.feet_changed[at] = cleaned_here;
      continue;
    }
    if (u <= 0.0) continue;  // the previous frame, as it is
    // Outside the blend window the new blend is the previous one (the same weights and root
    // states): a frame neither clean-up changed is that blend, and stays as it is.
    if (!cleaned_here && !r.feet_changed[at]) continue;
    r.feet_changed[at] = 1;
    const double s = u * u * (3.0 - 2.0 * u);
    for (int j = 0; j < J; ++j) {
      Eigen::Quaterniond& q = r.motion.rotation(k, j);
      q = q.slerp(s, cleaned.motion.rotation(n, j)).normalized();
      Eigen::Vector3d& t = r.motion.translation(k, j);
      t = (1.0 - s) * t + s * cleaned.motion.translation(n, j);
    }
  }
  // What was held: the previous contacts outside [c0, c1), the new ones inside.
  for (int side = 0; side < 2; ++side) {
    std::vector<ContactInterval> iv;
    for (const ContactInterval& c :
         previous.contacts.size() == 2 ? previous.contacts[static_cast<std::size_t>(side)].intervals
                                       : std::vector<ContactInterval>{}) {
      if (c.last < c0 || c.first >= c1) {
        if (c.first < F) iv.push_back({c.first, std::min(c.last, F - 1)});
      } else {
        if (c.first < c0) iv.push_back({c.first, c0 - 1});
        if (c.last >= c1) iv.push_back({c1, c.last});
      }
    }
    for (const ContactInterval& c : cleaned.contacts[static_cast<std::size_t>(side)].intervals) {
      const int f = std::max(c.first + x0, c0), l = std::min(c.last + x0, c1 - 1);
      if (f <= l) iv.push_back({f, l});
    }
    if (r.contacts.size() == 2) {
      r.contacts[static_cast<std::size_t>(side)].intervals = merged(std::move(iv));
    }
  }
  // The clean-up's count over the whole motion: the previous frames' outside [c0, c1).
  r.feet_frames_changed = 0;
  for (char c : r.feet_changed) r.feet_frames_changed += c;
  if (std::string note = unreachable_feet_note(cleaned, "the edited part"); !note.empty()) {
    r.notes.push_back(std::move(note));
  }
  return out;
}

PathEditResult edit_path(const MapBlender& blender, const MapPath& previous_path,
                         const MapPath& path, const SynthOptions& options,
                         const PathEditOptions& edit_options, const Control& control) {
  edit_options.validate();
  options.validate();
  path.validate();
  SynthResult previous;
  try {
    previous_path.validate();
    previous = synthesize(blender, previous_path, options, control.part(0.0, 0.8));
  } catch (const ParameterError& e) {
    throw ParameterError(std::string("previous path: ") + e.what());
  }
  PathEditResult edit = edit_path(blender, previous, path, edit_options, control.part(0.8, 1.0));
  if (edit.first == 0 && edit.end == edit.result.motion.num_frames && edit.end > 0) {
    edit.result = synthesize(blender, path, options, control.part(0.8, 1.0));
    edit.whole = true;
  }
  return edit;
}

}  // namespace motionmap::synth
