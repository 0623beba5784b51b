#pragma once
// Local path edits: a synthesized motion re-made only where an edit of its path changes it.
//
//   auto before = motionmap::synth::synthesize(blender, path);
//   path.points[7] += Eigen::Vector2d(0.3, -0.1);            // a control point moved
//   auto edit = motionmap::synth::edit_path(blender, before, path);
//   // edit.result: the motion along the edited path; frames outside [edit.first, edit.end) are
//   // before.motion's, bit for bit
//
// Method (docs/synthesis.md, "Editing a path"):
//  1. The edited path is resampled at the previous motion's frames (MapBlender::path_points: a
//     moved point moves the frames of the strokes on either side of it); the frames whose path
//     point differs from the one the previous motion followed (PointValidity::query, bit for bit)
//     are the changed frames, and their neighbours (a frame's weights read the path's velocity
//     there: MapBlender::locate_path), and every run routed (outside the data or far inside it)
//     of the previous path or the new one that a changed frame reaches (detail/outside_route.h: a
//     run's route reads its points and the blends beside it), widened by the weight smoothing's
//     half-width (3σ): the blend window [blend_first, blend_end). Its frames are blended anew
//     (weights smoothed over the new path); of the frames located for it, those whose clip-time
//     fits read no changed point take them from previous.fits (PathFits).
//  2. Root: the new velocities are integrated from the previous root's floor position and
//     heading at blend_first; the position and heading mismatch at blend_end (where the previous
//     motion goes on) is spread over the window where the root moves (turns) — in proportion to
//     its steps, plus a tenth of its mean step each frame — so the frame after it continues
//     exactly as before and the rest lines up in world space. A window reaching the motion's end
//     (a path made longer or shorter) ends where the new path ends.
//  3. Feet (when the previous motion's were cleaned): the window widened by a margin on both
//     sides, [first, end), is cleaned by clean_feet() — the frames of `context` seconds more on
//     each side blended again (unchanged) to find the contacts, its two border frames given as
//     the previous motion's and fixed (a contact through them stays where it was held) — and
//     within the margins the result fades from the previous motion's frames to the new ones
//     (per joint slerp, smoothstep), so nothing pops at the borders.
// So frames before `first` and from `end` on are the previous result's, bit for bit. The result's
// validity, contact shares and root states are the new ones in the blend window; its contacts are
// the previous ones outside [first, end) and the new clean-up's inside; feet_changed likewise,
// and feet_frames_changed is recounted from it over the whole motion.
#include <vector>

#include "motionmap/core/control.h"
#include "motionmap/synth/blender.h"
#include "motionmap/synth/path.h"
#include "motionmap/synth/synthesize.h"

namespace motionmap::synth {

struct PathEditOptions {
  /// Frames on each side of the blend window over which the new clean-up fades into the previous
  /// motion, in seconds, in [0, 2]; at least the clean-up's fade (0.15 s) plus a frame is used.
  double margin_seconds = 0.3;
  /// Frames beyond the margins blended again to find the contacts, in seconds, in [0, 5].
  double context_seconds = 0.5;

  /// @throws ParameterError naming the field, its value and its range.
  void validate() const;
};

struct PathEditResult {
  SynthResult result;  ///< the motion along the edited path (as synthesize() returns it)
  /// The frames blended anew: [blend_first, blend_end) (empty when the path did not change).
  int blend_first = 0;
  int blend_end = 0;
  /// The frames that may differ from the previous motion: [first, end) (the blend window and the
  /// clean-up's margins). Every other frame is the previous motion's, bit for bit.
  int first = 0;
  int end = 0;
  /// Set by the overload from a previous path when the edit reached every frame: the motion was
  /// then synthesized whole (synthesize()'s along the edited path).
  bool whole = false;
};

/// The motion along `path`, re-made from `previous` (synthesize()'s result on the same blender,
/// along another path) only where the path changed (see the top of the file), with
/// previous.options.
/// @throws ParameterError for bad options, an invalid path (as synthesize()), a previous result
///         without its root states (not made by synthesize()) or of another skeleton; Cancelled if
///         `control` says so.
PathEditResult edit_path(const MapBlender& blender, const SynthResult& previous,
                         const MapPath& path, const PathEditOptions& options = {},
                         const Control& control = {});

/// The same edit when only the previous take's path and options are known (the CLI's `synth
/// --edit-of`, Python's motionmap.edit_path): the previous motion is synthesized again along
/// `previous_path` with `options` (synthesize() is deterministic, so it is that take, bit for
/// bit), then edited as above. When the edit reaches every frame ([first, end) is the whole
/// motion) there is nothing to keep: the result is synthesize(blender, path, options) and `whole`
/// is set.
/// @throws as synthesize() for either path (ParameterError names which: "previous path: …" for
///         the previous one) and as above.
PathEditResult edit_path(const MapBlender& blender, const MapPath& previous_path,
                         const MapPath& path, const SynthOptions& options,
                         const PathEditOptions& edit_options = {}, const Control& control = {});

}  // namespace motionmap::synth
