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

#include "commands.h"
#include "map_options.h"
#include "motionmap/core/error.h"
#include "motionmap/features/joint_match.h"
#include "motionmap/io/bvh.h"
#include "motionmap/mapfile/saved_map.h"
#include "motionmap/pipeline/map_csv.h"
#include "motionmap/synth/synthesize.h"

namespace motionmap::cli {

namespace {

struct BlendCommand {
  CLI::App* sub = nullptr;
  MapCliOptions map;
  std::string map_csv;
  synth::BlendMode blend = synth::BlendMode::Local;
  int neighbors = 12;
  double reach = 3.0;
  std::string output;
  // pose
  std::string at;
  // synth
  std::string path;
  double speed = 0.0;
  double fps = 0.0;
  double smooth = 0.0;
  bool no_clean_feet = false;
};

// The options a saved map fixes (its clips, features, method, frames): usage errors with a map
// file, which already holds what they would choose.
constexpr const char* kFixedBySavedMap[] = {
    "files",        "--asf",    "--amc-fps",     "--method",     "--dims",     "-k",
    "--heat",       "--reg",    "--standardize", "--strict",     "--features", "--distance",
    "--exclude",    "--frames", "--stride",      "--keep-first", "--up",       "--recursive",
    "--keep-going", "--joints", "--exact",       "--landmarks"};

/// Whether `path` is a saved map (an HDF5 file) rather than a map CSV.
bool is_hdf5(const std::string& path) {
  return mapfile::looks_like_map_file(path);
}

void add_blend_options(CLI::App* sub, BlendCommand& cmd) {
  cmd.sub = sub;
  add_map_options(sub, cmd.map, MapOptionsFor::Synthesis);
  // With a saved map (--map lib.mmap.h5) the clips come from the map file.
  sub->get_option("files")->required(false);
  sub->add_option(
         "--map", cmd.map_csv,
         "A saved map (lib.mmap.h5 from `motionmap map --save`): no FILE, its clips are loaded "
         "from the paths it records and checked against their SHA-256; or a map CSV from "
         "`motionmap map` on the same files and options, instead of recomputing it (checked to "
         "belong to the clips: same samples; --method is then unused)")
      ->check(CLI::ExistingFile);
  sub->add_option(
         "--blend", cmd.blend,
         "Weights of the samples around a map point: local (kriging on the K map-nearest "
         "samples, default), kriging (over all samples, ≤ 10 000) or idw (inverse distance)")
      ->transform(CLI::CheckedTransformer(choices(synth::all_blend_modes(), synth::blend_mode_name),
                                          CLI::ignore_case));
  sub->add_option("--neighbors", cmd.neighbors,
                  "K: samples per local kriging system, or blended by idw (default 12)");
  sub->add_option(
      "--reach", cmd.reach,
      "A point farther from every sample than reach × the median step between consecutive "
      "samples is moved to the edge of the data, with a note (default 3)");
  sub->add_option("-o,--output", cmd.output,
                  "BVH file to write (the source skeleton and channel order)")
      ->required();
}

synth::BlendOptions blend_options(const BlendCommand& cmd, Axis up) {
  synth::BlendOptions blend;
  blend.mode = cmd.blend;
  blend.neighbors = cmd.neighbors;
  blend.reach = cmd.reach;
  blend.up = up;
  return blend;
}

/// A blender over a saved map: the blender `prepare` makes for the same clips mapped directly
/// with the map's options, blending bit for bit the same. The local and idw modes read the clips
/// on demand (mapfile::make_blender: only those of the samples a blend uses, each checked against
/// its recorded SHA-256); kriging blends every sample and loads every clip. `clip_paths` receives
/// the clips' paths as the map records them.
synth::MapBlender prepare_saved(const BlendCommand& cmd, std::vector<std::string>& clip_paths,
                                features::FeatureSet& samples) {
  for (const char* name : kFixedBySavedMap) {
    const CLI::Option* option = cmd.sub->get_option_no_throw(name);
    if (option && option->count() > 0) {
      throw CLI::ValidationError(
          option->get_name(),
          "the saved map " + cmd.map_csv + " fixes its clips, features, method and frames: " +
              (std::string(name) == "files" ? "give no FILE with --map " + cmd.map_csv
                                            : "leave " + option->get_name() + " out"));
    }
  }
  mapfile::MapFile file = mapfile::read_map_file(cmd.map_csv, {.model = false});
  if (!cmd.map.quiet) {
    for (const std::string& note : file.read_notes) std::cerr << "note: " << note << '\n';
  }
  for (const mapfile::ClipRecord& record : file.clips) clip_paths.push_back(record.path);
  const synth::BlendOptions blend = blend_options(cmd, file.options.features.up);
  // The blender keeps the states of the samples it blended, not their clips: a few clips cached.
  const int num_clips = static_cast<int>(file.clips.size());
  const auto saved = std::make_shared<const mapfile::SavedMap>(std::move(file));
  samples = saved->samples();
  if (blend.mode != synth::BlendMode::Kriging) {
    if (!saved->file().blend && !cmd.map.quiet) {
      std::cerr << "note: " << cmd.map_csv
                << " does not record what blending needs of all its clips (saved by an older "
                   "MotionMap, with --stream, or a map of placed clips): each of its "
                << num_clips
                << " clips is read once first (about 0.1 s per 6 000 frames); `motionmap map "
                   "--save` without --stream records it\n";
    }
    try {
      return mapfile::make_blender(saved, blend, progress_line(cmd.map, "blend"));
    } catch (const ParameterError& e) {
      // Clips of several skeletons (a --joints common map) cannot be blended together.
      if (std::string(e.what()).find("joint hierarchy differs") == std::string::npos) throw;
      throw Error(cmd.map_csv + ": " + e.what() +
                  " (pose and synth blend clips of one skeleton; a --joints common map holds "
                  "clips of several, but cannot blend them)");
    }
  }
  // Kriging blends every sample: every clip is loaded.
  const std::vector<Clip> clips = saved->load_all_clips();
  for (const Clip& clip : clips) {
    if (const std::string why = features::hierarchy_difference(clips.front(), clip); !why.empty())
      throw Error(cmd.map_csv + ": " + clip.path + ": its joint hierarchy differs from " +
                  clips.front().path + "'s (" + why +
                  "); pose and synth blend clips of one skeleton (a --joints common map holds "
                  "clips of several, but cannot blend them)");
  }
  if (samples.num_samples() > 2000 && !cmd.map.quiet) {
    std::cerr << "note: factoring the kriging system of " << samples.num_samples()
              << " samples (O(N³): tens of seconds at 10 000; --blend local takes a fraction of a "
                 "second)\n";
  }
  return synth::MapBlender(clips, samples, saved->file().coordinates, blend,
                           progress_line(cmd.map, "blend"));
}

/// The clips, their map (recomputed, or read with --map and checked) and a blender over it.
/// `clip_paths` receives the clips' paths.
synth::MapBlender prepare(const BlendCommand& cmd, std::vector<std::string>& clip_paths,
                          features::FeatureSet& samples) {
  if (!cmd.map_csv.empty() && is_hdf5(cmd.map_csv)) return prepare_saved(cmd, clip_paths, samples);
  if (cmd.map.files.empty()) {
    throw CLI::ValidationError("files",
                               "give the clips (FILE…), or a saved map with --map lib.mmap.h5");
  }
  const std::vector<Clip> clips = load_inputs(cmd.map);
  for (const Clip& clip : clips) clip_paths.push_back(clip.path);
  // A new pose has one skeleton: say so before a map of several (--joints common) is computed.
  for (const Clip& clip : clips) {
    if (const std::string why = features::hierarchy_difference(clips.front(), clip); !why.empty())
      throw Error(clip.path + ": its joint hierarchy differs from " + clips.front().path + "'s (" +
                  why +
                  "); pose and synth blend clips of one skeleton (--joints common maps "
                  "clips of several, but cannot blend them)");
  }
  const pipeline::ClipMapOptions options =
      clip_map_options(cmd.map, cmd.map.method, /*metrics=*/false);
  Eigen::MatrixXd coords;
  if (!cmd.map_csv.empty()) {
    const pipeline::MapTable table = pipeline::read_map_csv(cmd.map_csv);
    samples = features::select_samples(clips, options.features);
    for (const auto& n : samples.notes) std::cerr << "note: " << n << '\n';
    table.check_matches(samples);
    coords = table.coords;
  } else {
    pipeline::ClipMap map = pipeline::map_clips(
        clips, options, progress_line(cmd.map, embed::method_name(cmd.map.method)));
    print_diagnostics(map);
    samples = *map.features;
    coords = std::move(map.embedding.coordinates);
  }
  const synth::BlendOptions blend = blend_options(cmd, options.features.up);
  if (blend.mode == synth::BlendMode::Kriging && samples.num_samples() > 2000 && !cmd.map.quiet) {
    std::cerr << "note: factoring the kriging system of " << samples.num_samples()
              << " samples (O(N³): tens of seconds at 10 000; --blend local takes a fraction of a "
                 "second)\n";
  }
  return synth::MapBlender(clips, samples, coords, blend, progress_line(cmd.map, "blend"));
}

Eigen::Vector2d parse_point(const std::string& text) {
  const auto comma = text.find(',');
  Eigen::Vector2d p;
  bool ok = comma != std::string::npos;
  for (int k = 0; ok && k < 2; ++k) {
    const std::string_view part =
        k == 0 ? std::string_view(text).substr(0, comma) : std::string_view(text).substr(comma + 1);
    const auto [ptr, ec] = std::from_chars(part.data(), part.data() + part.size(), p[k]);
    ok = !part.empty() && ec == std::errc() && ptr == part.data() + part.size() &&
         std::isfinite(p[k]);
  }
  if (!ok)
    throw ParameterError("--at: '" + text +
                         "' is not a map point X,Y of two finite numbers (e.g. --at=-0.5,1.2)");
  return p;
}

/// A measured value for a message: 4 significant digits.
std::string approx(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

std::string point_text(const Eigen::Vector2d& p) {
  return "(" + approx(p.x()) + ", " + approx(p.y()) + ")";
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
  add_blend_options(sub, *cmd);
  sub->add_option("--at", cmd->at, "The map point X,Y (write --at=X,Y when X is negative)")
      ->required();
  sub->callback([cmd] {
    const Eigen::Vector2d p = parse_point(cmd->at);
    std::vector<std::string> clip_paths;
    features::FeatureSet samples;
    const synth::MapBlender blender = prepare(*cmd, clip_paths, samples);
    const synth::MapWeights weights = blender.locate(p);
    const synth::PointValidity& v = weights.validity;
    if (v.clamped) {
      std::cerr << "note: " << point_text(p) << " is " << approx(v.distance)
                << " map units from the nearest sample, beyond the reach "
                << approx(blender.reach_distance()) << ": the pose is taken at "
                << point_text(v.point) << ", the nearest edge of the data\n";
    }
    write_motion(blender, blender.pose(weights), cmd->output);
    const int nearest = v.nearest_sample;
    std::cerr << "wrote " << cmd->output << ": 1 frame blended from " << weights.samples.size()
              << " samples (" << synth::blend_mode_name(blender.options().mode)
              << "); nearest sample: " << clip_paths[samples.clip_of[nearest]] << " frame "
              << samples.frame_of[nearest] << " at " << approx(v.distance) << "\n";
  });
}

void setup_synth(CLI::App& app) {
  auto cmd = std::make_shared<BlendCommand>();
  auto* sub = app.add_subcommand(
      "synth",
      "Synthesize a new motion along a path on the clips' map and write it as BVH: each frame is\n"
      "the blend at the path's point; root motion is integrated from the samples' own velocities;\n"
      "then each foot is held still through its contacts with the floor (--no-clean-feet: not).\n"
      "The path CSV holds t,x,y rows (seconds) or x,y rows drawn at --speed.\n"
      "The map: computed from FILE…, read with --map map.csv, or a saved map --map lib.mmap.h5.");
  add_blend_options(sub, *cmd);
  sub->add_option("--path", cmd->path,
                  "Path CSV: t,x,y or x,y per line (optional header, # comments)")
      ->required()
      ->check(CLI::ExistingFile);
  sub->add_option(
      "--speed", cmd->speed,
      "Map units per second for a path without times (default: the clip's median map speed)");
  sub->add_option("--fps", cmd->fps, "Frame rate of the new motion (default: the source clip's)");
  sub->add_option(
      "--smooth", cmd->smooth,
      "Gaussian smoothing of the blend weights over time, σ in seconds (default 0: a path "
      "retracing the clip's trajectory at its timing reproduces the clip)");
  sub->add_flag("--no-clean-feet", cmd->no_clean_feet,
                "Keep the feet as blended: by default each foot is held still through its "
                "contacts with the floor, the legs bent to reach (docs/synthesis.md, \"Clean "
                "feet\"); a skeleton without feet is left as blended, with a note");
  sub->callback([cmd] {
    const synth::MapPath path = synth::read_path_csv(cmd->path);
    synth::SynthOptions options;
    options.speed = cmd->speed;
    options.fps = cmd->fps;
    options.smooth = cmd->smooth;
    options.clean_feet = !cmd->no_clean_feet;
    options.validate();
    std::vector<std::string> clip_paths;
    features::FeatureSet samples;
    const synth::MapBlender blender = prepare(*cmd, clip_paths, samples);
    const Control line = progress_line(cmd->map, "synth");
    const synth::SynthResult result = synth::synthesize(
        blender, path, options, line.reports() ? line.stage("blending frames", 0, 1) : line);
    if (result.clamped_frames > 0) {
      std::cerr << "note: " << result.clamped_frames << " of " << result.motion.num_frames
                << " frames lie outside the data (beyond the reach "
                << approx(blender.reach_distance())
                << " from every sample) and were blended at the nearest edge of the data\n";
    }
    if (!cmd->map.quiet) {
      for (const std::string& note : result.notes) std::cerr << "note: " << note << '\n';
    }
    write_motion(blender, result.motion, cmd->output);
    std::cerr << "wrote " << cmd->output << ": " << result.motion.num_frames << " frames at "
              << approx(result.motion.fps()) << " fps (" << approx(result.motion.duration())
              << " s)";
    if (result.feet_cleaned) {
      std::size_t held = 0;
      for (const FootContacts& fc : result.contacts) held += fc.intervals.size();
      std::cerr << "; feet held through " << held << " contacts";
    }
    std::cerr << "\n";
  });
}

}  // namespace motionmap::cli
