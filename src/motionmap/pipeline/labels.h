#pragma once
// Labels of a library's clips and frames (docs/labels.md): what a clip is ("walk", "angry"), read
// from its file name or from a CSV/JSON file, expanded to one value per map sample, kept in map
// files and map CSVs, drawn as colours, and measured against (the label accuracy of a map).
//
//   auto pattern = motionmap::pipeline::NamePattern("{action}_{style}_{take}");
//   auto table = motionmap::pipeline::labels_from_names(paths, pattern);      // one row per clip
//   // or: auto table = motionmap::pipeline::read_label_file("labels.csv", paths, frame_counts);
//   auto labels = motionmap::pipeline::sample_labels(table, features->clip_of, features->frame_of);
//   labels.columns[0].name;          // "action"
//   labels.columns[0].value(i);      // frame i's action ("" when unlabelled)
//
// A label table names clips by index (the order of the paths it was read against); frames are
// frame indices of the clip's file, as FeatureSet::frame_of holds them.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "motionmap/embed/metrics.h"
#include "motionmap/features/features.h"

namespace motionmap::pipeline {

/// At most this many labels (columns) and this many bytes per label name or value: map files
/// store them as fixed-length strings (docs/map-file.md).
constexpr int kMaxLabels = 32;
constexpr int kMaxLabelBytes = 255;

/// One labelled span of a clip: frames [first, last] (inclusive, file frame indices) of clip
/// `clip` have value `value` for the table's label `label`. A whole clip is first = 0,
/// last = kToEnd.
struct LabelSpan {
  static constexpr int kToEnd = -1;
  int clip = 0;
  int first = 0;
  int last = kToEnd;
  int label = 0;  ///< index into LabelTable::names
  std::string value;
};

/// Labels as read: label names and spans of clips. Where spans of one label overlap, the later
/// span wins (so a file can give a clip's label and then override some of its frames).
struct LabelTable {
  std::vector<std::string> names;  ///< label names, in the order of the source's columns
  std::vector<LabelSpan> spans;
  /// Notes for the user: clips with no label, …
  std::vector<std::string> notes;
};

/// A file-name pattern that labels clips (`--labels-from-name`).
///
/// - A template: literal text and `{name}` fields, e.g. "{action}_{style}_{take}". It is matched
///   against the END of the file's stem (its name without folder and extension), so a prefix
///   such as "dataset-1_" is skipped; write "^" first to match the whole stem. A field captures
///   one or more characters up to the first character of the text after it (in "{a}_{b}" a
///   field holds no '_'); the last field, characters other than the last character of the text
///   before it. Literal text must match exactly. "{{" and "}}" are literal braces;
///   "{_}" or "{}" captures and discards.
/// - A regular expression, when the pattern starts with "re:": ECMAScript syntax with named
///   groups `(?P<name>…)` or `(?<name>…)` (the names become labels), searched in the stem
///   (anchor it with ^…$ as needed).
class NamePattern {
 public:
  /// @throws ParameterError naming the pattern and the problem (no field, a bad field name, an
  ///   unclosed brace, a regular expression that does not compile or has no named group, a label
  ///   name given twice).
  explicit NamePattern(std::string pattern);

  const std::string& pattern() const { return m_pattern; }
  /// The label names, in the order of the fields or groups.
  const std::vector<std::string>& names() const { return m_names; }
  /// The labels of a file name (folder and extension are removed first): one value per name,
  /// or nullopt when the name does not match.
  std::optional<std::vector<std::string>> match(std::string_view path) const;

