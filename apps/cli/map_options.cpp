#include "map_options.h"

#include <unistd.h>

#include <charconv>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>

#include "motionmap/core/error.h"
#include "motionmap/core/files.h"
#include "motionmap/core/format.h"
#include "motionmap/core/memory.h"
#include "motionmap/io/clip_inputs.h"

namespace motionmap::cli {

namespace {

// An input must exist: a file or folder, or after '@' a list file. Missing ones are usage errors
// (exit 2), as CLI::ExistingFile made them; what a list names is checked when it is read.
CLI::Validator clip_input_validator() {
  return CLI::Validator(
      [](std::string& input) -> std::string {
        std::error_code ec;
        if (!input.empty() && input.front() == '@') {
          const std::string list = input.substr(1);
          return std::filesystem::is_regular_file(list, ec) ? std::string()
                                                            : "List file does not exist: " + list;
        }
        return std::filesystem::exists(input, ec) ? std::string()
                                                  : "File or folder does not exist: " + input;
      },
      "PATH|@LIST");
}

// "loading 12/40 clips (183 000 frames)" on stderr while several clips load, for people watching
// a terminal; the last line ("loaded 40 clips …") stays.
Control loading_line(const MapCliOptions& opt, std::size_t clips) {
  if (opt.quiet || clips < 2 || !isatty(STDERR_FILENO)) return {};
  return Control([](double fraction, std::string_view stage) {
    std::fprintf(stderr, "\r%-60.*s", static_cast<int>(stage.size()), stage.data());
    if (fraction >= 1.0) std::fprintf(stderr, "\n");
    std::fflush(stderr);
  });
}

}  // namespace

void add_map_options(CLI::App* sub, MapCliOptions& opt, MapOptionsFor use) {
  sub->add_option("files", opt.files,
                  "Clips: .bvh files, .amc files (with their .asf), folders (their .bvh and .amc "
                  "files, sorted by path; subfolders only with --recursive) and @LIST files (one "
                  "path a line, relative to the list's folder; blank lines and # comments "
                  "ignored). Several clips make one map: of one skeleton, or of several with "
                  "--joints common")
      ->required()
      ->check(clip_input_validator());
  sub->add_option("--asf", opt.asf, "ASF skeleton for .amc inputs (default: the .asf beside them)")
      ->check(CLI::ExistingFile);
  // pose/synth: --fps is the new motion's frame rate there.
  sub->add_option(use == MapOptionsFor::Synthesis ? "--amc-fps" : "--fps", opt.fps,
                  "Frame rate of .amc inputs (default 120)")
      ->check(CLI::PositiveNumber);
  if (use != MapOptionsFor::Figure) {
    sub->add_option("-m,--method", opt.method,
                    "pca, svd, mds, isomap, le, lle, umap or gplvm (default isomap)")
        ->transform(CLI::CheckedTransformer(choices(embed::all_methods(), embed::method_name),
                                            CLI::ignore_case));
  }
  sub->add_option("--dims", opt.dims, "Map dimensions, 2 or 3 (default 2)")
      ->check(CLI::IsMember({2, 3}));
  sub->add_option(
      use == MapOptionsFor::Synthesis ? "-k" : "-k,--neighbors", opt.k,
      "Neighbours per frame in the map's graph for isomap, le, lle (default 20); umap's "
      "n_neighbors, the frame itself counted (default 15)");
  sub->add_option("--min-dist", opt.min_dist,
                  "umap: smallest distance between frames on the map, in [0, 1] (default 0.1)");
  sub->add_option("--epochs", opt.epochs,
                  "umap: layout epochs (default 0: 500 up to 10 000 frames, 200 above)");
  sub->add_option("--max-iter", opt.max_iterations,
                  "gplvm: L-BFGS iterations at most (default 300)");
  sub->add_option("--inducing", opt.inducing,
                  "gplvm: inducing points of the sparse model, 1 to the number of frames "
                  "(default 0: the full model up to 1000 frames, 100 inducing points above)");
  sub->add_option("--lengthscale", opt.lengthscale,
                  "gplvm: hold the kernel's lengthscale at this value, in units of the latent "
                  "points' prior N(0, I), so that the fit can converge (try 1 with --max-iter "
                  "20000); 0 (default) fits it with the latent points, which has no optimum: the "
                  "fit ends at --max-iter, its short lengthscale keeping the GP's sure region "
                  "close to the data (docs/methods/gplvm.md)");
  sub->add_option("--seed", opt.seed,
                  "umap: seed of the layout's random numbers; one seed, one map, whatever the "
                  "thread count (default 0)");
  sub->add_option("--heat", opt.heat,
                  "Laplacian eigenmap heat-kernel width: 'auto' (median squared k-NN distance, "
                  "printed) or a number; ≤ 0 makes every weight 1 (default auto)");
  sub->add_option("--reg", opt.reg, "LLE regularisation (default 1e-3)");
  sub->add_flag("--standardize", opt.standardize, "PCA on standardised columns (correlation PCA)");
  sub->add_flag("--strict", opt.strict,
                "Fail on a disconnected neighbour graph instead of joining its components");
  sub->add_option(
         "--features", opt.features,
         "Data matrix X for pca, svd and lle: quat (joint rotation quaternions, default) or "
         "positions (heading-local joint positions)")
      ->transform(CLI::CheckedTransformer(
          choices(features::all_feature_kinds(), features::feature_kind_name), CLI::ignore_case));
  sub->add_option(
         "--distance", opt.distance,
         "Pose distance D for mds, isomap, le, umap and lle's neighbours: pointcloud (default), "
         "geodesic (joint rotation angles) or features (Euclidean on X)")
      ->transform(CLI::CheckedTransformer(
          choices(features::all_distance_kinds(), features::distance_kind_name), CLI::ignore_case));
  sub->add_option(
      "--exclude", opt.exclude,
      "Regular expression: joints whose name matches are left out, e.g. '.*(Thumb|Finger).*'");
  sub->add_option("--frames", opt.frames,
                  "Frame range A:B of each file (B exclusive; either may be empty)");
  sub->add_option("--stride", opt.stride, "Use every S-th frame (default 1)")
      ->check(CLI::PositiveNumber);
  sub->add_flag("--keep-first", opt.keep_first,
                "Keep a leading bind/T-pose frame (left out by default, with a note)");
  sub->add_option("--up", opt.up, "Up axis of the files: y (default) or z")
      ->check(CLI::IsMember({"y", "z", "Y", "Z"}));
  sub->add_flag("--recursive", opt.recursive,
                "Folders given (on the command line or in @lists) contribute the clips of their "
                "subfolders too; without it, only the files directly in them");
  sub->add_flag(
      "--keep-going", opt.keep_going,
      "Skip a clip that fails to load (its error is printed) and map the others; "
      "without it the first failure is an error. If no clip loads, that is an error either way");
  sub->add_option("--joints", opt.joints,
                  "all: every joint, the clips must share one joint hierarchy (default); common: "
                  "the joints whose names all clips have, so clips of different skeletons share "
                  "a map (each clip's own skeleton and forward kinematics; a note lists what was "
                  "kept and dropped)")
      ->transform(CLI::CheckedTransformer(
          choices(features::all_joint_selections(), features::joint_selection_name),
          CLI::ignore_case));
  auto* exact = sub->add_flag(
      "--exact", opt.exact,
      "Compute the exact (dense) map from the #frames² distance matrix however many frames there "
      "are (8·#frames² bytes; by default maps are dense up to " +
          std::to_string(pipeline::kDenseFrameLimit) + " frames)");
  sub->add_option("--landmarks", opt.landmarks,
                  "Take the scalable path however few frames there are — landmark MDS and "
                  "Isomap with L landmarks (0: " +
                      std::to_string(embed::kDefaultLandmarks) +
                      "), le and lle on a sparse k-NN graph — the default above " +
                      std::to_string(pipeline::kDenseFrameLimit) + " frames")
      ->check(CLI::NonNegativeNumber)
      ->excludes(exact);
  if (use == MapOptionsFor::Map) {
    sub->add_flag(
        "--stream", opt.stream,
        "pca and svd: read the clips from their files a few at a time (one per thread), twice "
        "(features and XᵀX, then the projection), holding neither the clips nor X: memory for "
        "the #features² matrix, a clip per thread and the coordinates. The map equals the "
        "in-memory one to rounding. "
        "Automatic when the clips and X would not fit in the available memory (estimated from "
        "the files' sizes); not with --joints common or --metrics");
  }
  if (use != MapOptionsFor::Synthesis) add_label_options(sub, opt);
  sub->add_flag("--verbose", opt.verbose,
                "Print each stage's time and the peak memory so far to standard error");
  sub->add_flag("-q,--quiet", opt.quiet, "No progress line");
}

std::vector<std::string> input_paths(const MapCliOptions& opt) {
  io::ExpandOptions expand;
  expand.recursive = opt.recursive;
  return io::expand_clip_inputs(opt.files, expand);
}

std::vector<Clip> load_inputs(const MapCliOptions& opt) {
  return load_inputs(opt, input_paths(opt));
}

io::LoadClipsOptions load_options(const MapCliOptions& opt, bool sha256) {
  io::LoadClipsOptions load;
  load.load.asf_path = opt.asf;
  load.load.fps = opt.fps;
  load.load.sha256 = sha256;
  load.keep_going = opt.keep_going;
  return load;
}

void print_loading(const std::vector<Clip>& clips, const std::vector<std::string>& failures,
                   std::size_t paths) {
  for (const Clip& clip : clips) {
    for (const auto& w : clip.warnings) std::cerr << w << '\n';
  }
  for (const auto& failure : failures) std::cerr << failure << '\n';
  if (!failures.empty()) {
    std::cerr << "note: skipped " << failures.size() << " of " << paths
              << " clips that failed to load (--keep-going)\n";
  }
}

std::vector<Clip> load_inputs(const MapCliOptions& opt, const std::vector<std::string>& paths,
                              bool sha256) {
  io::LoadedClips loaded =
      io::load_clips(paths, load_options(opt, sha256), loading_line(opt, paths.size()));
  print_loading(loaded.clips, loaded.failures, paths.size());
  return std::move(loaded.clips);
}

std::vector<std::string> clip_paths(const std::vector<Clip>& clips) {
  std::vector<std::string> paths;
  for (const Clip& clip : clips) paths.push_back(clip.path);
  return paths;
}

std::string clip_names(const std::vector<Clip>& clips) {
  constexpr std::size_t kShown = 3;
  const std::size_t shown = clips.size() <= kShown + 1 ? clips.size() : kShown - 1;
  std::string out;
  for (std::size_t i = 0; i < shown; ++i) out += (i ? ", " : "") + base_name(clips[i].path);
  if (shown < clips.size()) {
    out += " and " + std::to_string(clips.size() - shown) + " more clips";
  }
  return out;
}

namespace {

int parse_frame_bound(const std::string& text, const std::string& whole) {
  int value = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || ptr != text.data() + text.size() || value < 0) {
    throw ParameterError("--frames: '" + whole +
                         "' is not a range A:B of non-negative frame numbers");
  }
  return value;
}

}  // namespace

