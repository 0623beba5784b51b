// The key-pose contact sheet: its size, the bones drawn in their colours inside their cells,
// standing on one ground line, and bad inputs refused.
#include "motionmap/render/pose_sheet.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>
#include <QImage>

#include "motionmap/core/error.h"
#include "support/error_message.h"

namespace motionmap::render {
namespace {

// A stick figure standing at x = `at`: a red leg, a blue leg, a spine (y up, 170 tall).
SheetPose figure(double at, const QString& caption) {
  SheetPose p;
  const Eigen::Vector3d hips(at, 90, 0), head(at, 170, 0);
  p.bones = {{hips, Eigen::Vector3d(at - 15, 0, 0), QColor(220, 60, 50)},
             {hips, Eigen::Vector3d(at + 15, 0, 0), QColor(50, 110, 230)},
             {hips, head, QColor(200, 160, 70)}};
  p.center = hips;
  p.caption = caption;
  return p;
}

SheetRow row(int poses) {
  SheetRow r;
  r.title = "walk.bvh";
  r.coords.resize(20, 2);
  for (int i = 0; i < 20; ++i) r.coords.row(i) << i, std::sin(i * 0.3);
  for (int i = 0; i < poses; ++i) {
    r.poses.push_back(figure(100.0 * i, "frame " + QString::number(i)));
    r.marked.push_back(i * 19 / std::max(1, poses - 1));
  }
  return r;
}

bool near(QRgb a, const QColor& b, int tolerance = 40) {
  return std::abs(qRed(a) - b.red()) + std::abs(qGreen(a) - b.green()) +
             std::abs(qBlue(a) - b.blue()) <
         tolerance;
}

TEST(PoseSheet, EachPoseIsDrawnInItsCellInItsBonesColours) {
  const std::vector<SheetRow> rows{row(3), row(2)};
  PoseSheetOptions options;
  options.pose_px = 100;
  const QSize size = pose_sheet_size(rows, options);
  // Margins 16, map cell 140, gap 14, three pose cells; two rows of 22 + 140 + 14.
  EXPECT_EQ(size, QSize(16 * 2 + 140 + 14 + 300, 16 * 2 + 2 * (22 + 140 + 14)));
  QImage image(size, QImage::Format_RGB32);
  QPainter painter(&image);
  paint_pose_sheet(painter, QRectF(QPointF(0, 0), QSizeF(size)), rows, options);
  painter.end();
  // In each pose cell of the first row: red and blue leg pixels (the legs stand apart across the
  // view: the row is seen along its widest horizontal axis, x here).
  for (int cell = 0; cell < 3; ++cell) {
    const int left = 16 + 140 + 14 + 100 * cell;
    int red = 0, blue = 0;
    for (int y = 16 + 22; y < 16 + 22 + 140; ++y) {
      for (int x = left; x < left + 100; ++x) {
        red += near(image.pixel(x, y), QColor(220, 60, 50));
        blue += near(image.pixel(x, y), QColor(50, 110, 230));
      }
    }
    EXPECT_GT(red, 30) << "cell " << cell;
    EXPECT_GT(blue, 30) << "cell " << cell;
  }
}

TEST(PoseSheet, BadInputsAreRefused) {
  PoseSheetOptions options;
  EXPECT_EQ(test::error_message<ParameterError>([&] { pose_sheet_size({}, options); }),
            "pose sheet: no row to draw");
  SheetRow unmarked = row(2);
  unmarked.marked.pop_back();
  EXPECT_EQ(test::error_message<ParameterError>([&] { pose_sheet_size({unmarked}, options); }),
            "pose sheet: row 'walk.bvh' marks 1 map points for 2 poses");
  SheetRow outside = row(2);
  outside.marked.back() = 20;
  EXPECT_EQ(test::error_message<ParameterError>([&] { pose_sheet_size({outside}, options); }),
            "pose sheet: marked map point 20 outside the 20 of row 'walk.bvh'");
  SheetRow nan = row(1);
  nan.poses[0].bones[0].to.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(test::error_message<ParameterError>([&] { pose_sheet_size({nan}, options); }),
            "pose sheet: a bone of row 'walk.bvh' has a non-finite end");
  options.pose_px = 8;
  EXPECT_EQ(test::error_message<ParameterError>([&] { pose_sheet_size({row(1)}, options); }),
            "pose sheet: a pose cell of 8 pixels, expected 32 to 2000");
  EXPECT_EQ(test::error_message<Error>([&] { save_pose_sheet("sheet.gif", {row(1)}, {}); }),
            "cannot write 'sheet.gif': unknown extension '.gif' (expected .png, .svg or .pdf)");
}

TEST(PoseSheet, PosesDrawnAloneStandInTheirRectsAtOneScale) {
  // Studio's key pose strip: the figures without the sheet, each in the rect it is given.
  const std::vector<SheetPose> poses{figure(0, "a"), figure(300, "b")};
  QImage image(400, 200, QImage::Format_RGB32);
  image.fill(Qt::white);
  QPainter painter(&image);
  const std::vector<QRectF> figures{QRectF(0, 20, 200, 160), QRectF(200, 20, 200, 160)};
  paint_sheet_poses(painter, figures, poses, 1);
  painter.end();
  // Each figure in its rect: the spine's ochre in both halves, nothing drawn outside the rects;
  // one scale: the two figures, of one height, drawn equally tall.
  int heights[2] = {0, 0};
  for (int half = 0; half < 2; ++half) {
    int ochre = 0, outside = 0, highest = 200;
    for (int y = 0; y < 200; ++y) {
      for (int x = 200 * half; x < 200 * half + 200; ++x) {
        const QRgb c = image.pixel(x, y);
        ochre += near(c, QColor(200, 160, 70));
        if (c == qRgb(255, 255, 255)) continue;
        outside += y < 20 || y >= 180;
        highest = std::min(highest, y);
      }
    }
    EXPECT_GT(ochre, 30) << half;
    EXPECT_EQ(outside, 0) << half;
    heights[half] = 180 - highest;
  }
  EXPECT_NEAR(heights[0], heights[1], 1);
  EXPECT_GT(heights[0], 100);  // scaled to the rect's height, not drawn tiny
  QImage other(10, 10, QImage::Format_RGB32);
  QPainter p2(&other);
  EXPECT_EQ(
      test::error_message<ParameterError>([&] { paint_sheet_poses(p2, {figures[0]}, poses, 1); }),
      "pose sheet: 1 places for 2 poses");
  EXPECT_EQ(test::error_message<ParameterError>([&] { paint_sheet_poses(p2, figures, poses, 3); }),
            "pose sheet: up axis 3, expected 0, 1 or 2");
  p2.end();
}

}  // namespace
}  // namespace motionmap::render
