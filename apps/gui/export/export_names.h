#pragma once
// The file names the export dialogs suggest, built from what is shown: the clip's base name, the
// map's method, the frame and whether a synthesized motion plays. No widgets.
//
//   ExportNaming n{.clip = clipBaseName("/data/64_08.bvh"), .method = "isomap", .frame = 190};
//   mapFileName(n, "png");                        // "64_08-isomap.png"
//   pictureFileName(n, PictureKind::Both);        // "64_08-frame0190.png"
#include <string>

#include <QString>

namespace motionmap::studio {

/// What File → Export picture saves: the 3-D view, the map view, or both side by side (3-D view
/// left, map right, as in the window).
enum class PictureKind { View3D, Map, Both };

/// What is shown, as the names need it.
struct ExportNaming {
  QString clip;              ///< the clip's base name (clipBaseName); empty: "motion" is used
  QString method;            ///< the map's method ("isomap"); empty without a map
  int frame = 0;             ///< the frame shown
  bool synthesized = false;  ///< the synthesized motion plays (else the clip)
  QString take;              ///< the take exported or playing ("Take 1"); empty: none
};

/// What the File menu's export dialogs need to know of the window (MainWindow::exportContext).
struct ExportContext {
  ExportNaming naming;
  QString folder;    ///< where the dialogs start (the last folder used)
  int first = 0;     ///< the frames an animation covers: the motion playing, first..last
  int last = -1;     ///< −1: no motion
  double fps = 0.0;  ///< its frame rate
};

/// A clip path's file name without folder and suffix, safe in a file name: "/d/64_08.bvh" →
/// "64_08", "02_02.amc" → "02_02", "sample:swing" → "sample-swing" (characters other than
/// letters, digits, '.', '_' and '-' become '-').
QString clipBaseName(const std::string& path);
/// The map export: "64_08-isomap.<suffix>" ("64_08-map.<suffix>" without a method).
QString mapFileName(const ExportNaming& naming, const QString& suffix);
/// A synthesized motion: "64_08-Take_1.bvh" for the take "Take 1" (of its name, letters, digits,
/// '-' and '_' kept and other runs as one '_'), "64_08-synth.bvh" without a take.
QString motionFileName(const ExportNaming& naming);
/// A picture of the frame shown: both views "64_08-frame0190.png", the 3-D view
/// "64_08-3d-frame0190.png", the map "64_08-isomap-frame0190.png"; "-synth" follows the clip's
/// name while a synthesized motion plays ("64_08-synth-frame0012.png").
QString pictureFileName(const ExportNaming& naming, PictureKind kind);
/// The base name of an animation export (its images are <name>_0000.png …, its video
/// <name>.mp4): "64_08-isomap", or "64_08-synth" for a synthesized motion.
QString animationName(const ExportNaming& naming);

}  // namespace motionmap::studio
