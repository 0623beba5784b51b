#include "motionmap/synth/path.h"

#include <algorithm>
#include <cmath>

#include "motionmap/core/error.h"
#include "motionmap/core/files.h"
#include "motionmap/core/format.h"
#include "motionmap/core/text_cursor.h"

namespace motionmap::synth {

namespace {

std::string row_kind(std::size_t columns) {
  return columns == 3 ? "3 values (t,x,y)" : "2 values (x,y)";
}

}  // namespace

void MapPath::validate() const {
  if (points.size() < 2) {
    throw ParameterError("path: " + std::to_string(points.size()) +
                         " point(s); at least 2 are needed");
  }
  if (!times.empty() && times.size() != points.size()) {
    throw ParameterError("path: " + std::to_string(times.size()) + " times for " +
                         std::to_string(points.size()) + " points (give one per point, or none)");
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite())
      throw ParameterError("path: point " + std::to_string(i) + " is not finite");
    if (times.empty()) continue;
    if (!std::isfinite(times[i]))
      throw ParameterError("path: the time of point " + std::to_string(i) + " is not finite");
    if (i > 0 && !(times[i] > times[i - 1])) {
      throw ParameterError("path: the time of point " + std::to_string(i) + ", " +
                           format_number(times[i]) + " s, is not after the previous point's " +
                           format_number(times[i - 1]) + " s (times must increase)");
    }
  }
}

MapPath parse_path_csv(std::string_view text, const std::string& path) {
  TextCursor cur(skip_utf8_bom(text), path);
  MapPath out;
  std::size_t columns = 0;     // 2 or 3 once the header or first row says so
  std::size_t shape_line = 0;  // the line that fixed `columns`
  std::size_t first_point_line = 0;
  bool any_content = false;
  CsvRow csv;
  while (next_csv_row(cur, csv)) {
    const std::size_t line = csv.line;
    const std::string_view row = csv.text;
    const std::vector<CsvField>& fields = csv.fields;

    if (!any_content) {
      any_content = true;
      // A first line whose first field is not a number at all is the header.
      const char* first = fields.front().text.data();
      double ignored = 0.0;
      if (!fields.front().text.empty() && parse_number(first, first + fields.front().text.size(),
                                                       ignored) == NumberStatus::NotANumber) {
        if (fields.size() != 2 && fields.size() != 3) {
          cur.fail_at(line, fields.front().column,
                      "expected a header 't,x,y' or 'x,y', found " + std::to_string(fields.size()) +
                          " fields");
        }
        const std::size_t offset = fields.size() == 3 ? 1 : 0;
        if (offset == 1) {
          const std::string t = ascii_lower(fields[0].text);
          if (t != "t" && t != "time") {
            cur.fail_at(line, fields[0].column,
                        "expected 't' or 'time' as the first header field, found '" +
                            quote_token(fields[0].text) + "'");
          }
        }
        for (std::size_t k = 0; k < 2; ++k) {
          const CsvField& f = fields[offset + k];
          if (ascii_lower(f.text) != (k == 0 ? "x" : "y")) {
            cur.fail_at(line, f.column,
                        std::string("expected '") + (k == 0 ? "x" : "y") +
                            "' in the header, found '" + quote_token(f.text) + "'");
          }
        }
        columns = fields.size();
        shape_line = line;
        continue;
      }
    }

    if (columns == 0) {
      if (fields.size() != 2 && fields.size() != 3) {
        cur.fail_at(line, 1,
                    "expected 2 (x,y) or 3 (t,x,y) values, found " + std::to_string(fields.size()));
      }
      columns = fields.size();
      shape_line = line;
    }
    if (fields.size() != columns) {
      const std::size_t col = fields.size() > columns ? fields[columns].column : row.size() + 1;
      cur.fail_at(line, col,
                  "expected " + row_kind(columns) + " as on line " + std::to_string(shape_line) +
                      ", found " + std::to_string(fields.size()));
    }
    double v[3] = {0.0, 0.0, 0.0};
    for (std::size_t k = 0; k < columns; ++k) {
      const CsvField& f = fields[k];
      if (f.text.empty()) cur.fail_at(line, f.column, "expected a number, found an empty field");
      const char* first = f.text.data();
      switch (parse_number(first, first + f.text.size(), v[k])) {
        case NumberStatus::Ok:
          break;
        case NumberStatus::NotANumber:
          cur.fail_at(line, f.column, "expected a number, found '" + quote_token(f.text) + "'");
        case NumberStatus::NotFinite:
          cur.fail_at(line, f.column,
                      "expected a finite number, found '" + quote_token(f.text) + "'");
      }
    }
    if (columns == 3) {
      if (!out.times.empty() && !(v[0] > out.times.back())) {
        cur.fail_at(line, fields[0].column,
                    "time " + format_number(v[0]) + " is not after the previous point's " +
                        format_number(out.times.back()) + " (times must increase)");
      }
      out.times.push_back(v[0]);
      out.points.emplace_back(v[1], v[2]);
    } else {
      out.points.emplace_back(v[0], v[1]);
    }
    if (out.points.size() == 1) first_point_line = line;
  }
  if (out.points.empty()) cur.fail_at(cur.line(), 1, "expected at least 2 path points, found none");
  if (out.points.size() == 1) {
    cur.fail_at(first_point_line, 1, "expected at least 2 path points, found only this one");
  }
  return out;
}

