#include "export/animation_export.h"

#include <QCoreApplication>
#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QProcess>
#include <QProgressDialog>
#include <QStandardPaths>
#include <cmath>

#include "export/picture_export.h"
#include "motionmap/core/error.h"

namespace motionmap::studio {

namespace {

/// Bytes queued for ffmpeg's stdin before the export waits for it (a few frames).
constexpr qint64 kMaxQueuedBytes = 16 << 20;

std::string str(const QString& s) {
  return s.toStdString();
}

/// The last non-empty line of what a process wrote.
QString lastLine(const QByteArray& text) {
  const QStringList lines = QString::fromLocal8Bit(text).split('\n', Qt::SkipEmptyParts);
  for (auto it = lines.rbegin(); it != lines.rend(); ++it) {
    if (!it->trimmed().isEmpty()) return it->trimmed();
  }
  return {};
}

/// The files an export has written so far, removed unless it completes: a cancelled or failed
/// export leaves nothing behind.
class Outputs {
 public:
  ~Outputs() {
    if (m_keep) return;
    for (const QString& path : m_files) QFile::remove(path);
    if (!m_folder.isEmpty()) QDir().rmdir(m_folder);  // only when empty
  }
  void add(const QString& path) { m_files << path; }
  /// A folder the export created.
  void addFolder(const QString& path) { m_folder = path; }
  void keep() { m_keep = true; }

 private:
  QStringList m_files;
  QString m_folder;
  bool m_keep = false;
};

/// ffmpeg reading raw RGB frames on stdin and writing an H.264 MP4 to `partPath`.
class Encoder {
 public:
  Encoder(const QString& program, const QString& partPath, double fps, QSize size) : m_size(size) {
    const QStringList args = {
        "-hide_banner", "-loglevel", "error", "-y",
        // The input: raw frames as piped, at the motion's rate.
        "-f", "rawvideo", "-pixel_format", "rgb24", "-video_size",
        QStringLiteral("%1x%2").arg(size.width()).arg(size.height()), "-framerate", ffmpegRate(fps),
        "-i", "pipe:0",
        // H.264 in yuv420p: what every player and browser plays; +faststart for streaming.
        "-an", "-c:v", "libx264", "-preset", "fast", "-crf", "18", "-pix_fmt", "yuv420p",
        "-movflags", "+faststart", "-f", "mp4", partPath};
    m_process.start(program, args);
    if (!m_process.waitForStarted(10000))
      throw Error("ffmpeg (" + str(program) +
                  ") could not be started: " + str(m_process.errorString()));
  }
  ~Encoder() {
    if (m_process.state() != QProcess::NotRunning) {
      m_process.kill();
      m_process.waitForFinished(5000);
    }
  }
  QSize size() const { return m_size; }

  /// Queues one frame (already m_size, RGB888); waits while ffmpeg is behind.
  void write(const QImage& frame) {
    QByteArray bytes;
    const qsizetype row = qsizetype(m_size.width()) * 3;
    bytes.reserve(row * m_size.height());
    for (int y = 0; y < m_size.height(); ++y)
      bytes.append(reinterpret_cast<const char*>(frame.constScanLine(y)), row);
    checkRunning();
    m_process.write(bytes);
    while (m_process.bytesToWrite() > kMaxQueuedBytes) {
      m_process.waitForBytesWritten(100);
      m_stderr += m_process.readAllStandardError();
      checkRunning();
    }
    m_stderr += m_process.readAllStandardError();
  }
  /// Ends the input and waits for ffmpeg, calling `keepGoing` every 50 ms (false: cancel).
  /// True when ffmpeg wrote the video, false when cancelled; throws when ffmpeg failed.
  bool finish(const std::function<bool()>& keepGoing) {
    m_process.closeWriteChannel();
    while (!m_process.waitForFinished(50)) {
      m_stderr += m_process.readAllStandardError();
      if (m_process.state() == QProcess::NotRunning) break;
      if (!keepGoing()) return false;
    }
    m_stderr += m_process.readAllStandardError();
    if (m_process.exitStatus() != QProcess::NormalExit || m_process.exitCode() != 0) fail();
    return true;
  }

