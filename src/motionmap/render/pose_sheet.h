#pragma once
// A contact sheet of key poses: one row per clip — its map trajectory with the key poses marked
// and numbered, then each key pose as a stick figure with its frame and time — as `motionmap
// keyposes -o sheet.png` writes it, and Studio's key pose strip draws its figures with
// paint_sheet_poses. Plain data in (world joint positions; sheet_pose() makes them from a clip's
// frame), QtGui only.
//
// Each row is seen from one horizontal direction, the one along which its poses' joints spread
// the most about their roots (a golf swing from the front, a walk from the side), orthographic,
// with the up axis up; all its poses at one scale, standing on one ground line; bones farther from
// the viewer than the body's centre drawn paler and first.
#include <string>
#include <vector>

#include <Eigen/Core>
#include <QColor>
#include <QPainter>
#include <QRectF>
#include <QSize>
#include <QString>

#include "motionmap/skeleton/skeleton.h"

namespace motionmap::render {

/// One bone of a key pose, in world coordinates, with its colour.
struct SheetBone {
  Eigen::Vector3d from;
  Eigen::Vector3d to;
  QColor color;
};

/// One key pose: its bones, the point put at its cell's horizontal centre (the body's centre),
/// and the caption under it ("frame 120\n1.00 s").
struct SheetPose {
  std::vector<SheetBone> bones;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  QString caption;
};

/// Frame `frame` of `motion` (of `skeleton`) as a key pose: its bones (skeleton/bones.h's
/// segments, skipping those of `detached` joints, in their body side's colour), their centre,
/// and the caption "frame F\nT s". @throws what forward_kinematics throws (a frame out of range).
SheetPose sheet_pose(const Skeleton& skeleton, const Motion& motion,
                     const std::vector<bool>& detached, int frame);

/// One clip's row.
struct SheetRow {
  QString title;                 ///< the clip's name
  std::vector<SheetPose> poses;  ///< in time order
  Eigen::MatrixXd coords;        ///< the clip's map trajectory (#samples × ≥ 2)
  std::vector<int> marked;       ///< the row of `coords` of each pose (same order)
};

struct PoseSheetOptions {
  QString title;      ///< above the rows
  int up_axis = 1;    ///< 0 x, 1 y, 2 z: the skeleton's up axis
  int pose_px = 150;  ///< width of a pose's cell (its height is 1.4 times that)
};

/// The sheet's size in pixels. @throws ParameterError for no row, a row without poses, or more
/// than 10⁸ pixels.
QSize pose_sheet_size(const std::vector<SheetRow>& rows, const PoseSheetOptions& options);

/// Draws the sheet into `rect` (of pose_sheet_size()). Needs a QGuiApplication.
/// @throws ParameterError for a pose without bones or with a non-finite point, or `marked` not
///   matching the poses; as pose_sheet_size().
void paint_pose_sheet(QPainter& painter, const QRectF& rect, const std::vector<SheetRow>& rows,
                      const PoseSheetOptions& options);

/// Draws `poses` as the sheet draws a row's figures, pose i in figures[i] (captions are the
/// caller's): one view for all (the horizontal direction of largest spread), one scale (the
/// smallest rect's size), the ground line at each rect's bottom. Antialiased; the painter's state
/// is restored. @throws ParameterError for a pose without bones or with a non-finite point, an up
/// axis other than 0, 1 or 2, or as many rects as poses not given.
void paint_sheet_poses(QPainter& painter, const std::vector<QRectF>& figures,
                       const std::vector<SheetPose>& poses, int up_axis);

/// Writes the sheet to `path` (.png, .svg or .pdf, as write_drawing()).
/// @throws as paint_pose_sheet() and write_drawing().
void save_pose_sheet(const std::string& path, const std::vector<SheetRow>& rows,
                     const PoseSheetOptions& options);

}  // namespace motionmap::render
