// The label options of `map` and `figure` (docs/labels.md): --labels-from-name, --labels and
// --color-by, and what they make of a map's plot and metrics.
#include <algorithm>
#include <cstdio>
#include <iostream>

#include "map_options.h"
#include "motionmap/core/error.h"
#include "motionmap/core/files.h"

namespace motionmap::cli {

void add_label_options(CLI::App* sub, MapCliOptions& opt) {
  sub->add_option(
         "--labels-from-name", opt.labels_from_name,
         "Label the clips from their file names: a template such as '{action}_{style}_{take}' "
         "matched at the end of the name without extension (a prefix like 'dataset-1_' is "
         "skipped; '^' first anchors it at the start; a field holds no character of the "
         "template's own text), or 're:REGEX' with named groups (?P<action>…). A name that "
         "does not match is an error (docs/labels.md)")
      ->check(CLI::Validator(
          [](std::string& pattern) -> std::string {
            try {
              pipeline::NamePattern check(pattern);
            } catch (const ParameterError& e) {
              return e.what();
            }
            return {};
          },
          "PATTERN"));
  sub->add_option("--labels", opt.labels_file,
                  "Labels from a CSV file with a header: 'clip,action,style' (one row per clip) "
                  "or 'clip,start,end,action' (frames start to end, inclusive), or JSON "
                  "([{\"clip\": …, \"action\": …}] or {\"clip\": {\"action\": …}}); a clip is "
                  "named by its path, file name or name without extension (docs/labels.md)")
      ->check(CLI::ExistingFile);
  sub->add_option("--color-by", opt.color_by,
                  "Colour the plot by time (each clip red → blue; default), clip (each clip's "
                  "file name a value), or a label's name (--labels-from-name, --labels): up to "
                  "12 values, with a legend and counts; more: the 11 most frequent and 'other'");
}

std::optional<pipeline::LabelTable> read_clip_labels(const MapCliOptions& opt,
                                                     const std::vector<Clip>& clips) {
  const bool by_label = opt.color_by != "time" && opt.color_by != "clip";
  if (opt.labels_from_name.empty() && opt.labels_file.empty()) {
    if (by_label) {
      throw CLI::ValidationError("--color-by",
                                 "'" + opt.color_by +
                                     "' is not time or clip, and there are no labels: give "
                                     "--labels-from-name or --labels");
    }
    return std::nullopt;
  }
  std::vector<std::string> paths;
  std::vector<int> frames;
  for (const Clip& clip : clips) {
    paths.push_back(clip.path);
    frames.push_back(clip.motion.num_frames);
  }
  pipeline::LabelTable table;
  if (!opt.labels_from_name.empty()) {
    table = pipeline::labels_from_names(paths, pipeline::NamePattern(opt.labels_from_name));
  }
  if (!opt.labels_file.empty()) {
    // The file's labels after the names', span by span (the rule Studio's "Labels from file…"
    // follows too).
    pipeline::merge_labels(table, pipeline::read_label_file(opt.labels_file, paths, frames),
                           opt.labels_file);
  }
  if (by_label &&
      std::find(table.names.begin(), table.names.end(), opt.color_by) == table.names.end()) {
    std::string names;
    for (const std::string& name : table.names) names += (names.empty() ? "" : ", ") + name;
    throw CLI::ValidationError("--color-by", "no label named '" + opt.color_by +
                                                 "'; the labels are " + names + " (or time, clip)");
  }
  for (const std::string& note : table.notes) std::cerr << "note: " << note << '\n';
  return table;
}

pipeline::Labels labels_of(const std::optional<pipeline::LabelTable>& table,
                           const features::FeatureSet& set) {
  if (!table) return {};
  return pipeline::sample_labels(*table, set.clip_of, set.frame_of);
}

void color_plot(render::MapPlotOptions& plot, const MapCliOptions& opt,
                const pipeline::Labels& labels, const std::vector<Clip>& clips,
                std::span<const int> clip_of) {
  plot.time_legend = true;
  if (opt.color_by == "time") return;
  // By clip: the clips' file names as the values of a label, in clip order.
  pipeline::LabelColumn by_clip;
  const pipeline::LabelColumn* column = &by_clip;
  if (opt.color_by == "clip") {
    by_clip.name = "clip";
    for (const Clip& clip : clips) by_clip.categories.push_back(base_name(clip.path));
    by_clip.codes.assign(clip_of.begin(), clip_of.end());
  } else {
    column = labels.find(opt.color_by);
    if (!column) throw ParameterError("--color-by: no label named '" + opt.color_by + "'");
  }
  // The values' colours by render's rule (the most frequent coloured, the rest grey 'other').
  const std::vector<int> counts = column->counts();
  const std::vector<int> colour = render::category_slots(counts);
  int others = 0;
  int other = 0;
  for (std::size_t v = 0; v < counts.size(); ++v) {
    if (colour[v] < 0) {
      ++others;
      other += counts[v];
      continue;
    }
    const std::string& value = column->categories[v];
    plot.categories << QString::fromStdString(value.empty() ? "(none)" : value) + " (" +
                           QString::number(counts[v]) + ")";
  }
  if (others > 0) {
    const std::size_t shown = counts.size() - std::size_t(others);
    plot.other_category =
        "other (" + QString::number(others) + " values, " + QString::number(other) + ")";
    std::cerr << "note: " << (column == &by_clip ? "the map" : "label '" + column->name + "'")
              << " has " << counts.size() << (column == &by_clip ? " clips" : " values")
              << "; the plot colours the " << shown << " most frequent and shows the other "
              << others << " in grey as 'other'\n";
  }
  plot.point_category.resize(column->codes.size());
  for (std::size_t i = 0; i < column->codes.size(); ++i) {
    plot.point_category[i] = colour[std::size_t(column->codes[i])];
  }
  plot.start_marker = false;
  plot.line_width = std::min(plot.line_width, 1.0);
}

void print_label_accuracy(std::ostream& out, std::span<const pipeline::LabelAccuracy> accuracy) {
  if (accuracy.empty()) return;
  char line[200];
  std::snprintf(line, sizeof line, "%-16s %8s %9s %8s\n", "label accuracy", "map", "features",
                "frames");
  out << line;
  for (const pipeline::LabelAccuracy& a : accuracy) {
    std::snprintf(line, sizeof line, "%-16s %8.4f %9.4f %8d\n", a.label.c_str(), a.map, a.features,
                  a.queries);
    out << line;
  }
  out << "(each frame's label by the vote of its " << accuracy.front().k
      << " nearest frames of other clips: on the map, and by the pose distance)\n";
}

}  // namespace motionmap::cli
