// `motionmap figure FILE… -o fig.png`: the reference evaluation — all six methods side by side
// (`--methods` chooses others, umap and gplvm among them).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>

#include "commands.h"
#include "map_options.h"
#include "motionmap/core/error.h"
#include "motionmap/render/map_plot.h"

namespace motionmap::cli {

namespace {

// Frames voted on for the label accuracy: all up to this many, else a seeded sample.
constexpr int kLabelQueries = 5000;

struct FigureCommand {
  MapCliOptions map;
  std::string output;
  int panel_px = 500;
  std::string axes = "fill";
  std::string methods;  ///< comma-separated; empty: the six spectral methods
};

// The methods of --methods (comma-separated names, in the order given, each once); empty: the
// reference evaluation's six spectral methods (umap and gplvm, optimised and slower, on request).
std::vector<embed::Method> figure_methods(const std::string& list) {
  std::vector<embed::Method> methods;
  if (list.empty()) {
    for (embed::Method m : embed::all_methods()) {
      if (m != embed::Method::Umap && m != embed::Method::Gplvm) methods.push_back(m);
    }
    return methods;
  }
  std::stringstream in(list);
  for (std::string name; std::getline(in, name, ',');) {
    if (name.empty()) throw ParameterError("--methods: an empty name in '" + list + "'");
    const std::optional<embed::Method> m = embed::parse_method(name);
    if (!m) {
      throw ParameterError("--methods: unknown method '" + name +
                           "' (expected a comma-separated list of pca, svd, mds, isomap, le, "
                           "lle, umap, gplvm)");
    }
    if (std::find(methods.begin(), methods.end(), *m) != methods.end()) {
      throw ParameterError("--methods: " + name + " is given twice");
    }
    methods.push_back(*m);
  }
  return methods;
}

// Panels per row: one row up to 3, then 2 × 2, then rows of 3 (up to 6 and 9) or 4 (7, 8).
int figure_columns(std::size_t panels) {
  if (panels <= 3) return static_cast<int>(panels);
  if (panels == 4) return 2;
  return panels == 7 || panels == 8 ? 4 : 3;
}

const char* long_name(embed::Method m) {
  switch (m) {
    case embed::Method::Pca:
      return "PCA";
    case embed::Method::Svd:
      return "SVD";
    case embed::Method::Mds:
      return "Classical MDS";
    case embed::Method::Isomap:
      return "Isomap";
    case embed::Method::LaplacianEigenmap:
      return "Laplacian eigenmap";
    case embed::Method::Lle:
      return "LLE";
    case embed::Method::Umap:
      return "UMAP";
    case embed::Method::Gplvm:
      return "GP-LVM";
  }
  return "?";
}

QString format(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v);
  return QString::fromLatin1(buf);
}

}  // namespace

