#pragma once
// A path on a motion map: the points a user sketched, with or without times, and its CSV form.
//
//   auto path = motionmap::synth::read_path_csv("sketch.csv");   // t,x,y or x,y rows
//   auto frames = motionmap::synth::resample_path(path, 1.0 / 120, speed);  // a point per frame
//
// CSV: one point per line, fields separated by commas (blanks around them ignored), either
// `t,x,y` (t in seconds, strictly increasing) or `x,y`. An optional header names the columns
// exactly `t,x,y` (or `time,x,y`) or `x,y`, case ignored. Blank lines and lines starting with '#'
// are skipped; LF, CRLF and CR line ends and a leading UTF-8 byte-order mark are accepted.
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

namespace motionmap::synth {

struct MapPath {
  std::vector<Eigen::Vector2d> points;  ///< map points in drawing order
  /// Seconds, one per point, strictly increasing; empty for an untimed path (drawn at a speed).
  std::vector<double> times;

  bool timed() const { return !times.empty(); }
  /// Checks the path can be followed: ≥ 2 points, finite coordinates and times, times (if any)
  /// one per point and strictly increasing.
  /// @throws ParameterError naming the first offending point (0-based) and what is wrong.
  void validate() const;
};

/// Parses path CSV text (format above). `path` is only used in messages.
/// @throws ParseError `path:line:col: error: …` for a malformed header, a field that is not a
///         finite number, a row with another field count than the first, a time not after the
///         previous row's, and for a file with fewer than 2 points.
MapPath parse_path_csv(std::string_view text, const std::string& path = "<memory>");

/// Reads and parses a path CSV file. @throws Error if unreadable, ParseError as above.
MapPath read_path_csv(const std::string& path);

/// The path with a time per point: a timed path as it is; an untimed one drawn at `speed` map
/// units per second from t = 0, consecutive repeated points skipped.
/// @throws ParameterError for an invalid path (see MapPath::validate), an untimed path whose
///         points all coincide, or (untimed paths) speed not a finite number > 0.
MapPath timed_path(const MapPath& path, double speed);

/// The path's points at times t0, t0 + frame_time, … up to its end (t0: its first time, or 0),
/// linearly interpolated between consecutive points: ⌊duration / frame_time + 1e-9⌋ + 1 points.
/// An untimed path is drawn at `speed` map units per second from t = 0 (consecutive repeated
/// points are skipped).
/// @throws ParameterError for an invalid path (see MapPath::validate), an untimed path whose
///         points all coincide, frame_time or (untimed paths) speed not a finite number > 0, or
///         more than `max_frames` points.
std::vector<Eigen::Vector2d> resample_path(const MapPath& path, double frame_time,
                                           double speed = 0.0, long long max_frames = 360000);

}  // namespace motionmap::synth
