// `motionmap map FILE… --method M -o map.csv [--plot map.png] [--metrics]`: one map of the clips.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>

#include "commands.h"
#include "map_options.h"
#include "motionmap/core/error.h"
#include "motionmap/pipeline/map_csv.h"
#include "motionmap/render/map_plot.h"

namespace motionmap::cli {

namespace {

struct MapCommand {
  MapCliOptions map;
  std::string output;
  std::string plot;
  bool metrics = false;
  std::string axes = "equal";
};

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
}

}  // namespace

void setup_map(CLI::App& app) {
  auto cmd = std::make_shared<MapCommand>();
  auto* sub = app.add_subcommand(
      "map",
      "Map every frame of the clips to a point (PCA, SVD, classical MDS, Isomap, Laplacian\n"
      "eigenmap, LLE) and write frame,x,y as CSV, with the effective parameters in a # comment.\n"
      "A leading bind/T-pose frame is left out unless --keep-first.");
  add_map_options(sub, cmd->map, MapOptionsFor::Map);
  sub->add_option("-o,--output", cmd->output, "CSV file to write (default: standard output)");
  sub->add_option("--plot", cmd->plot, "Also draw the map: .png, .svg or .pdf");
  sub->add_option(
         "--axes", cmd->axes,
         "For --plot: equal (one scale for both axes, distances to scale; default) or fill "
         "(each axis scaled to fill the square panel)")
      ->check(CLI::IsMember({"fill", "equal"}));
  sub->add_flag(
      "--metrics", cmd->metrics,
      "Compute trustworthiness and continuity (k = 10), stress (mds, isomap) and the jump "
      "score; printed as a table and in the CSV comment");
  sub->callback([cmd] {
    const std::vector<Clip> clips = load_inputs(cmd->map);
    const pipeline::ClipMapOptions options =
        clip_map_options(cmd->map, cmd->map.method, cmd->metrics);
    const pipeline::ClipMap map = pipeline::map_clips(
        clips, options, progress_line(cmd->map, embed::method_name(cmd->map.method)));
    print_diagnostics(map);
    if (map.embedding.method == embed::Method::LaplacianEigenmap) {
      std::cerr << "heat " << map.embedding.heat_used
                << (options.embed.heat ? "\n" : " (auto: median squared k-NN distance)\n");
    }
    if (cmd->output.empty() || cmd->output == "-") {
      pipeline::write_map_csv(std::cout, map, options, clip_paths(clips));
    } else {
      std::ofstream out(cmd->output);
      if (!out) throw Error(cmd->output + ": error: cannot open for writing");
      pipeline::write_map_csv(out, map, options, clip_paths(clips));
      if (!out.flush()) throw Error(cmd->output + ": error: write failed");
    }
    if (map.metrics) {
      const bool csv_on_stdout = cmd->output.empty() || cmd->output == "-";
      print_metrics_table(csv_on_stdout ? std::cerr : std::cout, map, options.metrics_k);
    }
    if (!cmd->plot.empty()) {
      render::MapPlotOptions plot;
      plot.title = QString::fromStdString(clip_names(clips) + " — " +
                                          std::string(embed::method_name(map.embedding.method)));
      plot.notes << QString::fromStdString(pipeline::describe_parameters(map.embedding, options));
      if (map.metrics)
        plot.notes << QString::fromStdString(pipeline::describe_metrics(*map.metrics));
      plot.time_legend = true;
      if (cmd->axes == "fill") plot.notes << "axes scaled to fill the panel";
      ensure_gui_application();
      render::save_map_plot(cmd->plot,
                            cmd->axes == "fill" ? render::fill_axes(map.embedding.coordinates)
                                                : map.embedding.coordinates,
                            map.features->segment_starts, plot);
    }
  });
}

}  // namespace motionmap::cli