pipeline::ClipMapOptions clip_map_options(const MapCliOptions& opt, embed::Method method,
                                          bool metrics) {
  pipeline::ClipMapOptions out;
  features::FeatureOptions& f = out.features;
  f.features = opt.features;
  f.distance = opt.distance;
  f.up = parse_axis(opt.up).value_or(Axis::Y);  // --up accepts only y and z
  f.exclude = opt.exclude;
  f.stride = opt.stride;
  f.keep_first = opt.keep_first;
  f.joints = opt.joints;
  if (!opt.frames.empty()) {
    const auto colon = opt.frames.find(':');
    if (colon == std::string::npos) {
      throw ParameterError("--frames: '" + opt.frames +
                           "' is not a range A:B (e.g. 100:400, 100:, :400)");
    }
    const std::string a = opt.frames.substr(0, colon), b = opt.frames.substr(colon + 1);
    if (!a.empty()) f.first_frame = parse_frame_bound(a, opt.frames);
    if (!b.empty()) f.end_frame = parse_frame_bound(b, opt.frames);
  }

  embed::EmbedOptions& e = out.embed;
  e.method = method;
  e.dimensions = opt.dims;
  e.k = opt.k >= 0 ? opt.k : method == embed::Method::Umap ? 15 : 20;
  e.min_dist = opt.min_dist;
  e.epochs = opt.epochs;
  e.max_iterations = opt.max_iterations;
  e.inducing = opt.inducing;
  e.lengthscale = opt.lengthscale;
  e.seed = opt.seed;
  e.reg = opt.reg;
  e.standardize = opt.standardize;
  e.strict = opt.strict;
  if (opt.heat != "auto") {
    double heat = 0.0;
    const auto [ptr, ec] =
        std::from_chars(opt.heat.data(), opt.heat.data() + opt.heat.size(), heat);
    if (ec != std::errc() || ptr != opt.heat.data() + opt.heat.size() || !std::isfinite(heat)) {
      throw ParameterError("--heat: '" + opt.heat + "' is neither 'auto' nor a number");
    }
    e.heat = heat;
  }
  if (opt.exact) out.path = pipeline::MapPath::Dense;
  if (opt.landmarks >= 0) {
    out.path = pipeline::MapPath::Landmarks;
    e.landmarks = opt.landmarks;
  }
  out.metrics = metrics;
  return out;
}