MapPath read_path_csv(const std::string& path) {
  return parse_path_csv(read_text_file(path), path);
}

MapPath timed_path(const MapPath& path, double speed) {
  path.validate();
  if (path.timed()) return path;
  if (!(speed > 0.0) || !std::isfinite(speed)) {
    throw ParameterError("speed: " + format_number(speed) +
                         " map units per second is out of range (must be > 0)");
  }
  MapPath out;
  out.points.push_back(path.points.front());
  out.times.push_back(0.0);
  for (std::size_t i = 1; i < path.points.size(); ++i) {
    const double step = (path.points[i] - out.points.back()).norm();
    if (step == 0.0) continue;
    out.points.push_back(path.points[i]);
    out.times.push_back(out.times.back() + step / speed);
  }
  if (out.points.size() < 2) {
    throw ParameterError(
        "path: all " + std::to_string(path.points.size()) +
        " points are the same map point; an untimed path must move (give times to hold a pose)");
  }
  return out;
}

std::vector<Eigen::Vector2d> resample_path(const MapPath& path, double frame_time, double speed,
                                           long long max_frames) {
  path.validate();
  if (!(frame_time > 0.0) || !std::isfinite(frame_time)) {
    throw ParameterError("fps: the frame time " + format_number(frame_time) +
                         " s is not a finite number > 0");
  }
  const MapPath timed = timed_path(path, speed);
  const std::vector<Eigen::Vector2d>& pts = timed.points;
  const std::vector<double>& times = timed.times;
  const double duration = times.back() - times.front();
  const double steps = std::floor(duration / frame_time + 1e-9);
  if (!(steps + 1.0 <= static_cast<double>(max_frames))) {
    throw ParameterError("path: " + format_number(duration) + " s at " +
                         format_number(1.0 / frame_time, 6) + " fps gives " +
                         format_number(steps + 1.0) + " frames, more than the limit of " +
                         std::to_string(max_frames));
  }
  const auto count = static_cast<std::size_t>(steps) + 1;
  std::vector<Eigen::Vector2d> out(count);
  std::size_t seg = 0;
  for (std::size_t k = 0; k < count; ++k) {
    const double t = times.front() + static_cast<double>(k) * frame_time;
    while (seg + 2 < times.size() && t > times[seg + 1]) ++seg;
    const double a = std::clamp((t - times[seg]) / (times[seg + 1] - times[seg]), 0.0, 1.0);
    // (1 − a)·p0 + a·p1 is exact at both ends, so a path timed like a clip hits its samples.
    out[k] = (1.0 - a) * pts[seg] + a * pts[seg + 1];
  }
  return out;
}

}  // namespace motionmap::synth
