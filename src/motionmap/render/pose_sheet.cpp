#include "motionmap/render/pose_sheet.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include <Eigen/Eigenvalues>
#include <QFont>
#include <QFontMetricsF>

#include "motionmap/core/error.h"
#include "motionmap/render/drawing_file.h"
#include "motionmap/render/map_plot.h"
#include "motionmap/skeleton/bones.h"
#include "motionmap/skeleton/forward_kinematics.h"

namespace motionmap::render {
namespace {

constexpr double kMargin = 16.0;
constexpr double kTitleHeight = 34.0;
constexpr double kRowTitleHeight = 22.0;
constexpr double kRowGap = 14.0;
constexpr double kCaptionHeight = 34.0;
constexpr double kCellAspect = 1.4;  // a cell's height ÷ its width

double cell_height(const PoseSheetOptions& o) {
  return kCellAspect * o.pose_px;
}

std::size_t most_poses(const std::vector<SheetRow>& rows) {
  std::size_t n = 0;
  for (const SheetRow& r : rows) n = std::max(n, r.poses.size());
  return n;
}

void check_up_axis(int up_axis) {
  if (up_axis < 0 || up_axis > 2) {
    throw ParameterError("pose sheet: up axis " + std::to_string(up_axis) + ", expected 0, 1 or 2");
  }
}

// `where` names the poses' row in messages.
void check_poses(const std::vector<SheetPose>& poses, const std::string& where) {
  for (const SheetPose& p : poses) {
    if (p.bones.empty() || !p.center.allFinite()) {
      throw ParameterError("pose sheet: a pose of " + where + " has no bone or no centre");
    }
    for (const SheetBone& b : p.bones) {
      if (!b.from.allFinite() || !b.to.allFinite()) {
        throw ParameterError("pose sheet: a bone of " + where + " has a non-finite end");
      }
    }
  }
}

void check(const std::vector<SheetRow>& rows, const PoseSheetOptions& options) {
  if (rows.empty()) throw ParameterError("pose sheet: no row to draw");
  if (options.pose_px < 32 || options.pose_px > 2000) {
    throw ParameterError("pose sheet: a pose cell of " + std::to_string(options.pose_px) +
                         " pixels, expected 32 to 2000");
  }
  check_up_axis(options.up_axis);
  for (const SheetRow& r : rows) {
    if (r.poses.empty())
      throw ParameterError("pose sheet: row '" + r.title.toStdString() + "' has no pose");
    if (r.marked.size() != r.poses.size()) {
      throw ParameterError("pose sheet: row '" + r.title.toStdString() + "' marks " +
                           std::to_string(r.marked.size()) + " map points for " +
                           std::to_string(r.poses.size()) + " poses");
    }
    for (const int m : r.marked) {
      if (m < 0 || m >= r.coords.rows()) {
        throw ParameterError("pose sheet: marked map point " + std::to_string(m) + " outside the " +
                             std::to_string(r.coords.rows()) + " of row '" + r.title.toStdString() +
                             "'");
      }
    }
    check_poses(r.poses, "row '" + r.title.toStdString() + "'");
  }
}

// The row's view: screen x along the horizontal direction of largest spread of the joints about
// their pose's root, screen depth across it.
struct View {
  int up = 1, h1 = 0, h2 = 2;
  Eigen::Vector2d across = Eigen::Vector2d::UnitX();  // in (h1, h2)
  double x(const Eigen::Vector3d& p) const { return across.x() * p[h1] + across.y() * p[h2]; }
  double depth(const Eigen::Vector3d& p) const { return -across.y() * p[h1] + across.x() * p[h2]; }
};

View row_view(const std::vector<SheetPose>& poses, int up) {
  View v;
  v.up = up;
  v.h1 = up == 0 ? 1 : 0;
  v.h2 = up == 2 ? 1 : 2;
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const SheetPose& p : poses) {
    for (const SheetBone& b : p.bones) {
      for (const Eigen::Vector3d& q : {b.from, b.to}) {
        const Eigen::Vector2d d(q[v.h1] - p.center[v.h1], q[v.h2] - p.center[v.h2]);
        cov += d * d.transpose();
      }
    }
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
  if (eig.info() == Eigen::Success && eig.eigenvalues()(1) > 0.0) {
    v.across = eig.eigenvectors().col(1).normalized();
  }
  return v;
}

void paint_pose(QPainter& p, const QRectF& area, const SheetPose& pose, const View& view,
                double scale, double ground, double depth_lo, double depth_hi) {
  const double cx = area.center().x(), base = area.bottom() - 4.0;
  const double center_x = view.x(pose.center), center_depth = view.depth(pose.center);
  auto screen = [&](const Eigen::Vector3d& q) {
    return QPointF(cx + (view.x(q) - center_x) * scale, base - (q[view.up] - ground) * scale);
  };
  std::vector<std::pair<double, const SheetBone*>> order;
  for (const SheetBone& b : pose.bones) {
    order.emplace_back(0.5 * (view.depth(b.from) + view.depth(b.to)) - center_depth, &b);
  }
  std::sort(order.begin(), order.end(),
            [](const auto& a, const auto& b) { return a.first > b.first; });
  const double span = depth_hi - depth_lo;
  for (const auto& [depth, bone] : order) {
    const double far = span > 0 ? std::clamp((depth - depth_lo) / span, 0.0, 1.0) : 0.0;
    const double pale = 0.55 * far;  // toward white
    const QColor c = bone->color;
    const QColor shade(int(std::lround(c.red() + (255 - c.red()) * pale)),
                       int(std::lround(c.green() + (255 - c.green()) * pale)),
                       int(std::lround(c.blue() + (255 - c.blue()) * pale)));
    p.setPen(QPen(shade, 3.4 - 1.4 * far, Qt::SolidLine, Qt::RoundCap));
    p.drawLine(screen(bone->from), screen(bone->to));
  }
  // The ground under the figure.
  p.setPen(QPen(QColor(200, 200, 200), 1.0));
  p.drawLine(QPointF(area.left() + 8, base + 1), QPointF(area.right() - 8, base + 1));
}

void paint_badge(QPainter& p, const QPointF& at, int number, const QColor& fill) {
  const double r = 9.0;
  p.setPen(QPen(Qt::black, 1.2));
  p.setBrush(fill);
  p.drawEllipse(at, r, r);
  p.setBrush(Qt::NoBrush);
  const bool dark = fill.lightnessF() < 0.5;
  p.setPen(dark ? Qt::white : Qt::black);
  p.drawText(QRectF(at.x() - r, at.y() - r, 2 * r, 2 * r), Qt::AlignCenter,
             QString::number(number));
}

}  // namespace

SheetPose sheet_pose(const Skeleton& skeleton, const Motion& motion,
                     const std::vector<bool>& detached, int frame) {
  const WorldPose world = forward_kinematics(skeleton, motion, frame);
  const std::vector<JointSide> sides = joint_sides(skeleton);
  SheetPose pose;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const BoneSegment& b : bone_segments(skeleton, world, detached)) {
    const Eigen::Vector3f c = side_color(sides[std::size_t(b.joint)]);
    pose.bones.push_back({b.from, b.to, QColor::fromRgbF(c.x(), c.y(), c.z())});
    sum += b.from + b.to;
  }
  if (!pose.bones.empty()) pose.center = sum / (2.0 * double(pose.bones.size()));
  char caption[64];
  std::snprintf(caption, sizeof caption, "frame %d\n%.2f s", frame, frame * motion.frame_time);
  pose.caption = QString::fromUtf8(caption);
  return pose;
}

