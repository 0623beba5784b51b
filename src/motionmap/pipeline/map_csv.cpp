#include "motionmap/pipeline/map_csv.h"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <limits>
#include <set>

#include "motionmap/core/error.h"
#include "motionmap/core/files.h"
#include "motionmap/core/text_cursor.h"

namespace motionmap::pipeline {

void MapTable::check_matches(const features::FeatureSet& samples) const {
  if (num_rows() != samples.num_samples()) {
    throw ParameterError(
        path + ": " + std::to_string(num_rows()) + " map rows, but the clips give " +
        std::to_string(samples.num_samples()) +
        " samples with these options (frames, stride, bind pose, files): not a map of "
        "these clips; compute it with the same options, or leave out --map");
  }
  for (int i = 0; i < num_rows(); ++i) {
    if (clip_of[i] != samples.clip_of[i] || frame_of[i] != samples.frame_of[i]) {
      throw ParameterError(
          path + ":" + std::to_string(lines[i]) + ": row " + std::to_string(i + 1) + " is clip " +
          std::to_string(clip_of[i]) + " frame " + std::to_string(frame_of[i]) +
          ", but the clips' sample " + std::to_string(i + 1) + " is clip " +
          std::to_string(samples.clip_of[i]) + " frame " + std::to_string(samples.frame_of[i]) +
          ": not a map of these clips with these options");
    }
  }
}

void write_map_csv(std::ostream& out, const ClipMap& map, const ClipMapOptions& options,
                   std::span<const std::string> files, const Labels* labels,
                   std::span<const LabelAccuracy> accuracy) {
  if (labels) check_labels(*labels, map.features->num_samples());
  out << "# motionmap map " << describe_parameters(map.embedding, options);
  out << " files=";
  for (std::size_t i = 0; i < files.size(); ++i) out << (i ? "," : "") << base_name(files[i]);
  out << '\n';
  for (const auto& note : map.features->notes) out << "# note: " << note << '\n';
  for (const auto& note : map.embedding.notes) out << "# note: " << note << '\n';
  for (const auto& w : map.embedding.warnings) out << "# warning: " << w << '\n';
  if (map.metrics) out << "# metrics " << describe_metrics(*map.metrics) << '\n';
  if (!accuracy.empty()) {
    out << "# label accuracy (map/features, " << accuracy.front().k
        << "-NN vote among other clips' frames) " << describe_label_accuracy(accuracy) << '\n';
  }
  const bool several = map.features->segment_starts.size() > 1;
  const auto& Y = map.embedding.coordinates;
  out << (several ? "clip,frame,x,y" : "frame,x,y") << (Y.cols() == 3 ? ",z" : "");
  if (labels) {
    for (const LabelColumn& column : labels->columns) out << ',' << csv_field(column.name);
  }
  out << '\n';
  // Each label's categories quoted once.
  std::vector<std::vector<std::string>> quoted;
  if (labels) {
    for (const LabelColumn& column : labels->columns) {
      quoted.emplace_back();
      for (const std::string& value : column.categories) quoted.back().push_back(csv_field(value));
    }
  }
  char buf[32];
  for (Eigen::Index i = 0; i < Y.rows(); ++i) {
    if (several) out << map.features->clip_of[i] << ',';
    out << map.features->frame_of[i];
    for (Eigen::Index c = 0; c < Y.cols(); ++c) {
      std::snprintf(buf, sizeof buf, ",%.17g", Y(i, c));
      out << buf;
    }
    for (std::size_t l = 0; l < quoted.size(); ++l) {
      out << ',' << quoted[l][std::size_t(labels->columns[l].codes[std::size_t(i)])];
    }
    out << '\n';
  }
}

MapTable parse_map_csv(std::string_view text, const std::string& path) {
  TextCursor cur(skip_utf8_bom(text), path);
  MapTable table;
  table.path = path;
  bool has_clip = false;
  std::size_t columns = 0;                             // set by the header
  std::size_t coordinate_end = 0;                      // fields before the label columns
  std::vector<std::vector<std::string>> label_values;  // per label column, per row
  std::vector<double> values;
  CsvRow csv;
  while (next_csv_row(cur, csv)) {
    const std::size_t line = csv.line;
    const std::string_view row = csv.text;
    const std::vector<CsvField>& raw_fields = csv.fields;

    if (columns == 0) {
      // The map's own columns, then labels.
      const auto named = split_quoted_csv(row, line, path);
      std::size_t own = 0;
      while (own < named.size()) {
        const std::string name = ascii_lower(named[own].first);
        if (name != "clip" && name != "frame" && name != "x" && name != "y" && name != "z") break;
        ++own;
      }
      std::string header;
      for (std::size_t f = 0; f < own; ++f) {
        header += (header.empty() ? "" : ",") + ascii_lower(named[f].first);
      }
      for (std::size_t f = own; f < named.size(); ++f) {
        LabelColumn column;
        column.name = named[f].first;
        table.labels.columns.push_back(std::move(column));
        label_values.emplace_back();
      }
      if (header == "frame,x,y" || header == "frame,x,y,z") {
        has_clip = false;
      } else if (header == "clip,frame,x,y" || header == "clip,frame,x,y,z") {
        has_clip = true;
      } else {
        cur.fail_at(
            line, 1,
            "expected the header of a map (frame,x,y or clip,frame,x,y, with ,z in 3-D), found '" +
                quote_token(row) + "'");
      }
      coordinate_end = own;
      for (std::size_t f = own; f < named.size(); ++f) {
        for (std::size_t g = 0; g < f; ++g) {
          if (named[g].first == named[f].first) {
            cur.fail_at(line, named[f].second,
                        "duplicate column '" + quote_token(named[f].first) + "'");
          }
        }
      }
      try {
        check_labels(table.labels, 0);
      } catch (const ParameterError& e) {
        cur.fail_at(line, named[own].second,
                    std::string("expected label columns after the map's: ") + e.what());
      }
      columns = named.size();
      continue;
    }
    std::vector<CsvField> quoted_fields;
    std::vector<std::pair<std::string, std::size_t>> unquoted;
    const std::vector<CsvField>* row_fields = &raw_fields;
    if (!label_values.empty()) {
      // Label values may be quoted (csv_field()): split the row honouring quotes.
      unquoted = split_quoted_csv(row, line, path);
      for (const auto& [text, column] : unquoted) quoted_fields.push_back({text, column});
      row_fields = &quoted_fields;
    }
    const std::vector<CsvField>& fields = *row_fields;
    if (fields.size() != columns) {
      const std::size_t col = fields.size() > columns ? fields[columns].column : row.size() + 1;
      cur.fail_at(line, col,
                  "expected " + std::to_string(columns) + " fields as in the header, found " +
                      std::to_string(fields.size()));
    }
    const std::size_t ids = has_clip ? 2 : 1;
    int id[2] = {0, 0};
    for (std::size_t k = 0; k < ids; ++k) {
      const CsvField& f = fields[k];
      const char* end = f.text.data() + f.text.size();
      const auto [ptr, ec] = std::from_chars(f.text.data(), end, id[k]);
      if (f.text.empty() || ec != std::errc() || ptr != end || id[k] < 0) {
        cur.fail_at(line, f.column,
                    std::string("expected a ") + (k + 1 == ids ? "frame" : "clip") +
                        " number (an integer ≥ 0), found '" + quote_token(f.text) + "'");
      }
    }
    for (std::size_t k = coordinate_end; k < columns; ++k) {
      label_values[k - coordinate_end].emplace_back(fields[k].text);
    }
    for (std::size_t k = ids; k < coordinate_end; ++k) {
      const CsvField& f = fields[k];
      double v = 0.0;
      const char* first = f.text.data();
      const auto status =
          f.text.empty() ? NumberStatus::NotANumber : parse_number(first, first + f.text.size(), v);
      if (status != NumberStatus::Ok) {
        cur.fail_at(line, f.column,
                    "expected a finite coordinate, found '" + quote_token(f.text) + "'");
      }
      values.push_back(v);
    }
    table.clip_of.push_back(has_clip ? id[0] : 0);
    table.frame_of.push_back(id[ids - 1]);
    table.lines.push_back(line);
  }
  if (columns == 0)
    cur.fail_at(cur.line(), 1,
                "expected the header of a map (frame,x,y or clip,frame,x,y), found none");
  if (table.frame_of.empty())
    cur.fail_at(cur.line(), 1, "expected map rows after the header, found none");
  const auto dims = static_cast<Eigen::Index>(coordinate_end - (has_clip ? 2 : 1));
  for (std::size_t l = 0; l < label_values.size(); ++l) {
    LabelColumn& column = table.labels.columns[l];
    const std::set<std::string> distinct(label_values[l].begin(), label_values[l].end());
    column.categories.assign(distinct.begin(), distinct.end());
    for (const std::string& value : label_values[l]) {
      column.codes.push_back(
          std::int32_t(std::lower_bound(column.categories.begin(), column.categories.end(), value) -
                       column.categories.begin()));
    }
  }
  try {
    check_labels(table.labels, table.num_rows());
  } catch (const ParameterError& e) {
    cur.fail_at(table.lines.front(), 1, e.what());
  }
  table.coords =
      Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
          values.data(), table.num_rows(), dims);
  return table;
}

MapTable read_map_csv(const std::string& path) {
  return parse_map_csv(read_text_file(path), path);
}

}  // namespace motionmap::pipeline