void setup_figure(CLI::App& app) {
  auto cmd = std::make_shared<FigureCommand>();
  auto* sub = app.add_subcommand(
      "figure",
      "Map the clips with all six methods (PCA, SVD, MDS / Isomap, LE, LLE), or those of\n"
      "--methods, and draw them in a grid with each map's quality metrics under it\n"
      "(trustworthiness T and continuity C at k = 10, stress for MDS/Isomap, jump score). Also\n"
      "prints the metrics as a table.");
  add_map_options(sub, cmd->map, MapOptionsFor::Figure);
  sub->add_option("-o,--output", cmd->output, "Figure to write: .png, .svg or .pdf")->required();
  sub->add_option("--methods", cmd->methods,
                  "Comma-separated methods to draw, in order, e.g. pca,isomap,umap,gplvm "
                  "(default: pca,svd,mds,isomap,le,lle)");
  sub->add_option("--panel-size", cmd->panel_px, "Pixels per panel (default 500)")
      ->check(CLI::Range(64, 4096));
  sub->add_option(
         "--axes", cmd->axes,
         "fill: each panel's axes scaled to fill it, as the reference system draws (default); "
         "equal: one scale for both axes, so distances are to scale")
      ->check(CLI::IsMember({"fill", "equal"}));
  sub->callback([cmd] {
    const std::vector<Clip> clips = load_inputs(cmd->map);
    const std::optional<pipeline::LabelTable> table = read_clip_labels(cmd->map, clips);
    const std::vector<embed::Method> methods = figure_methods(cmd->methods);
    pipeline::ClipMapOptions options =
        clip_map_options(cmd->map, methods.front(), /*metrics=*/true);
    const Control overall = progress_line(cmd->map, "figure");
    const double n = static_cast<double>(methods.size()) + 1.0;
    auto start = std::chrono::steady_clock::now();

    // One feature set (and D, on the dense path) shared by every method.
    pipeline::FeatureCache cache;
    const std::shared_ptr<const features::FeatureSet> features =
        cache.get(clips, options.features, false, overall.stage("features", 0, 1 / n));
    const features::FeatureSet& set = *features;
    for (const auto& note : set.notes) std::cerr << "note: " << note << '\n';
    const pipeline::Labels labels = labels_of(table, set);
    std::vector<render::FigurePanel> panels;
    int failures = 0;
    // With labels, one more column per label: its accuracy on the map (the feature space's, the
    // same for every method, is printed once under the table).
    std::string label_header;
    for (const pipeline::LabelColumn& column : labels.columns) {
      label_header += " acc[" + column.name + "]";
    }
    std::vector<pipeline::LabelAccuracy> feature_accuracy;
    // Every panel coloured alike (--color-by); the figure's header holds the legend.
    render::MapPlotOptions colored;
    color_plot(colored, cmd->map, labels, clips, set.clip_of);
    colored.time_legend = false;
    std::printf("%-7s %16s %11s %8s %7s %9s%s\n", "method", "trustworthiness", "continuity",
                "stress", "jump", "seconds", label_header.c_str());
    for (std::size_t i = 0; i < methods.size(); ++i) {
      render::FigurePanel panel;
      panel.options = colored;
      panel.options.title = long_name(methods[i]);
      panel.segment_starts = set.segment_starts;
      // Each method's own defaults (umap's k is 15, the others' 20, when -k is not given).
      options = clip_map_options(cmd->map, methods[i], /*metrics=*/true);
      const auto t0 = std::chrono::steady_clock::now();
      try {
        const pipeline::ClipMap map =
            pipeline::map_clips(clips, options, overall.part((i + 1) / n, (i + 2) / n), &cache);
        const embed::Embedding& e = map.embedding;
        const pipeline::MapMetrics& m = *map.metrics;
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        for (const auto& w : e.warnings)
          std::cerr << "warning: " << embed::method_name(methods[i]) << ": " << w << '\n';
        panel.coords = cmd->axes == "fill" ? render::fill_axes(e.coordinates) : e.coordinates;
        QString line = "T " + format("%.3f", m.neighborhood.trustworthiness) + "   C " +
                       format("%.3f", m.neighborhood.continuity);
        if (m.stress) line += "   stress " + format("%.3f", *m.stress);
        line += "   jump " + format("%.1f", m.jump);
        panel.options.notes << line;
        if (!m.degenerate.empty()) {
          panel.options.notes << "degenerate, not comparable: " +
                                     QString::fromStdString(m.degenerate);
        }
        if (m.sample > 0) {
          panel.options.notes << "T, C on " + QString::number(m.sample) + " random frames" +
                                     (m.stress ? ", stress on the landmarks" : "");
        }
        if (e.method == embed::Method::LaplacianEigenmap) {
          panel.options.notes << "k = " + QString::number(e.k_used) + ", heat " +
                                     format("%.3g", e.heat_used);
        } else if (e.k_used > 0) {
          panel.options.notes << "k = " + QString::number(e.k_used);
        }
        std::string label_cells;
        if (!labels.empty()) {
          // The feature space's figures once: they are the same for every map.
          const std::vector<pipeline::LabelAccuracy> accuracy =
              pipeline::label_accuracy(*map.features, e.coordinates, labels, options.metrics_k,
                                       kLabelQueries, {}, feature_accuracy.empty());
          QString accuracy_line = "label accuracy";
          for (const pipeline::LabelColumn& column : labels.columns) {
            const auto a = std::find_if(accuracy.begin(), accuracy.end(),
                                        [&](const auto& x) { return x.label == column.name; });
            const std::string cell =
                a == accuracy.end() ? "-" : format("%.4f", a->map).toStdString();
            const std::size_t width = column.name.size() + 5;  // "acc[" + name + "]"
            label_cells +=
                " " + std::string(width > cell.size() ? width - cell.size() : 0, ' ') + cell;
            if (a != accuracy.end()) {
              accuracy_line +=
                  " " + QString::fromStdString(column.name) + " " + format("%.3f", a->map);
            }
          }
          if (accuracy_line != "label accuracy") panel.options.notes << accuracy_line;
          if (feature_accuracy.empty()) feature_accuracy = accuracy;
        }
        std::printf(
            "%-7s %16.4f %11.4f %8s %7.2f %9.3f%s%s\n",
            std::string(embed::method_name(methods[i])).c_str(), m.neighborhood.trustworthiness,
            m.neighborhood.continuity,
            m.stress ? format("%.4f", *m.stress).toStdString().c_str() : "-", m.jump, seconds,
            label_cells.c_str(),
            m.degenerate.empty() ? "" : ("  degenerate, not comparable: " + m.degenerate).c_str());
      } catch (const Cancelled&) {
        throw;
      } catch (const Error& e) {
        ++failures;
        std::cerr << "motionmap: " << embed::method_name(methods[i]) << ": " << e.what() << '\n';
        panel.coords.resize(0, 2);
        panel.options.notes << QString("failed: ") + QString::fromStdString(e.what()).left(80);
      }
      panels.push_back(std::move(panel));
    }
    for (const pipeline::LabelAccuracy& a : feature_accuracy) {
      std::printf(
          "label accuracy of %s in the feature space (what a perfect map keeps): %.4f "
          "(%d frames; each frame's label by the vote of its %d nearest frames of other "
          "clips)\n",
          a.label.c_str(), a.features, a.queries, a.k);
    }
    const QString title = QString::fromStdString(clip_names(clips)) + " — " +
                          QString::number(set.num_samples()) + " frames, features " +
                          QString::fromStdString(
                              std::string(features::feature_kind_name(options.features.features))) +
                          ", distance " +
                          QString::fromStdString(std::string(
                              features::distance_kind_name(options.features.distance))) +
                          (cmd->axes == "fill" ? ", axes scaled to fill each panel" : "");
    ensure_gui_application();
    render::save_figure(cmd->output, panels, figure_columns(panels.size()), cmd->panel_px, title);
    const double total =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cerr << "wrote " << cmd->output << " (" << total << " s)\n";
    if (failures > 0)
      throw Error(std::to_string(failures) + " of the " + std::to_string(methods.size()) +
                  " maps failed (shown as empty panels)");
  });
}

}  // namespace motionmap::cli