void paint_sheet_poses(QPainter& p, const std::vector<QRectF>& figures,
                       const std::vector<SheetPose>& poses, int up_axis) {
  check_up_axis(up_axis);
  check_poses(poses, "the poses drawn");
  if (figures.size() != poses.size()) {
    throw ParameterError("pose sheet: " + std::to_string(figures.size()) + " places for " +
                         std::to_string(poses.size()) + " poses");
  }
  if (poses.empty()) return;
  const View view = row_view(poses, up_axis);
  double ground = 1e300, top = -1e300, half_width = 0.0, depth_lo = 1e300, depth_hi = -1e300;
  for (const SheetPose& pose : poses) {
    const double cx = view.x(pose.center), cd = view.depth(pose.center);
    for (const SheetBone& b : pose.bones) {
      for (const Eigen::Vector3d& q : {b.from, b.to}) {
        ground = std::min(ground, q[view.up]);
        top = std::max(top, q[view.up]);
        half_width = std::max(half_width, std::abs(view.x(q) - cx));
        depth_lo = std::min(depth_lo, view.depth(q) - cd);
        depth_hi = std::max(depth_hi, view.depth(q) - cd);
      }
    }
  }
  double figure_w = 1e300, figure_h = 1e300;
  for (const QRectF& r : figures) {
    figure_w = std::min(figure_w, r.width());
    figure_h = std::min(figure_h, r.height());
  }
  const double height = std::max(top - ground, 1e-9);
  const double scale = std::max(
      0.0,
      std::min(0.92 * figure_h / height, half_width > 0 ? 0.45 * figure_w / half_width : 1e300));
  p.save();
  p.setRenderHint(QPainter::Antialiasing);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    paint_pose(p, figures[i], poses[i], view, scale, ground, depth_lo, depth_hi);
  }
  p.restore();
}

