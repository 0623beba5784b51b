#pragma once
// File → Export animation: the playback written frame by frame — each frame set, rendered and
// saved, never timed by the playback clock — as an image sequence (NAME_0000.png …) and/or an
// MP4 video encoded by ffmpeg (H.264, yuv420p, the motion's frame rate), the frames piped to it as
// raw RGB through QProcess. A cancelled or failed export removes every file it wrote, so nothing
// half-written is left (the video is written as NAME.mp4.part and renamed when ffmpeg succeeds).
//
//   AnimationSettings s{.folder = "/tmp/out", .name = "64_08-isomap", .video = true};
//   AnimationResult r = writeAnimation(s, motionFrames, fps, render, progress);  // @throws Error
#include <functional>

#include <QImage>
#include <QString>
#include <QStringList>

class QWidget;

namespace motionmap::studio {

struct AnimationSettings {
  QString folder;      ///< created when missing
  QString name;        ///< NAME_0000.png …, NAME.mp4
  bool images = true;  ///< the PNG image sequence
  bool video = false;  ///< the MP4 (needs ffmpeg on PATH)
  int first = -1;      ///< the frames exported, first..last; −1: the motion's first / last frame
  int last = -1;
};

struct AnimationResult {
  int frames = 0;          ///< frames rendered
  QStringList images;      ///< the image files written, in order
  QString video;           ///< the MP4 written, or empty
  bool cancelled = false;  ///< the user cancelled: nothing is left on disk
};

/// Frames done so far and their total; return false to cancel.
using AnimationProgress = std::function<bool(int done, int total)>;
/// The picture of one frame (the window sets the frame, then renders).
using FrameRenderer = std::function<QImage(int frame)>;

/// ffmpeg's path when it is on PATH, else empty.
QString ffmpegProgram();
/// A frame rate as ffmpeg takes it: "120" for 120.0048 (a BVH's rounded frame time), "30000/1001"
/// for 29.97, else the decimal.
QString ffmpegRate(double fps);
/// The image of frame `index` (0-based within the export) of `count`: NAME_0000.png, with more
/// digits when `count` needs them, so the files sort in order.
QString sequenceFileName(const QString& name, int index, int count);

/// Renders frames settings.first..last of a motion of `motionFrames` frames and writes them as
/// `settings` asks; `fps` is the video's rate. `progress` is called before each frame and while
/// ffmpeg finishes. @throws Error (after removing what it wrote) for a range outside the motion,
/// nothing to write, a folder that cannot be created or written, ffmpeg missing, failing to start
/// or failing (with the last line ffmpeg wrote to stderr).
AnimationResult writeAnimation(const AnimationSettings& settings, int motionFrames, double fps,
                               const FrameRenderer& render, const AnimationProgress& progress);

/// The status line after an export: "Wrote 61 images (NAME_0000.png …) and NAME.mp4 to FOLDER",
/// or that it was cancelled and its files removed.
QString animationSummary(const AnimationResult& result, const AnimationSettings& settings);

/// writeAnimation with a progress dialog (window-modal over `parent`, with Cancel).
AnimationResult writeAnimationWithProgress(QWidget* parent, const AnimationSettings& settings,
                                           int motionFrames, double fps,
                                           const FrameRenderer& render);

}  // namespace motionmap::studio