 private:
  std::string m_pattern;
  std::string m_regex;               ///< the ECMAScript expression it compiles to
  std::vector<std::string> m_names;  ///< label names
  std::vector<int> m_groups;         ///< per name: its capture group
};

/// One row per clip: the labels `pattern` reads from each path's file name.
/// @throws ParameterError naming the file and the pattern for a name that does not match.
LabelTable labels_from_names(std::span<const std::string> paths, const NamePattern& pattern);

/// Parses labels in CSV: a header naming the columns, then one row per clip or span.
///   clip,action,style            one row per clip: its labels
///   clip,start,end,action        a span of frames (inclusive, file frame indices) per row
/// `clip` names a clip of `paths` by its path as given, its file name or its stem (a name two
/// clips share is an error). `frame_counts` (one per path, or empty to skip the check) bounds
/// the frames. Lines starting with '#' and blank lines are skipped; fields may be quoted ("…",
/// "" inside for a quote). `path` is for messages.
/// @throws ParseError `path:line:col: error: …` for an empty file, a header without a clip
///   column or without a label column, a duplicate column, a row with another field count, an
///   unknown or ambiguous clip, a start or end that is not an integer ≥ 0, start > end, a frame
///   beyond its clip, a name or value over kMaxLabelBytes bytes or not valid UTF-8, more than
///   kMaxLabels labels. Bytes that are not printable are escaped in every message.
LabelTable parse_label_csv(std::string_view text, std::span<const std::string> paths,
                           std::span<const int> frame_counts = {},
                           const std::string& path = "<memory>");

/// Parses labels in JSON: an array of objects, each with "clip" (a string as in CSV), optionally
/// "start" and "end" (integers, both or neither), and the labels as string values:
///   [{"clip": "walk_1.bvh", "action": "walk"}, {"clip": "a.bvh", "start": 0, "end": 40, …}]
/// @throws ParseError for malformed JSON and everything parse_label_csv() refuses.
LabelTable parse_label_json(std::string_view text, std::span<const std::string> paths,
                            std::span<const int> frame_counts = {},
                            const std::string& path = "<memory>");

/// Reads a label file: JSON when its first non-blank character is '[' or '{', CSV otherwise.
/// @throws Error if unreadable; ParseError as above.
LabelTable read_label_file(const std::string& path, std::span<const std::string> paths,
                           std::span<const int> frame_counts = {});

/// Adds the labels of `later` (a label file's) after those of `table` (the file names'): the rule
/// of `motionmap map --labels-from-name … --labels FILE`, and of Studio's "Labels from file…" on
/// a map that has labels. A label of `later` whose name `table` has is the same label: its spans
/// come after the table's, so they win where they cover frames (span by span) and the table's
/// values stay where they do not; the other labels of `later` join the table's names, in order.
/// Notes are appended. `source` (the file) names the table in messages.
/// @throws ParameterError if the names would be more than kMaxLabels; `table` is then unchanged.
void merge_labels(LabelTable& table, LabelTable later, const std::string& source);

/// One label of every sample: the distinct values (sorted by byte order; "" for samples no span
/// covers) and each sample's index into them.
struct LabelColumn {
  std::string name;
  std::vector<std::string> categories;
  std::vector<std::int32_t> codes;  ///< per sample
  const std::string& value(int sample) const { return categories[std::size_t(codes[sample])]; }
  /// How many samples have each category.
  std::vector<int> counts() const;
};

/// Labels per sample of a map; empty when the map has none.
struct Labels {
  std::vector<LabelColumn> columns;
  bool empty() const { return columns.empty(); }
  /// The column named `name`, or nullptr.
  const LabelColumn* find(std::string_view name) const;
};

/// The labels of each sample (clip_of[i], frame_of[i]) from `table`.
/// @throws ParameterError if clip_of and frame_of differ in size.
Labels sample_labels(const LabelTable& table, std::span<const int> clip_of,
                     std::span<const int> frame_of);

/// A table that gives each sample (clip_of[i], frame_of[i]) its value of `labels` (a saved map's
/// labels, for merge_labels()): per label and clip, one span per run of samples with the same
/// value in frame order (first and last: the run's first and last sampled frame); samples with
/// "" get none. sample_labels() of it on the same samples gives `labels` back (up to the order
/// of each column's categories, which is sorted in both). Samples of one clip and frame are
/// expected to share their values (as every map's are); where they do not, the one later in
/// frame order wins.
/// @throws ParameterError if clip_of and frame_of differ in size or a column in size from them.
LabelTable label_table(const Labels& labels, std::span<const int> clip_of,
                       std::span<const int> frame_of);

/// Checks a Labels for use with `samples` samples: sizes, codes in range, names distinct,
/// non-empty, UTF-8 and within kMaxLabelBytes (what reading a map file checks).
/// @throws ParameterError naming the label and the problem.
void check_labels(const Labels& labels, int samples);

/// Label accuracy of a map (docs/labels.md): for each label, the fraction of query frames whose
/// label wins the vote of its k nearest frames of OTHER clips, in the map and in the feature
/// space. Queries: every labelled frame, or a seeded random sample of `sample` of them.
struct LabelAccuracy {
  std::string label;
  double map = 0.0;       ///< the vote among the map's nearest neighbours
  double features = 0.0;  ///< the same vote among the nearest by the pose distance
  int queries = 0;        ///< frames voted on
  int k = 10;
};

/// label_accuracy() for each label of `labels` that has ≥ 2 values and frames in ≥ 2 clips.
/// Neighbours: by D when `features` has it, else by the distances of features.distance_input;
/// on the map by Euclidean distance of the coordinates. Unlabelled ("") frames are neither
/// queries nor neighbours. The k nearest are the k smallest distances, ties to the smaller
/// sample index; a tied vote goes to the label of the nearest neighbour among the tied labels.
/// `feature_space` false leaves the feature space's figures out (NaN; they do not depend on the
/// map: a figure of several maps of one feature set measures them once).
/// On the map and on points by the Euclidean distance, frames that cannot be among the k nearest
/// are skipped by lower bounds of their distance (a walk along sorted projections); the figures
/// are those of every frame's distance (docs/labels.md).
/// @throws ParameterError if the sizes differ or k < 1; Cancelled.
std::vector<LabelAccuracy> label_accuracy(const features::FeatureSet& features,
                                          const Eigen::MatrixXd& coordinates, const Labels& labels,
                                          int k = 10, int sample = 5000,
                                          const Control& control = {}, bool feature_space = true);

/// A CSV field: as it is, or in double quotes (quotes inside doubled) when it holds a comma, a
/// quote, a line end or leading/trailing blanks.
std::string csv_field(std::string_view text);

/// The fields of one CSV line, quotes removed ("a,b" is one field; "" inside is a quote), each
/// with the 1-based column where it starts; blanks around unquoted fields dropped.
/// @throws ParseError `path:line:col` for an unclosed quote or text after a closing quote.
std::vector<std::pair<std::string, std::size_t>> split_quoted_csv(std::string_view line,
                                                                  std::size_t line_number,
                                                                  const std::string& path);

/// "label_accuracy[action]=0.91/0.95" … for CSV comments: map / feature space, one per label.
std::string describe_label_accuracy(std::span<const LabelAccuracy> accuracy);

}  // namespace motionmap::pipeline