QSize pose_sheet_size(const std::vector<SheetRow>& rows, const PoseSheetOptions& options) {
  check(rows, options);
  const double cell_h = cell_height(options);
  const double width = 2 * kMargin + cell_h + kRowGap + double(most_poses(rows)) * options.pose_px;
  const double height = 2 * kMargin + (options.title.isEmpty() ? 0.0 : kTitleHeight) +
                        double(rows.size()) * (kRowTitleHeight + cell_h + kRowGap);
  if (width * height > 1e8) {
    throw ParameterError("pose sheet: " + std::to_string(long(width)) + "×" +
                         std::to_string(long(height)) + " pixels, more than 10⁸");
  }
  return QSize(int(std::ceil(width)), int(std::ceil(height)));
}

void paint_pose_sheet(QPainter& p, const QRectF& rect, const std::vector<SheetRow>& rows,
                      const PoseSheetOptions& options) {
  check(rows, options);
  require_gui_application("paint_pose_sheet");
  p.save();
  p.setRenderHint(QPainter::Antialiasing);
  p.fillRect(rect, Qt::white);
  QFont font = p.font();
  font.setPixelSize(12);
  p.setFont(font);
  double y = rect.top() + kMargin;
  if (!options.title.isEmpty()) {
    QFont big = font;
    big.setPixelSize(16);
    big.setBold(true);
    p.setFont(big);
    p.setPen(Qt::black);
    p.drawText(QRectF(rect.left() + kMargin, y, rect.width() - 2 * kMargin, kTitleHeight - 8),
               Qt::AlignLeft | Qt::AlignVCenter, options.title);
    p.setFont(font);
    y += kTitleHeight;
  }
  const double cell_h = cell_height(options);
  for (const SheetRow& row : rows) {
    QFont bold = font;
    bold.setBold(true);
    p.setFont(bold);
    p.setPen(Qt::black);
    p.drawText(QRectF(rect.left() + kMargin, y, rect.width() - 2 * kMargin, kRowTitleHeight),
               Qt::AlignLeft | Qt::AlignVCenter, row.title);
    p.setFont(font);
    y += kRowTitleHeight;

    // The map with the key poses marked.
    const QRectF map_rect(rect.left() + kMargin, y, cell_h, cell_h);
    MapPlotOptions map_options;
    map_options.line_width = 1.5;
    paint_map(p, map_rect, row.coords, {0}, map_options);
    const QTransform to_map = map_transform(row.coords, map_rect, map_options);
    const double last = std::max<double>(1.0, double(row.coords.rows() - 1));
    for (std::size_t i = 0; i < row.poses.size(); ++i) {
      const int m = row.marked[i];
      paint_badge(p, to_map.map(QPointF(row.coords(m, 0), row.coords(m, 1))), int(i) + 1,
                  time_color(m / last));
    }

    // The poses: one view, one scale, one ground for the row.
    const double figure_h = cell_h - kCaptionHeight - 8.0;
    const double first_x = map_rect.right() + kRowGap;
    std::vector<QRectF> figures;
    for (std::size_t i = 0; i < row.poses.size(); ++i) {
      figures.emplace_back(first_x + double(i) * options.pose_px, y + 4, options.pose_px, figure_h);
    }
    paint_sheet_poses(p, figures, row.poses, options.up_axis);
    double x = first_x;
    for (std::size_t i = 0; i < row.poses.size(); ++i) {
      const QRectF cell(x, y, options.pose_px, cell_h);
      const SheetPose& pose = row.poses[i];
      paint_badge(p, QPointF(cell.left() + 12, cell.top() + 14), int(i) + 1,
                  time_color(row.marked[i] / last));
      p.setPen(QColor(60, 60, 60));
      p.drawText(QRectF(cell.left(), cell.bottom() - kCaptionHeight, cell.width(), kCaptionHeight),
                 Qt::AlignHCenter | Qt::AlignTop | Qt::TextWordWrap, pose.caption);
      if (i + 1 < row.poses.size()) {
        p.setPen(QPen(QColor(230, 230, 230), 1.0));
        p.drawLine(QPointF(cell.right(), cell.top() + 8), QPointF(cell.right(), cell.bottom() - 8));
      }
      x += options.pose_px;
    }
    y += cell_h + kRowGap;
  }
  p.restore();
}

void save_pose_sheet(const std::string& path, const std::vector<SheetRow>& rows,
                     const PoseSheetOptions& options) {
  const QSize size = pose_sheet_size(rows, options);
  write_drawing("save_pose_sheet", path, size, options.title,
                [&](QPainter& p, const QRectF& r) { paint_pose_sheet(p, r, rows, options); });
}

}  // namespace motionmap::render
