#include "motionmap/synth/path.h"

#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "support/error_message.h"

namespace motionmap::synth {
namespace {

// The ParseError message of parsing `text`, or "no error".
std::string parse_message(const std::string& text) {
  return motionmap::test::error_message<ParseError>([&] { parse_path_csv(text, "p.csv"); });
}

std::string parameter_message(const std::function<void()>& f) {
  return motionmap::test::error_message<ParameterError>(f);
}

TEST(SynthPath, ParsesTimedRowsWithHeader) {
  const MapPath p = parse_path_csv("t,x,y\n0,1.5,-2\n0.25, 2 ,-1e-1\n1,+3,.5\n");
  ASSERT_TRUE(p.timed());
  ASSERT_EQ(p.points.size(), 3u);
  EXPECT_EQ(p.times, (std::vector<double>{0.0, 0.25, 1.0}));
  EXPECT_EQ(p.points[0], Eigen::Vector2d(1.5, -2));
  EXPECT_EQ(p.points[1], Eigen::Vector2d(2, -0.1));
  EXPECT_EQ(p.points[2], Eigen::Vector2d(3, 0.5));
}

TEST(SynthPath, ParsesUntimedRowsCommentsBlankLinesAndLineEnds) {
  const MapPath p = parse_path_csv("# a sketch\r\n\r\nX , Y\r\n1,2\r\n  \r\n3,4\r5,6");
  EXPECT_FALSE(p.timed());
  ASSERT_EQ(p.points.size(), 3u);
  EXPECT_EQ(p.points[2], Eigen::Vector2d(5, 6));
  const MapPath q = parse_path_csv("Time,x,y\n0,0,0\n1,1,1\n");
  EXPECT_EQ(q.times.size(), 2u);
  const MapPath r = parse_path_csv("0,0,0\n2,1,1\n");  // no header
  const MapPath bom =
      parse_path_csv("\xEF\xBB\xBFt,x,y\n0,0,0\n1,1,1\n");  // as spreadsheets save it
  EXPECT_EQ(bom.points.size(), 2u);
  EXPECT_EQ(r.times, (std::vector<double>{0.0, 2.0}));
}

TEST(SynthPath, ReportsMalformedInputWithItsPosition) {
  EXPECT_EQ(parse_message(""), "p.csv:1:1: error: expected at least 2 path points, found none");
  EXPECT_EQ(parse_message("t,x,y\n\n"),
            "p.csv:3:1: error: expected at least 2 path points, found none");
  EXPECT_EQ(parse_message("t,x,y\n0,1,2\n"),
            "p.csv:2:1: error: expected at least 2 path points, found only this one");
  EXPECT_EQ(parse_message("x,y\n1,2\n3,abc\n"), "p.csv:3:3: error: expected a number, found 'abc'");
  EXPECT_EQ(parse_message("x,y\n1,2\n3, nan\n"),
            "p.csv:3:4: error: expected a finite number, found 'nan'");
  EXPECT_EQ(parse_message("1,2\ninf,2\n"),
            "p.csv:2:1: error: expected a finite number, found 'inf'");
  EXPECT_EQ(parse_message("1,2\n1e999,2\n"),
            "p.csv:2:1: error: expected a finite number, found '1e999'");
  EXPECT_EQ(
      parse_message("t,x,y\n0,1,2\n0.5,1,2\n0.4,1,2\n"),
      "p.csv:4:1: error: time 0.4 is not after the previous point's 0.5 (times must increase)");
  EXPECT_EQ(parse_message("0,1,2\n0,1,3\n"),
            "p.csv:2:1: error: time 0 is not after the previous point's 0 (times must increase)");
  EXPECT_EQ(parse_message("t,x,y\n0,1,2\n1,2\n"),
            "p.csv:3:4: error: expected 3 values (t,x,y) as on line 1, found 2");
  EXPECT_EQ(parse_message("1,2\n3,4,5\n"),
            "p.csv:2:5: error: expected 2 values (x,y) as on line 1, found 3");
  EXPECT_EQ(parse_message("1,2,3,4\n"),
            "p.csv:1:1: error: expected 2 (x,y) or 3 (t,x,y) values, found 4");
  EXPECT_EQ(parse_message("1,,2\n"), "p.csv:1:3: error: expected a number, found an empty field");
  EXPECT_EQ(parse_message("a,b,c\n"),
            "p.csv:1:1: error: expected 't' or 'time' as the first header field, found 'a'");
  EXPECT_EQ(parse_message("x,z\n"), "p.csv:1:3: error: expected 'y' in the header, found 'z'");
  EXPECT_EQ(parse_message("y,x\n"), "p.csv:1:1: error: expected 'x' in the header, found 'y'");
  EXPECT_EQ(parse_message("hello\n"),
            "p.csv:1:1: error: expected a header 't,x,y' or 'x,y', found 1 fields");
  EXPECT_EQ(parse_message("x,y\nx,y\n"), "p.csv:2:1: error: expected a number, found 'x'");
  EXPECT_EQ(parse_message(std::string("1,2\n3,\x01\n")),
            "p.csv:2:3: error: expected a number, found '\\x01'");
}

TEST(SynthPath, ParseErrorCarriesLineAndColumn) {
  try {
    parse_path_csv("x,y\n0,0\n1,q\n", "sketch.csv");
    FAIL() << "no error";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.path(), "sketch.csv");
    EXPECT_EQ(e.line(), 3u);
    EXPECT_EQ(e.column(), 3u);
  }
}

TEST(SynthPath, ReadsFiles) {
  const auto file = std::filesystem::temp_directory_path() / "motionmap_synth_path_test.csv";
  {
    std::ofstream out(file);
    out << "t,x,y\n0,0,0\n0.5,1,0\n";
  }
  const MapPath p = read_path_csv(file.string());
  EXPECT_EQ(p.points.size(), 2u);
  std::filesystem::remove(file);
  EXPECT_THROW(
      read_path_csv(
          (std::filesystem::temp_directory_path() / "motionmap_no_such_path.csv").string()),
      Error);
}

TEST(SynthPath, ValidateNamesTheOffendingPoint) {
  MapPath p;
  EXPECT_EQ(parameter_message([&] { p.validate(); }), "path: 0 point(s); at least 2 are needed");
  p.points = {{0, 0}};
  EXPECT_EQ(parameter_message([&] { p.validate(); }), "path: 1 point(s); at least 2 are needed");
  p.points = {{0, 0}, {1, NAN}};
  EXPECT_EQ(parameter_message([&] { p.validate(); }), "path: point 1 is not finite");
  p.points = {{0, 0}, {1, 1}, {2, 2}};
  p.times = {0, 1};
  EXPECT_EQ(parameter_message([&] { p.validate(); }),
            "path: 2 times for 3 points (give one per point, or none)");
  p.times = {0, 1, 1};
  EXPECT_EQ(parameter_message([&] { p.validate(); }),
            "path: the time of point 2, 1 s, is not after the previous point's 1 s (times must "
            "increase)");
  p.times = {0, NAN, 1};
  EXPECT_EQ(parameter_message([&] { p.validate(); }), "path: the time of point 1 is not finite");
  p.times = {0, 1, 2};
  EXPECT_NO_THROW(p.validate());
}

TEST(SynthPath, ResamplesTimedPathsLinearly) {
  MapPath p;
  p.points = {{0, 0}, {1, 0}, {1, 2}};
  p.times = {1.0, 1.5, 2.5};
  const auto pts = resample_path(p, 0.25);
  ASSERT_EQ(pts.size(), 7u);  // 1.0, 1.25, …, 2.5
  EXPECT_EQ(pts[0], Eigen::Vector2d(0, 0));
  EXPECT_EQ(pts[1], Eigen::Vector2d(0.5, 0));
  EXPECT_EQ(pts[2], Eigen::Vector2d(1, 0));
  EXPECT_EQ(pts[3], Eigen::Vector2d(1, 0.5));
  EXPECT_EQ(pts[6], Eigen::Vector2d(1, 2));
  // A path timed like a clip (t = i·frame_time) gives its points back exactly.
  MapPath clip_like;
  const double ft = 1.0 / 120;
  for (int i = 0; i < 500; ++i) {
    clip_like.points.emplace_back(std::sin(0.01 * i), std::cos(0.013 * i));
    clip_like.times.push_back(i * ft);
  }
  const auto again = resample_path(clip_like, ft);
  ASSERT_EQ(again.size(), 500u);
  for (int i = 0; i < 500; ++i) EXPECT_EQ(again[i], clip_like.points[i]) << i;
}

TEST(SynthPath, ResamplesUntimedPathsAtASpeed) {
  MapPath p;
  p.points = {{0, 0}, {3, 4}, {3, 4}, {3, 6}};  // lengths 5, 0 (repeat skipped), 2
  const auto pts = resample_path(p, 0.5, 2.0);  // 1 unit per frame, 7 units
  ASSERT_EQ(pts.size(), 8u);
  EXPECT_NEAR((pts[1] - Eigen::Vector2d(0.6, 0.8)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((pts[5] - Eigen::Vector2d(3, 4)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((pts[7] - Eigen::Vector2d(3, 6)).norm(), 0.0, 1e-12);
}

TEST(SynthPath, ResampleRejectsBadArguments) {
  MapPath still;
  still.points = {{1, 1}, {1, 1}, {1, 1}};
  EXPECT_EQ(parameter_message([&] { resample_path(still, 0.1, 1.0); }),
            "path: all 3 points are the same map point; an untimed path must move (give times to "
            "hold a pose)");
  still.times = {0, 1, 2};  // timed: holds the pose
  EXPECT_EQ(resample_path(still, 0.5).size(), 5u);
  MapPath p;
  p.points = {{0, 0}, {1, 0}};
  EXPECT_EQ(parameter_message([&] { resample_path(p, 0.1, 0.0); }),
            "speed: 0 map units per second is out of range (must be > 0)");
  EXPECT_EQ(parameter_message([&] { resample_path(p, 0.0, 1.0); }),
            "fps: the frame time 0 s is not a finite number > 0");
  EXPECT_EQ(parameter_message([&] { resample_path(p, 0.1, 1e-6, 1000); }),
            "path: 1000000 s at 10 fps gives 10000001 frames, more than the limit of 1000");
  // CMU's BVH frame time, 0.0083333 s: the rate said as 120, not 120.00048000192001.
  MapPath timed = p;
  timed.times = {0.0, 10.0};
  EXPECT_EQ(parameter_message([&] { resample_path(timed, 0.0083333, 0.0, 100); }),
            "path: 10 s at 120 fps gives 1201 frames, more than the limit of 100");
  EXPECT_EQ(parameter_message([&] { resample_path(MapPath{}, 0.1, 1.0); }),
            "path: 0 point(s); at least 2 are needed");
}

}  // namespace
}  // namespace motionmap::synth