Control progress_line(const MapCliOptions& opt, std::string_view label) {
  // The line is for people watching a terminal; scripts and logs get none. --verbose adds a line
  // per stage, for them too.
  const bool line = !opt.quiet && isatty(STDERR_FILENO);
  if (!line && !opt.verbose) return {};
  struct State {
    int percent = -1;
    std::string stage;
    std::chrono::steady_clock::time_point start, stage_start;
    bool started = false, done = false;
  };
  auto state = std::make_shared<State>();
  return Control([state, line, verbose = opt.verbose, name = std::string(label)](
                     double fraction, std::string_view stage) {
    State& s = *state;
    const auto now = std::chrono::steady_clock::now();
    auto report = [&](const std::string& what, std::chrono::steady_clock::time_point since) {
      if (what.empty()) return;
      if (line) std::fprintf(stderr, "\r%60s\r", "");
      std::fprintf(stderr, "verbose: %s: %.2f s, peak %.0f MiB\n", what.c_str(),
                   std::chrono::duration<double>(now - since).count(),
                   double(peak_memory()) / (1024.0 * 1024.0));
    };
    if (verbose && !s.done) {
      if (!s.started) s.start = now;
      if (!s.started || stage != s.stage) {
        if (s.started) report(s.stage, s.stage_start);
        s.stage = std::string(stage);
        s.stage_start = now;
        s.started = true;
      }
      if (fraction >= 1.0) {
        report(s.stage, s.stage_start);
        report("total", s.start);
        s.done = true;
      }
    }
    if (!line) return;
    const int percent = static_cast<int>(fraction * 100.0);
    if (percent == s.percent) return;
    s.percent = percent;
    std::fprintf(stderr, "\r%-6s %3d%%  %-24.*s", name.c_str(), percent,
                 static_cast<int>(stage.size()), stage.data());
    if (percent >= 100) std::fprintf(stderr, "\r%60s\r", "");
    std::fflush(stderr);
  });
}

void print_diagnostics(const pipeline::ClipMap& map) {
  for (const auto& n : map.features->notes) std::cerr << "note: " << n << '\n';
  for (const auto& n : map.embedding.notes) std::cerr << "note: " << n << '\n';
  for (const auto& w : map.embedding.warnings) std::cerr << "warning: " << w << '\n';
}

}  // namespace motionmap::cli
