// `motionmap map FILE… --method M -o map.csv [--plot map.png] [--metrics] [--save lib.mmap.h5]`:
// one map of the clips; `motionmap map NEW… --onto lib.mmap.h5 -o new.csv`: the clips' frames
// placed on a saved map without refitting it.
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <span>

#include "commands.h"
#include "map_options.h"
#include "motionmap/core/error.h"
#include "motionmap/core/files.h"
#include "motionmap/core/memory.h"
#include "motionmap/mapfile/map_file.h"
#include "motionmap/pipeline/map_csv.h"
#include "motionmap/pipeline/stream_map.h"
#include "motionmap/render/map_plot.h"

namespace motionmap::cli {

namespace {

// Frames voted on for the label accuracy: all up to this many, else a seeded sample.
constexpr int kLabelQueries = 5000;

struct MapCommand {
  MapCliOptions map;
  std::string output;
  std::string plot;
  bool metrics = false;
  std::string axes = "equal";
  std::string save;
  std::string onto;
};

// The options a saved map fixes: with --onto they are usage errors (docs/map-file.md). --save
// is not one of them: with --onto it writes the placed clips as a map file (placed_map_file).
constexpr const char* kFixedByTheMap[] = {
    "--method", "--dims",      "--neighbors", "--heat",     "--reg",    "--standardize",
    "--strict", "--features",  "--distance",  "--exclude",  "--up",     "--joints",
    "--exact",  "--landmarks", "--metrics",   "--min-dist", "--epochs", "--seed"};

void write_csv(const std::string& output, const pipeline::ClipMap& map,
               const pipeline::ClipMapOptions& options, const std::vector<Clip>& clips,
               const pipeline::Labels& labels = {},
               std::span<const pipeline::LabelAccuracy> accuracy = {}) {
  const pipeline::Labels* with = labels.empty() ? nullptr : &labels;
  if (output.empty() || output == "-") {
    pipeline::write_map_csv(std::cout, map, options, clip_paths(clips), with, accuracy);
    return;
  }
  std::ofstream out(output);
  if (!out) throw Error(output + ": error: cannot open for writing");
  pipeline::write_map_csv(out, map, options, clip_paths(clips), with, accuracy);
  if (!out.flush()) throw Error(output + ": error: write failed");
}

// Once the features are built nothing reads the clips' poses again (the CSV and the map file read
// their paths, frame counts and frame times, and the first skeleton): free them before mapping,
// since they are most of a large library's memory (1.7 GB of 3.5 GB at 10⁶ frames).
void forget_poses(std::vector<Clip>& clips) {
  for (Clip& clip : clips) {
    std::vector<Eigen::Quaterniond>().swap(clip.motion.rotations);
    std::vector<Eigen::Vector3d>().swap(clip.motion.translations);
  }
  release_freed_memory();
}

// --onto: the clips' frames placed on the saved map, written as `map` writes a map.
void place_onto(const MapCommand& cmd) {
  const mapfile::MapFile saved = mapfile::read_map_file(cmd.onto);
  const std::vector<Clip> clips =
      load_inputs(cmd.map, input_paths(cmd.map), /*sha256=*/!cmd.save.empty());
  const std::optional<pipeline::LabelTable> table = read_clip_labels(cmd.map, clips);
  // The frames to place are the command line's (--frames, --stride, --keep-first); everything
  // else is the map's.
  const features::FeatureOptions chosen =
      clip_map_options(cmd.map, saved.options.embed.method, false).features;
  mapfile::PlaceOptions place;
  place.first_frame = chosen.first_frame;
  place.end_frame = chosen.end_frame;
  place.stride = chosen.stride;
  place.keep_first = chosen.keep_first;
  const std::string method(embed::method_name(saved.options.embed.method));
  mapfile::Placement placed =
      mapfile::place_clips(clips, saved, place, progress_line(cmd.map, method));
  const pipeline::Labels labels = labels_of(table, placed.features);
  if (!cmd.save.empty()) {
    const std::vector<mapfile::PlacedClip> records = mapfile::placed_clips(clips, placed);
    mapfile::MapFile file = mapfile::placed_map_file(saved, records, base_name(cmd.onto));
    file.labels = labels;
    mapfile::write_map_file(cmd.save, file);
  }

  pipeline::ClipMapOptions options = saved.options;
  options.features.first_frame = place.first_frame;
  options.features.end_frame = place.end_frame;
  options.features.stride = place.stride;
  options.features.keep_first = place.keep_first;
  auto features = std::make_shared<features::FeatureSet>(std::move(placed.features));
  const std::size_t saved_clips = saved.clips.size();
  features->notes.push_back("placed onto " + cmd.onto + " without refitting it (the " + method +
                            " map of " + std::to_string(saved.num_samples()) + " frames of " +
                            (saved_clips == 1 ? base_name(saved.clips.front().path)
                                              : std::to_string(saved_clips) + " clips") +
                            ")");
  features->notes.insert(features->notes.end(), saved.read_notes.begin(), saved.read_notes.end());
  pipeline::ClipMap map;
  map.features = features;
  map.embedding = mapfile::embedding_for_csv(saved, placed.coordinates);
  map.dense = saved.dense;
  print_diagnostics(map);
  write_csv(cmd.output, map, options, clips, labels);
  if (cmd.plot.empty()) return;
  // The new frames' trajectories over the map's samples in grey, framed together; --axes fill
  // scales both alike.
  render::MapPlotOptions plot;
  plot.title =
      QString::fromStdString(clip_names(clips) + " on " + base_name(cmd.onto) + " — " + method);
  plot.notes << QString::fromStdString(pipeline::describe_parameters(map.embedding, options))
             << QString::fromStdString("grey: the map's " + std::to_string(saved.num_samples()) +
                                       " frames; in colour: the new frames, placed on it");
  color_plot(plot, cmd.map, labels, clips, features->clip_of);
  Eigen::MatrixXd coords = map.embedding.coordinates;
  plot.backdrop = saved.coordinates;
  if (cmd.axes == "fill") {
    Eigen::MatrixXd both(coords.rows() + plot.backdrop.rows(), coords.cols());
    both << coords, plot.backdrop;
    both = render::fill_axes(both);
    coords = both.topRows(coords.rows());
    plot.backdrop = both.bottomRows(plot.backdrop.rows());
    plot.notes << "axes scaled to fill the panel";
  }
  ensure_gui_application();
  render::save_map_plot(cmd.plot, coords, features->segment_starts, plot);
}

// Whether `map` reads the clips a clip at a time (pipeline/stream_map.h): on request (--stream;
// a usage error for options that cannot be), or for pca and svd when loading the clips whole and
// building their features would take more memory than is available (estimated from the files'
// sizes), where the in-memory map could not be made.
bool streams(const MapCliOptions& opt, const pipeline::ClipMapOptions& options,
             const std::vector<std::string>& paths) {
  const std::string why = pipeline::why_not_streamed(options);
  if (opt.stream) {
    if (!why.empty()) throw CLI::ValidationError("--stream", why);
    return true;
  }
  const std::optional<std::int64_t> available = available_memory();
  if (!pipeline::streams_by_default(options, paths, available)) return false;
  std::cerr << "note: the clips and their features would take ~"
            << format_bytes(pipeline::estimate_load_bytes(paths))
            << " in memory (estimated from the files' sizes), more than the "
            << format_bytes(double(*available))
            << " available: reading them from their files a few at a time, twice (--stream)\n";
  return true;
}

// The streamed map of the clips at `paths`: the clips' warnings and the skipped clips' errors
// printed as load_inputs() prints them; the clips returned without their poses.
pipeline::ClipMap stream_clips(const MapCliOptions& opt, const std::vector<std::string>& paths,
                               bool sha256, const pipeline::ClipMapOptions& options,
                               const Control& progress, std::vector<Clip>& clips) {
  pipeline::StreamedMap streamed =
      pipeline::stream_map(paths, load_options(opt, sha256), options, progress);
  print_loading(streamed.clips, streamed.failures, paths.size());
  clips = std::move(streamed.clips);
  return std::move(streamed.map);
}

void print_metrics_table(std::ostream& out, const pipeline::ClipMap& map, int k) {
  const auto& m = *map.metrics;
  char line[160];
  std::snprintf(line, sizeof line, "%-8s %16s %12s %8s %6s\n", "method", "trustworthiness",
                "continuity", "stress", "jump");
  out << line;
  std::snprintf(line, sizeof line, "%-8s %16.4f %12.4f %8s %6.2f\n",
                std::string(embed::method_name(map.embedding.method)).c_str(),
                m.neighborhood.trustworthiness, m.neighborhood.continuity,
                m.stress ? std::to_string(*m.stress).substr(0, 6).c_str() : "-", m.jump);
  out << line << "(trustworthiness and continuity at k = " << k
      << " against the pose distance D)\n";
  if (!m.degenerate.empty()) {
    out << "degenerate map, its figures not comparable with other maps': " << m.degenerate << '\n';
  }
}

}  // namespace

void setup_map(CLI::App& app) {
  auto cmd = std::make_shared<MapCommand>();
  auto* sub = app.add_subcommand(
      "map",
      "Map every frame of the clips to a point (PCA, SVD, classical MDS, Isomap, Laplacian\n"
      "eigenmap, LLE) and write frame,x,y as CSV, with the effective parameters in a # comment.\n"
      "A leading bind/T-pose frame is left out unless --keep-first. --save also writes the map\n"
      "as an HDF5 map file; --onto places the clips' frames on a saved map instead of mapping.");
  add_map_options(sub, cmd->map, MapOptionsFor::Map);
  sub->add_option("-o,--output", cmd->output, "CSV file to write (default: standard output)");
  sub->add_option("--plot", cmd->plot,
                  "Also draw the map: .png, .svg or .pdf (with --onto: the new frames' "
                  "trajectories over the saved map's samples in grey)");
  sub->add_option(
         "--axes", cmd->axes,
         "For --plot: equal (one scale for both axes, distances to scale; default) or fill "
         "(each axis scaled to fill the square panel)")
      ->check(CLI::IsMember({"fill", "equal"}));
  sub->add_flag(
      "--metrics", cmd->metrics,
      "Compute trustworthiness and continuity (k = 10), stress (mds, isomap) and the jump "
      "score; printed as a table and in the CSV comment");
  sub->add_option("--save", cmd->save,
                  "Also write the map as an HDF5 map file (.mmap.h5; docs/map-file.md): the clips "
                  "(paths, frames, SHA-256), the parameters, the coordinates and what placing new "
                  "clips on it with --onto needs. With --onto: the placed clips as a map file of "
                  "their own (their frames are its rows; the saved map's model places further "
                  "clips)");
  auto* onto =
      sub->add_option(
             "--onto", cmd->onto,
             "Place the clips' frames on the map saved in this file (--save) without refitting "
             "it, and write them as `map` writes a map. The map fixes the method, its "
             "parameters and the features (those options are errors here); --frames, --stride "
             "and --keep-first choose the frames placed")
          ->check(CLI::ExistingFile);
  for (const char* name : kFixedByTheMap) onto->excludes(sub->get_option(name));
  onto->excludes(sub->get_option("--stream"));
  sub->callback([cmd] {
    if (!cmd->onto.empty()) {
      place_onto(*cmd);
      return;
    }
    const std::vector<std::string> paths = input_paths(cmd->map);
    const pipeline::ClipMapOptions options =
        clip_map_options(cmd->map, cmd->map.method, cmd->metrics);
    const Control progress = progress_line(cmd->map, embed::method_name(cmd->map.method));
    std::vector<Clip> clips;
    pipeline::ClipMap map;
    std::optional<mapfile::BlendRecord> blend;  // a streamed map's file has none
    std::optional<pipeline::LabelTable> table;
    if (streams(cmd->map, options, paths)) {
      map = stream_clips(cmd->map, paths, !cmd->save.empty(), options, progress, clips);
      table = read_clip_labels(cmd->map, clips);
    } else {
      clips = load_inputs(cmd->map, paths, /*sha256=*/!cmd->save.empty());
      table = read_clip_labels(cmd->map, clips);  // a bad label file fails before the mapping
      std::shared_ptr<features::FeatureSet> features =
          pipeline::clip_features(clips, options, progress);
      // What `pose`/`synth --map` need of all the clips, taken while their poses are here.
      if (!cmd->save.empty()) blend = mapfile::blend_record(clips, *features);
      forget_poses(clips);
      map = pipeline::map_features(std::move(features), options, progress);
    }
    print_diagnostics(map);
    if (map.embedding.method == embed::Method::LaplacianEigenmap) {
      std::cerr << "heat " << map.embedding.heat_used
                << (options.embed.heat ? "\n" : " (auto: median squared k-NN distance)\n");
    }
    const pipeline::Labels labels = labels_of(table, *map.features);
    std::vector<pipeline::LabelAccuracy> accuracy;
    if (map.metrics && !labels.empty()) {
      if (map.features->has_distances() ||
          map.features->distance_input.rows() == map.features->num_samples()) {
        const auto start = std::chrono::steady_clock::now();
        accuracy = pipeline::label_accuracy(*map.features, map.embedding.coordinates, labels,
                                            options.metrics_k, kLabelQueries);
        if (cmd->map.verbose) {
          std::fprintf(
              stderr, "verbose: label accuracy: %.2f s, peak %.0f MiB\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
              double(peak_memory()) / (1024.0 * 1024.0));
        }
      } else {
        std::cerr << "note: label accuracy not measured: this map's features were not kept\n";
      }
    }
    write_csv(cmd->output, map, options, clips, labels, accuracy);
    if (map.metrics) {
      const bool csv_on_stdout = cmd->output.empty() || cmd->output == "-";
      print_metrics_table(csv_on_stdout ? std::cerr : std::cout, map, options.metrics_k);
      print_label_accuracy(csv_on_stdout ? std::cerr : std::cout, accuracy);
    }
    if (!cmd->plot.empty()) {
      render::MapPlotOptions plot;
      plot.title = QString::fromStdString(clip_names(clips) + " — " +
                                          std::string(embed::method_name(map.embedding.method)));
      plot.notes << QString::fromStdString(pipeline::describe_parameters(map.embedding, options));
      if (map.metrics)
        plot.notes << QString::fromStdString(pipeline::describe_metrics(*map.metrics));
      for (const pipeline::LabelAccuracy& a : accuracy) {
        plot.notes << QString::fromStdString("label accuracy (" + a.label +
                                             ", 10-NN of other clips): map " +
                                             std::to_string(a.map).substr(0, 5) + ", features " +
                                             std::to_string(a.features).substr(0, 5));
      }
      color_plot(plot, cmd->map, labels, clips, map.features->clip_of);
      if (cmd->axes == "fill") plot.notes << "axes scaled to fill the panel";
      ensure_gui_application();
      render::save_map_plot(cmd->plot,
                            cmd->axes == "fill" ? render::fill_axes(map.embedding.coordinates)
                                                : map.embedding.coordinates,
                            map.features->segment_starts, plot);
    }
    // Last, so that the map file's model takes the map's landmark fit instead of a copy.
    if (!cmd->save.empty()) {
      mapfile::MapFile file = mapfile::make_map_file(clips, std::move(map), options);
      file.blend = std::move(blend);
      file.labels = labels;
      mapfile::write_map_file(cmd->save, file);
    }
  });
}

}  // namespace motionmap::cli
