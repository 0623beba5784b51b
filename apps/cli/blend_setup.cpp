#include "blend_setup.h"

#include <iostream>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/embed/gplvm.h"
#include "motionmap/features/joint_match.h"
#include "motionmap/pipeline/map_csv.h"

namespace motionmap::cli {

namespace {

// The options a saved map fixes (its clips, features, method, frames): usage errors with a map
// file, which already holds what they would choose.
constexpr const char* kFixedBySavedMap[] = {
    "files",        "--asf",    "--amc-fps",     "--method",     "--dims",     "-k",
    "--heat",       "--reg",    "--standardize", "--strict",     "--features", "--distance",
    "--exclude",    "--frames", "--stride",      "--keep-first", "--up",       "--recursive",
    "--keep-going", "--joints", "--exact",       "--landmarks"};

void check_one_skeleton(const std::vector<Clip>& clips, const std::string& where,
                        const std::string& who) {
  for (const Clip& clip : clips) {
    if (const std::string why = features::hierarchy_difference(clips.front(), clip); !why.empty())
      throw Error(where + clip.path + ": its joint hierarchy differs from " + clips.front().path +
                  "'s (" + why + "); " + who +
                  " blends clips of one skeleton (a --joints common map holds clips of several, "
                  "but cannot blend them)");
  }
}

void note_kriging(const BlendCliOptions& o, const synth::BlendOptions& blend, int samples) {
  if (blend.mode == synth::BlendMode::Kriging && samples > 2000 && !o.map.quiet) {
    std::cerr << "note: factoring the kriging system of " << samples
              << " samples (O(N³): tens of seconds at 10 000; --blend local takes a fraction of a "
                 "second)\n";
  }
}

// A gplvm map's GP: the map's rule of where it is valid in every mode, and its blends (the gp
// mode) unless --blend chose another.
void use_gplvm(const BlendCliOptions& o, std::shared_ptr<const embed::GplvmMap> gp,
               synth::BlendOptions& blend) {
  if (!gp) return;
  const CLI::Option* given = o.sub->get_option_no_throw("--blend");
  if (!given || given->count() == 0) blend.mode = synth::BlendMode::Gp;
  blend.gplvm = std::move(gp);
}

PreparedBlender prepare_saved(const BlendCliOptions& o, const std::string& who) {
  for (const char* name : kFixedBySavedMap) {
    const CLI::Option* option = o.sub->get_option_no_throw(name);
    if (option && option->count() > 0) {
      throw CLI::ValidationError(
          option->get_name(),
          "the saved map " + o.map_path + " fixes its clips, features, method and frames: " +
              (std::string(name) == "files" ? "give no FILE with --map " + o.map_path
                                            : "leave " + option->get_name() + " out"));
    }
  }
  mapfile::MapFile file = mapfile::read_map_file(o.map_path, {.model = false});
  if (!o.map.quiet) {
    for (const std::string& note : file.read_notes) std::cerr << "note: " << note << '\n';
  }
  synth::BlendOptions blend = blend_options(o, file.options.features.up);
  const int num_clips = static_cast<int>(file.clips.size());
  PreparedBlender p;
  p.saved = std::make_shared<const mapfile::SavedMap>(std::move(file));
  use_gplvm(o, p.saved->gplvm(), blend);
  p.samples = p.saved->samples();
  for (const mapfile::ClipRecord& record : p.saved->file().clips)
    p.clip_paths.push_back(record.path);
  if (blend.mode != synth::BlendMode::Kriging) {
    if (!p.saved->file().blend && !o.map.quiet) {
      std::cerr << "note: " << o.map_path
                << " does not record what blending needs of all its clips (saved by an older "
                   "MotionMap, with --stream, or a map of placed clips): each of its "
                << num_clips
                << " clips is read once first (about 0.1 s per 6 000 frames); `motionmap map "
                   "--save` without --stream records it\n";
    }
    try {
      p.blender = std::make_unique<synth::MapBlender>(
          mapfile::make_blender(p.saved, blend, progress_line(o.map, "blend")));
    } catch (const ParameterError& e) {
      // Clips of several skeletons (a --joints common map) cannot be blended together.
      if (std::string(e.what()).find("joint hierarchy differs") == std::string::npos) throw;
      throw Error(o.map_path + ": " + e.what() + " (" + who +
                  " blends clips of one skeleton; a --joints common map holds clips of several, "
                  "but cannot blend them)");
    }
    return p;
  }
  // Kriging blends every sample: every clip is loaded.
  const std::vector<Clip> clips = p.saved->load_all_clips();
  check_one_skeleton(clips, o.map_path + ": ", who);
  note_kriging(o, blend, p.samples.num_samples());
  p.blender = std::make_unique<synth::MapBlender>(clips, p.samples, p.saved->file().coordinates,
                                                  blend, progress_line(o.map, "blend"));
  return p;
}

}  // namespace

void add_blend_options(CLI::App* sub, BlendCliOptions& o, const std::string& map_help) {
  o.sub = sub;
  add_map_options(sub, o.map, MapOptionsFor::Synthesis);
  // With a saved map (--map lib.mmap.h5) the clips come from the map file.
  sub->get_option("files")->required(false);
  sub->add_option("--map", o.map_path, map_help)->check(CLI::ExistingFile);
  sub->add_option(
         "--blend", o.blend,
         "Weights of the samples around a map point: local (kriging on the K map-nearest "
         "samples, default), kriging (over all samples, ≤ 10 000), idw (inverse distance) or gp "
         "(a gplvm map's predictive mean, its default)")
      ->transform(CLI::CheckedTransformer(choices(synth::all_blend_modes(), synth::blend_mode_name),
                                          CLI::ignore_case));
  sub->add_option("--neighbors", o.neighbors,
                  "K: samples per local kriging system, or blended by idw (default 12)");
  sub->add_option("--reach", o.reach,
                  "A point farther from every sample than reach × the median step between "
                  "consecutive samples (and than 5 % of the map's size) is moved to the edge of "
                  "the data, with a note (default 3). On a gplvm map the GP decides instead: a "
                  "point whose predictive variance exceeds " +
                      format_number(embed::kGplvmValidFraction) + " of its prior is moved");
}

std::string outside_rule(const synth::MapBlender& blender) {
  if (blender.options().gplvm) {
    return "where the GP's predictive variance exceeds " +
           format_number(embed::kGplvmValidFraction) + " of its prior";
  }
  return "farther than the reach " + format_number(blender.reach_distance(), 4) +
         " from every sample";
}

synth::BlendOptions blend_options(const BlendCliOptions& o, Axis up) {
  synth::BlendOptions blend;
  blend.mode = o.blend;
  blend.neighbors = o.neighbors;
  blend.reach = o.reach;
  blend.up = up;
  return blend;
}

PreparedBlender prepare_blender(const BlendCliOptions& o, const std::string& who,
                                bool csv_allowed) {
  const bool saved = !o.map_path.empty() && mapfile::looks_like_map_file(o.map_path);
  if (saved) return prepare_saved(o, who);
  if (!o.map_path.empty() && !csv_allowed) {
    throw CLI::ValidationError("--map", o.map_path +
                                            " is not a saved map (`motionmap map --save "
                                            "lib.mmap.h5`); " +
                                            who +
                                            " places frames on the map, which a map CSV "
                                            "cannot do");
  }
  if (o.map.files.empty()) {
    throw CLI::ValidationError("files",
                               "give the clips (FILE…), or a saved map with --map lib.mmap.h5");
  }
  PreparedBlender p;
  auto clips = std::make_shared<std::vector<Clip>>(load_inputs(o.map));
  for (const Clip& clip : *clips) p.clip_paths.push_back(clip.path);
  // A new pose has one skeleton: say so before a map of several (--joints common) is computed.
  check_one_skeleton(*clips, "", who);
  p.options = clip_map_options(o.map, o.map.method, /*metrics=*/false);
  Eigen::MatrixXd coords;
  if (!o.map_path.empty()) {
    const pipeline::MapTable table = pipeline::read_map_csv(o.map_path);
    p.samples = features::select_samples(*clips, p.options.features);
    for (const auto& n : p.samples.notes) std::cerr << "note: " << n << '\n';
    table.check_matches(p.samples);
    coords = table.coords;
  } else {
    p.map = std::make_shared<pipeline::ClipMap>(pipeline::map_clips(
        *clips, p.options, progress_line(o.map, embed::method_name(o.map.method))));
    print_diagnostics(*p.map);
    p.samples = *p.map->features;
    coords = p.map->embedding.coordinates;
  }
  synth::BlendOptions blend = blend_options(o, p.options.features.up);
  if (p.map) use_gplvm(o, pipeline::map_gplvm(*p.map), blend);
  note_kriging(o, blend, p.samples.num_samples());
  p.blender = std::make_unique<synth::MapBlender>(*clips, p.samples, coords, blend,
                                                  progress_line(o.map, "blend"));
  p.clips = std::move(clips);
  return p;
}

}  // namespace motionmap::cli
