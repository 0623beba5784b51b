// `motionmap pose FILE… --at X,Y -o pose.bvh` and `motionmap synth FILE… --path path.csv -o
// new.bvh`: a pose blended from the samples around a map point, and a new motion along a path on
// the map (the library's synth::MapBlender and synth::synthesize; docs/synthesis.md has the maths).
// With `--map lib.mmap.h5` (a saved map, `motionmap map --save`) no FILE is given: the map file
// names its clips, which are loaded and checked against their recorded SHA-256.
#include <charconv>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>

#include "blend_setup.h"
#include "commands.h"
#include "map_options.h"
#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/features/joint_match.h"
#include "motionmap/io/bvh.h"
#include "motionmap/mapfile/saved_map.h"
#include "motionmap/pipeline/map_csv.h"
#include "motionmap/synth/path_edit.h"
#include "motionmap/synth/synthesize.h"

namespace motionmap::cli {

namespace {

struct BlendCommand {
  BlendCliOptions o;
  std::string output;
  // pose
  std::string at;
  // synth
  std::string path;
  std::string edit_of;
  double speed = 0.0;
  double fps = 0.0;
  double smooth = synth::kDefaultSmoothSeconds;
  bool no_clean_feet = false;
};

void add_options(CLI::App* sub, BlendCommand& cmd) {
  add_blend_options(
      sub, cmd.o,
      "A saved map (lib.mmap.h5 from `motionmap map --save`): no FILE, its clips are loaded "
      "from the paths it records and checked against their SHA-256; or a map CSV from "
      "`motionmap map` on the same files and options, instead of recomputing it (checked to "
      "belong to the clips: same samples; --method is then unused)");
  sub->add_option("-o,--output", cmd.output,
                  "BVH file to write (the source skeleton and channel order)")
      ->required();
}

Eigen::Vector2d parse_point(const std::string& text) {
  const auto p = parse_numbers<2>(text);
  if (!p)
    throw ParameterError("--at: '" + text +
                         "' is not a map point X,Y of two finite numbers (e.g. --at=-0.5,1.2)");
  return *p;
}

std::string point_text(const Eigen::Vector2d& p) {
  return "(" + format_number(p.x(), 4) + ", " + format_number(p.y(), 4) + ")";
}

void write_motion(const synth::MapBlender& blender, const Motion& motion, const std::string& path) {
  io::write_bvh(io::from_motion(blender.skeleton(), motion), path);
}

}  // namespace

void setup_pose(CLI::App& app) {
  auto cmd = std::make_shared<BlendCommand>();
  auto* sub = app.add_subcommand(
      "pose",
      "Blend a new pose from the samples around a point of the clips' map and write it as a\n"
      "one-frame BVH, standing at the origin facing the heading-0 direction (+Z for Y-up files).\n"
      "The map: computed from FILE…, read with --map map.csv, or a saved map --map lib.mmap.h5.");
  add_options(sub, *cmd);
  sub->add_option("--at", cmd->at, "The map point X,Y (write --at=X,Y when X is negative)")
      ->required();
  sub->callback([cmd] {
    const Eigen::Vector2d p = parse_point(cmd->at);
    const PreparedBlender prepared = prepare_blender(cmd->o, "pose");
    const synth::MapBlender& blender = *prepared.blender;
    const std::vector<std::string>& clip_paths = prepared.clip_paths;
    const features::FeatureSet& samples = prepared.samples;
    const synth::MapWeights weights = blender.locate(p);
    const synth::PointValidity& v = weights.validity;
    if (v.clamped) {
      std::cerr << "note: " << point_text(p) << " is " << format_number(v.distance, 4)
                << " map units from the nearest sample, outside the data (" << outside_rule(blender)
                << "): the pose is taken at " << point_text(v.point)
                << ", the nearest edge of the data\n";
    }
    write_motion(blender, blender.pose(weights), cmd->output);
    const int nearest = v.nearest_sample;
    std::cerr << "wrote " << cmd->output << ": 1 frame blended from " << weights.samples.size()
              << " samples (" << synth::blend_mode_name(blender.options().mode)
              << "); nearest sample: " << clip_paths[samples.clip_of[nearest]] << " frame "
              << samples.frame_of[nearest] << " at " << format_number(v.distance, 4) << "\n";
  });
}

void setup_synth(CLI::App& app) {
  auto cmd = std::make_shared<BlendCommand>();
  auto* sub = app.add_subcommand(
      "synth",
      "Synthesize a new motion along a path on the clips' map and write it as BVH: each frame is\n"
      "the blend at the path's point; root motion is integrated from the samples' own velocities;\n"
      "then each foot is held still through its contacts with the floor (--no-clean-feet: not).\n"
      "The path CSV holds t,x,y rows (seconds) or x,y rows drawn at --speed; the frames between\n"
      "two of its points on a clip's curve, at about that clip's pace, follow the curve (local).\n"
      "--edit-of PREVIOUS.csv: the path is an edit of PREVIOUS's (a control point moved); only "
      "the\n"
      "frames the edit changes are re-made, the rest is the take of PREVIOUS (same options).\n"
      "The map: computed from FILE…, read with --map map.csv, or a saved map --map lib.mmap.h5.");
  add_options(sub, *cmd);
  sub->add_option("--path", cmd->path,
                  "Path CSV: t,x,y or x,y per line (optional header, # comments)")
      ->required()
      ->check(CLI::ExistingFile);
  sub->add_option("--edit-of", cmd->edit_of,
                  "The path of a previous take (made by synth with the same map and options): "
                  "only the frames the edit of the path changes are re-made; every other frame is "
                  "that take's, bit for bit (docs/synthesis.md, \"Editing a path\")")
      ->check(CLI::ExistingFile);
  sub->add_option(
      "--speed", cmd->speed,
      "Map units per second for a path without times (default: the clip's median map speed)");
  sub->add_option("--fps", cmd->fps, "Frame rate of the new motion (default: the source clip's)");
  sub->add_option(
      "--smooth", cmd->smooth,
      "Gaussian smoothing of the blend weights over time, σ in seconds (default 0.05; 0: "
      "none), each neighbouring frame's weights moved in their clips by its distance in time "
      "first: it softens a path's jitter and jumps between clips (a path between two runs "
      "steps instead of gliding), and a path retracing a clip's trajectory at its timing "
      "still reproduces the clip");
  sub->add_flag("--no-clean-feet", cmd->no_clean_feet,
                "Keep the feet as blended: by default the root moves with the planted feet and "
                "each foot is held still through its contacts with the floor, the legs bent to "
                "reach (docs/synthesis.md, \"Clean feet\"); a skeleton without feet is left as "
                "blended, with a note");
  sub->callback([cmd] {
    const synth::MapPath path = synth::read_path_csv(cmd->path);
    synth::SynthOptions options;
    options.speed = cmd->speed;
    options.fps = cmd->fps;
    options.smooth = cmd->smooth;
    options.clean_feet = !cmd->no_clean_feet;
    options.validate();
    const PreparedBlender prepared = prepare_blender(cmd->o, "synth");
    const synth::MapBlender& blender = *prepared.blender;
    const Control line = progress_line(cmd->o.map, "synth");
    const Control blending = line.reports() ? line.stage("blending frames", 0, 1) : line;
    std::optional<synth::PathEditResult> edit;
    if (!cmd->edit_of.empty()) {
      const synth::MapPath previous = synth::read_path_csv(cmd->edit_of);
      try {
        edit = synth::edit_path(blender, previous, path, options, {}, blending);
      } catch (const ParameterError& e) {
        const std::string what = e.what();
        if (what.rfind("previous path: ", 0) != 0) throw;
        throw ParameterError(cmd->edit_of + ": " + what.substr(15));
      }
    }
    const synth::SynthResult result =
        edit ? std::move(edit->result) : synth::synthesize(blender, path, options, blending);
    if (result.clamped_frames > 0) {
      std::cerr << "note: " << result.clamped_frames << " of " << result.motion.num_frames
                << " frames lie outside the data (" << outside_rule(blender)
                << "): " << synth::outside_frames_note(result) << '\n';
    }
    if (!cmd->o.map.quiet) {
      for (const std::string& note : result.notes) std::cerr << "note: " << note << '\n';
    }
    write_motion(blender, result.motion, cmd->output);
    std::cerr << "wrote " << cmd->output << ": " << result.motion.num_frames << " frames at "
              << format_number(result.motion.fps(), 4) << " fps ("
              << format_number(result.motion.duration(), 4) << " s)";
    if (result.feet_cleaned) {
      std::size_t held = 0;
      for (const FootContacts& fc : result.contacts) held += fc.intervals.size();
      std::cerr << "; feet held through " << held << " contacts";
    }
    if (edit && edit->whole) {
      std::cerr << "; the edit of " << cmd->edit_of << " reaches every frame: re-made whole";
    } else if (edit && edit->first == edit->end) {
      std::cerr << "; the same path as " << cmd->edit_of << ": nothing re-made";
    } else if (edit) {
      std::cerr << "; re-made frames " << edit->first << "-" << edit->end - 1
                << ", the rest as the take of " << cmd->edit_of;
    }
    std::cerr << "\n";
  });
}

}  // namespace motionmap::cli