 private:
  void checkRunning() {
    if (m_process.state() != QProcess::Running) {
      m_process.waitForFinished(1000);
      fail();
    }
  }
  [[noreturn]] void fail() {
    m_stderr += m_process.readAllStandardError();
    const QString line = lastLine(m_stderr);
    const QString status = m_process.exitStatus() == QProcess::NormalExit
                               ? QStringLiteral("exit code %1").arg(m_process.exitCode())
                               : QStringLiteral("crashed");
    throw Error("ffmpeg failed (" + str(status) + ")" +
                (line.isEmpty() ? std::string() : ": " + str(line)));
  }

  QProcess m_process;
  QSize m_size;
  QByteArray m_stderr;
};

/// `result` of an export cancelled: its files are removed (Outputs), so none is listed.
AnimationResult cancelled(AnimationResult result) {
  result.cancelled = true;
  result.images.clear();
  result.video.clear();
  return result;
}

}  // namespace

QString ffmpegProgram() {
  return QStandardPaths::findExecutable(QStringLiteral("ffmpeg"));
}

QString ffmpegRate(double fps) {
  if (!(fps > 0) || !std::isfinite(fps)) throw Error("frame rate must be positive");
  const double whole = std::round(fps);
  if (std::abs(fps - whole) <= 1e-3 * fps) return QString::number(qint64(whole));
  const double ntsc = std::round(fps * 1.001);  // 29.97 = 30000/1001, 59.94, 23.976
  if (std::abs(fps - ntsc / 1.001) <= 1e-4 * fps)
    return QStringLiteral("%1/1001").arg(qint64(ntsc) * 1000);
  return QString::number(fps, 'f', 6);
}

QString sequenceFileName(const QString& name, int index, int count) {
  const int digits = std::max(4, int(QString::number(std::max(count - 1, 0)).size()));
  return QStringLiteral("%1_%2.png").arg(name).arg(index, digits, 10, QLatin1Char('0'));
}

AnimationResult writeAnimation(const AnimationSettings& settings, int motionFrames, double fps,
                               const FrameRenderer& render, const AnimationProgress& progress) {
  if (!settings.images && !settings.video)
    throw Error("nothing to export: choose the image sequence, the MP4 video or both");
  if (settings.name.trimmed().isEmpty()) throw Error("the animation needs a file name");
  if (settings.name.contains('/') || settings.name.contains('\\'))
    throw Error("the name '" + str(settings.name) + "' must not contain a folder separator");
  const int first = settings.first < 0 ? 0 : settings.first;
  const int last = settings.last < 0 ? motionFrames - 1 : settings.last;
  if (motionFrames <= 0) throw Error("there is no motion to export");
  if (first > last || last >= motionFrames)
    throw Error("frames " + std::to_string(first) + "–" + std::to_string(last) +
                " are not a range of the motion's frames 0–" + std::to_string(motionFrames - 1));
  QString program;
  if (settings.video) {
    program = ffmpegProgram();
    if (program.isEmpty())
      throw Error("MP4 needs ffmpeg (Debian package ffmpeg), which is not on PATH");
  }
  if (settings.folder.isEmpty()) throw Error("the animation needs a folder");
  const QDir dir(settings.folder);
  Outputs outputs;
  if (!dir.exists()) {
    if (!QDir().mkpath(dir.absolutePath()))
      throw Error("cannot create the folder " + str(dir.absolutePath()) +
                  " (is a part of its path a file, or not writable?)");
    outputs.addFolder(dir.absolutePath());
  }
  if (!QFileInfo(dir.absolutePath()).isWritable())
    throw Error("the folder " + str(dir.absolutePath()) + " is not writable");

  const int count = last - first + 1;
  AnimationResult result;
  std::unique_ptr<Encoder> encoder;
  const QString videoPath = dir.absoluteFilePath(settings.name + ".mp4");
  const QString partPath = videoPath + ".part";
  for (int i = 0; i < count; ++i) {
    if (!progress(i, count)) return cancelled(result);  // Outputs removes what was written
    const QImage image = render(first + i);
    if (image.isNull()) throw Error("frame " + std::to_string(first + i) + " rendered empty");
    if (settings.images) {
      const QString path = dir.absoluteFilePath(sequenceFileName(settings.name, i, count));
      outputs.add(path);
      savePicture(image, path);
      result.images << path;
    }
    if (settings.video) {
      QImage rgb = image.convertToFormat(QImage::Format_RGB888);
      if (!encoder) {
        // yuv420p halves the chroma both ways: the size must be even (a last odd column or row
        // is dropped).
        const QSize size(rgb.width() & ~1, rgb.height() & ~1);
        if (size.isEmpty()) throw Error("the picture is too small for a video");
        outputs.add(partPath);
        encoder = std::make_unique<Encoder>(program, partPath, fps, size);
      }
      if (rgb.width() >= encoder->size().width() && rgb.height() >= encoder->size().height())
        rgb = rgb.copy(QRect(QPoint(0, 0), encoder->size()));
      else  // the views were resized during the export
        rgb = rgb.scaled(encoder->size());
      encoder->write(rgb);
    }
    ++result.frames;
  }
  if (encoder) {
    if (!encoder->finish([&] { return progress(count, count); })) return cancelled(result);
    QFile::remove(videoPath);  // rename does not overwrite
    if (!QFile::rename(partPath, videoPath))
      throw Error("cannot rename " + str(partPath) + " to " + str(videoPath));
    outputs.add(videoPath);  // until the export is kept
    result.video = videoPath;
  }
  outputs.keep();
  return result;
}

QString animationSummary(const AnimationResult& result, const AnimationSettings& settings) {
  auto tr = [](const char* text, int n = -1) {
    return QCoreApplication::translate("AnimationExport", text, nullptr, n);
  };
  if (result.cancelled)
    return tr("Animation export cancelled; the files it had written were removed");
  QStringList parts;
  if (!result.images.isEmpty()) {
    parts << tr("%n images (%1 …)", int(result.images.size()))
                 .arg(QFileInfo(result.images.front()).fileName());
  }
  if (!result.video.isEmpty()) parts << QFileInfo(result.video).fileName();
  return tr("Wrote %1 to %2")
      .arg(parts.join(tr(" and ")), QFileInfo(settings.folder).absoluteFilePath());
}

AnimationResult writeAnimationWithProgress(QWidget* parent, const AnimationSettings& settings,
                                           int motionFrames, double fps,
                                           const FrameRenderer& render) {
  QProgressDialog dialog(QCoreApplication::translate("AnimationExport", "Exporting the animation…"),
                         QCoreApplication::translate("AnimationExport", "Cancel"), 0, 1, parent);
  dialog.setWindowTitle(QCoreApplication::translate("AnimationExport", "Export animation"));
  dialog.setWindowModality(Qt::WindowModal);
  dialog.setMinimumDuration(0);
  dialog.setAutoClose(false);
  dialog.setAutoReset(false);
  dialog.setToolTip(QCoreApplication::translate(
      "AnimationExport", "Cancel removes every file this export has written"));
  dialog.show();
  return writeAnimation(settings, motionFrames, fps, render, [&](int done, int total) {
    dialog.setMaximum(total);
    dialog.setValue(done);
    dialog.setLabelText(
        done < total
            ? QCoreApplication::translate("AnimationExport", "Rendering frame %1 of %2…")
                  .arg(done + 1)
                  .arg(total)
            : QCoreApplication::translate("AnimationExport", "Finishing the MP4 (ffmpeg)…"));
    QCoreApplication::processEvents();
    return !dialog.wasCanceled();
  });
}

}  // namespace motionmap::studio
