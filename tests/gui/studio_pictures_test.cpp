// File → Export picture and File → Export animation (offscreen; the OpenGL 3-D view's pictures are
// checked in gl_render_xvfb.cpp): the pictures of each kind and their sizes, the image sequence
// over a frame range, the MP4 checked with ffprobe, Cancel and errors leaving nothing behind, the
// dialogs without ffmpeg, and the file names the export dialogs suggest.
#include <gtest/gtest.h>

#include <unistd.h>
#include <QAbstractButton>
#include <QApplication>
#include <QCheckBox>
#include <QDialogButtonBox>
#include <QDir>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QImage>
#include <QLabel>
#include <QLineEdit>
#include <QProcess>
#include <QProgressDialog>
#include <QPushButton>
#include <QRadioButton>
#include <QSettings>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QTest>
#include <QTimer>
#include <functional>

#include "app/file_menu.h"
#include "app/main_window.h"
#include "export/animation_export.h"
#include "export/export_dialogs.h"
#include "export/export_names.h"
#include "export/picture_export.h"
#include "map/map_view.h"
#include "scene/skeleton_view.h"
#include "studio_test_util.h"

namespace motionmap::studio {
namespace {

using testing::kTimeoutMs;
using testing::pathAlong;
using testing::swing;

/// A shown window with the sample swing (`seconds` long) and its Isomap map; small, so that an
/// animation of every frame stays quick.
std::unique_ptr<MainWindow> smallWindow(double seconds = 2.0, QSize size = QSize(640, 360)) {
  auto w = std::make_unique<MainWindow>();
  w->setInteractive(false);
  w->resize(size);
  w->show();
  w->setMethod(embed::Method::Isomap);
  w->openClip(swing(seconds));
  EXPECT_TRUE(
      QTest::qWaitFor([&] { return w->currentMap() != nullptr || !w->isComputing(); }, kTimeoutMs));
  EXPECT_NE(w->currentMap(), nullptr) << w->lastError().toStdString();
  return w;
}

/// Pixels of a saturated colour (the skeleton's bones and joints; the background and grid are
/// gray).
int saturatedPixels(const QImage& image) {
  int n = 0;
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) {
      const QRgb c = image.pixel(x, y);
      if (std::max({qRed(c), qGreen(c), qBlue(c)}) - std::min({qRed(c), qGreen(c), qBlue(c)}) > 40)
        ++n;
    }
  }
  return n;
}

/// Pixels where red (or blue) clearly dominates: the trajectory's start and end colours.
std::pair<int, int> redAndBluePixels(const QImage& image) {
  int red = 0, blue = 0;
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) {
      const QRgb c = image.pixel(x, y);
      if (qRed(c) > qGreen(c) + 80 && qRed(c) > qBlue(c) + 80) ++red;
      if (qBlue(c) > qRed(c) + 80 && qBlue(c) > qGreen(c) + 30) ++blue;
    }
  }
  return {red, blue};
}

QImage rgb32(const QImage& image) {
  return image.convertToFormat(QImage::Format_RGB32);
}

/// Runs `answer` on the next modal dialog of type D (polled every 5 ms), as a user would.
template <typename D>
struct DialogAnswerer {
  int seen = 0;
  QTimer timer;
  explicit DialogAnswerer(std::function<void(D*)> answer) {
    timer.setInterval(5);
    QObject::connect(&timer, &QTimer::timeout, [this, answer] {
      if (auto* d = qobject_cast<D*>(QApplication::activeModalWidget())) {
        ++seen;
        answer(d);
      }
    });
    timer.start();
  }
};

/// Files in `dir` (names, sorted).
QStringList filesIn(const QString& dir) {
  return QDir(dir).entryList(QDir::Files | QDir::Dirs | QDir::NoDotAndDotDot, QDir::Name);
}

/// PATH replaced while it lives (ffmpeg found or not, a fake one first).
struct PathOverride {
  QByteArray saved = qgetenv("PATH");
  explicit PathOverride(const QByteArray& path) { qputenv("PATH", path); }
  ~PathOverride() { qputenv("PATH", saved); }
};

TEST(StudioExportNames, AreSuggestedFromTheClipMethodAndFrame) {
  EXPECT_EQ(clipBaseName("/data/cmu/64_08.bvh"), "64_08");
  EXPECT_EQ(clipBaseName("asfamc/02_02.amc"), "02_02");
  EXPECT_EQ(clipBaseName("sample:swing"), "sample-swing");
  EXPECT_EQ(clipBaseName("/d/BandaiNamcoResearchInc_dataset-1_walk_normal_001.bvh"),
            "BandaiNamcoResearchInc_dataset-1_walk_normal_001");
  ExportNaming n{"64_08", "isomap", 190, false, {}};
  EXPECT_EQ(mapFileName(n, "png"), "64_08-isomap.png");
  EXPECT_EQ(mapFileName(n, "csv"), "64_08-isomap.csv");
  EXPECT_EQ(motionFileName(n), "64_08-synth.bvh");
  EXPECT_EQ(pictureFileName(n, PictureKind::Both), "64_08-frame0190.png");
  EXPECT_EQ(pictureFileName(n, PictureKind::View3D), "64_08-3d-frame0190.png");
  EXPECT_EQ(pictureFileName(n, PictureKind::Map), "64_08-isomap-frame0190.png");
  EXPECT_EQ(animationName(n), "64_08-isomap");
  n.synthesized = true;
  n.frame = 12;
  EXPECT_EQ(pictureFileName(n, PictureKind::Both), "64_08-synth-frame0012.png");
  EXPECT_EQ(pictureFileName(n, PictureKind::Map), "64_08-isomap-synth-frame0012.png");
  EXPECT_EQ(animationName(n), "64_08-synth");
  // Nothing known: still a usable name.
  EXPECT_EQ(mapFileName(ExportNaming{}, "svg"), "motion-map.svg");
  EXPECT_EQ(pictureFileName(ExportNaming{}, PictureKind::Both), "motion-frame0000.png");
}

TEST(StudioExportNames, SequenceNamesAndFfmpegRates) {
  EXPECT_EQ(sequenceFileName("walk", 0, 365), "walk_0000.png");
  EXPECT_EQ(sequenceFileName("walk", 364, 365), "walk_0364.png");
  EXPECT_EQ(sequenceFileName("walk", 7, 12000), "walk_00007.png");  // they sort in order
  EXPECT_EQ(ffmpegRate(120.0), "120");
  EXPECT_EQ(ffmpegRate(1.0 / 0.008333), "120");  // a BVH's rounded frame time
  EXPECT_EQ(ffmpegRate(1.0 / 0.0333333), "30");
  EXPECT_EQ(ffmpegRate(30000.0 / 1001.0), "30000/1001");
  EXPECT_EQ(ffmpegRate(12.5), "12.500000");
}

TEST(StudioPictures, EachKindHasTheViewsSizesAndContent) {
  auto w = smallWindow(2.0, QSize(1000, 600));
  w->setFrame(120);
  QTemporaryDir dir;
  const QSize view = w->skeletonView()->size(), map = w->mapView()->size();
  ASSERT_GT(view.width(), 100);
  ASSERT_GT(map.width(), 100);

  ASSERT_TRUE(w->exportPicture(dir.filePath("3d.png"), PictureKind::View3D))
      << w->lastError().toStdString();
  ASSERT_TRUE(w->exportPicture(dir.filePath("map.png"), PictureKind::Map));
  ASSERT_TRUE(w->exportPicture(dir.filePath("both.png"), PictureKind::Both));
  EXPECT_TRUE(w->statusText().contains("both.png")) << w->statusText().toStdString();
  const QImage view3d = rgb32(QImage(dir.filePath("3d.png")));
  const QImage mapImage = rgb32(QImage(dir.filePath("map.png")));
  const QImage both = rgb32(QImage(dir.filePath("both.png")));
  ASSERT_FALSE(view3d.isNull());
  ASSERT_FALSE(mapImage.isNull());
  ASSERT_FALSE(both.isNull());
  EXPECT_EQ(view3d.size(), view);
  EXPECT_EQ(mapImage.size(), map);
  // Both: the two side by side, 3-D view left, the map right.
  EXPECT_EQ(both.size(), QSize(view.width() + map.width(), std::max(view.height(), map.height())));
  EXPECT_EQ(both.copy(QRect(QPoint(0, 0), view)), view3d);
  EXPECT_EQ(both.copy(QRect(QPoint(view.width(), 0), map)), mapImage);

  // The 3-D picture shows the skeleton (not a blank background), and the pose shown.
  EXPECT_GT(saturatedPixels(view3d), 200);
  w->setFrame(0);
  EXPECT_NE(rgb32(w->renderPicture(PictureKind::View3D)), view3d);
  // The map picture has the trajectory's colours, red at the start to blue at the end.
  const auto [red, blue] = redAndBluePixels(mapImage);
  EXPECT_GT(red, 30);
  EXPECT_GT(blue, 30);
  // …and its pointer on the frame shown: the map picture changes with the frame.
  EXPECT_NE(rgb32(w->renderPicture(PictureKind::Map)), mapImage);
}

TEST(StudioPictures, AFolderThatCannotHoldThePictureIsAClearError) {
  auto w = smallWindow(0.5);
  QTemporaryDir dir;
  QFile file(dir.filePath("a-file"));
  ASSERT_TRUE(file.open(QIODevice::WriteOnly));
  file.close();
  EXPECT_FALSE(w->exportPicture(dir.filePath("a-file/picture.png"), PictureKind::Both));
  EXPECT_TRUE(w->lastError().contains("does not exist")) << w->lastError().toStdString();
  EXPECT_TRUE(w->lastError().contains("a-file/picture.png")) << w->lastError().toStdString();
  EXPECT_FALSE(w->exportPicture(dir.filePath("missing/picture.png"), PictureKind::Map));
  EXPECT_TRUE(w->statusText().startsWith("Error: cannot write")) << w->statusText().toStdString();
  if (geteuid() != 0) {  // root writes anywhere
    const QString locked = dir.filePath("locked");
    ASSERT_TRUE(QDir().mkdir(locked));
    QFile::setPermissions(locked, QFile::ReadOwner | QFile::ExeOwner);
    EXPECT_FALSE(w->exportPicture(locked + "/picture.png", PictureKind::View3D));
    EXPECT_TRUE(w->lastError().contains("not writable")) << w->lastError().toStdString();
    QFile::setPermissions(locked, QFile::ReadOwner | QFile::WriteOwner | QFile::ExeOwner);
  }
}

TEST(StudioPictures, TheDialogSuggestsANameAndFollowsTheChoice) {
  QTemporaryDir dir;
  QSettings().setValue("lastExportDir", dir.path());
  auto w = smallWindow(2.0);
  EXPECT_TRUE(w->fileMenu()->exportPictureAction()->isEnabled());
  EXPECT_EQ(w->fileMenu()->exportPictureAction()->shortcut(), QKeySequence("Ctrl+Shift+P"));
  EXPECT_FALSE(w->fileMenu()->exportPictureAction()->toolTip().isEmpty());
  w->setFrame(42);
  QStringList suggested;
  DialogAnswerer<PictureDialog> answer([&](PictureDialog* d) {
    suggested << d->path();
    d->setKind(PictureKind::Map);  // an unedited name follows the kind
    suggested << d->path();
    d->accept();
  });
  w->fileMenu()->exportPictureAction()->trigger();
  ASSERT_EQ(answer.seen, 1);
  ASSERT_EQ(suggested.size(), 2);
  EXPECT_EQ(suggested[0], QDir(dir.path()).filePath("sample-swing-frame0042.png"));
  EXPECT_EQ(suggested[1], QDir(dir.path()).filePath("sample-swing-isomap-frame0042.png"));
  const QImage written(suggested[1]);
  ASSERT_FALSE(written.isNull()) << w->lastError().toStdString();
  EXPECT_EQ(written.size(), w->mapView()->size());

  // A name the user typed stays when the kind changes.
  PictureDialog dialog(w.get(), w->fileMenu()->context());
  dialog.setPath(dir.filePath("mine.png"));
  dialog.setKind(PictureKind::View3D);
  EXPECT_EQ(dialog.path(), dir.filePath("mine.png"));
  EXPECT_EQ(dialog.kind(), PictureKind::View3D);
}

TEST(StudioPictures, ExportActionsWaitForAMotion) {
  MainWindow w;
  w.setInteractive(false);
  EXPECT_FALSE(w.fileMenu()->exportPictureAction()->isEnabled());
  EXPECT_FALSE(w.fileMenu()->exportAnimationAction()->isEnabled());
  EXPECT_EQ(w.fileMenu()->exportAnimationAction()->shortcut(), QKeySequence("Ctrl+Shift+A"));
  AnimationSettings s;
  s.folder = QDir::tempPath();
  s.name = "nothing";
  EXPECT_FALSE(w.exportAnimation(s));
  EXPECT_TRUE(w.lastError().contains("Open a clip first")) << w.lastError().toStdString();
  w.openClip(swing(0.5));
  EXPECT_TRUE(w.fileMenu()->exportPictureAction()->isEnabled());
  EXPECT_TRUE(w.fileMenu()->exportAnimationAction()->isEnabled());
}

TEST(StudioAnimation, AnImageSequenceOfTheRangeFrameByFrame) {
  auto w = smallWindow(2.0);
  QTemporaryDir dir;
  w->setFrame(77);
  w->play();
  AnimationSettings s;
  s.folder = dir.filePath("out");  // created
  s.name = "swing";
  s.images = true;
  s.video = false;
  s.first = 10;
  s.last = 29;
  ASSERT_TRUE(w->exportAnimation(s)) << w->lastError().toStdString();
  QStringList expected;
  for (int i = 0; i < 20; ++i) expected << QString("swing_%1.png").arg(i, 4, 10, QChar('0'));
  EXPECT_EQ(filesIn(s.folder), expected);
  EXPECT_TRUE(w->statusText().contains("20 images")) << w->statusText().toStdString();
  // Each file is its frame as the window renders it (both views), whatever the playback clock.
  const QImage first = rgb32(QImage(s.folder + "/swing_0000.png"));
  const QImage last = rgb32(QImage(s.folder + "/swing_0019.png"));
  ASSERT_FALSE(first.isNull());
  EXPECT_NE(first, last);
  // The frame shown and playback are back as they were.
  EXPECT_TRUE(w->isPlaying());
  w->pause();
  EXPECT_EQ(first, rgb32(w->renderFrameImage(10, PictureKind::Both)));
  EXPECT_EQ(last, rgb32(w->renderFrameImage(29, PictureKind::Both)));
  EXPECT_EQ(first.size(), w->renderPicture(PictureKind::Both).size());

  // Without a range: the whole motion playing.
  auto small = smallWindow(0.25);
  QTemporaryDir all;
  s.folder = all.path();
  s.first = s.last = -1;
  ASSERT_TRUE(small->exportAnimation(s)) << small->lastError().toStdString();
  EXPECT_EQ(filesIn(all.path()).size(), small->clip()->motion.num_frames);
  EXPECT_EQ(small->clip()->motion.num_frames, 30);
  // A range outside the motion is refused.
  s.first = 5;
  s.last = 30;
  EXPECT_FALSE(small->exportAnimation(s));
  EXPECT_TRUE(small->lastError().contains("0–29")) << small->lastError().toStdString();
}

/// ffprobe's answer for the video stream of `path`: key=value lines.
QMap<QString, QString> probe(const QString& path) {
  QProcess ffprobe;
  ffprobe.start("ffprobe",
                {"-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
                 "stream=codec_name,pix_fmt,width,height,r_frame_rate,"
                 "nb_read_frames",
                 "-of", "default=noprint_wrappers=1", path});
  EXPECT_TRUE(ffprobe.waitForFinished(60000));
  QMap<QString, QString> out;
  for (const QString& line : QString(ffprobe.readAllStandardOutput()).split('\n')) {
    const auto kv = line.split('=');
    if (kv.size() == 2) out[kv[0]] = kv[1].trimmed();
  }
  return out;
}

TEST(StudioAnimation, AnMp4WithTheMotionsFramesSizeAndRate) {
  if (ffmpegProgram().isEmpty() || QStandardPaths::findExecutable("ffprobe").isEmpty())
    GTEST_SKIP() << "SKIPPED: ffmpeg/ffprobe not on PATH (Debian package ffmpeg; "
                    "scripts/install-deps.sh installs it)";
  // 641 px wide: the odd last column is dropped for yuv420p.
  auto w = smallWindow(0.5, QSize(641, 361));
  QTemporaryDir dir;
  AnimationSettings s;
  s.folder = dir.path();
  s.name = "swing";
  s.images = false;
  s.video = true;
  ASSERT_TRUE(w->exportAnimation(s)) << w->lastError().toStdString();
  EXPECT_EQ(filesIn(dir.path()), QStringList{"swing.mp4"});  // no images, no .part left
  const QSize picture = w->renderPicture(PictureKind::Both).size();
  const auto info = probe(dir.filePath("swing.mp4"));
  EXPECT_EQ(info.value("codec_name"), "h264");
  EXPECT_EQ(info.value("pix_fmt"), "yuv420p");
  EXPECT_EQ(info.value("width").toInt(), picture.width() & ~1);
  EXPECT_EQ(info.value("height").toInt(), picture.height() & ~1);
  EXPECT_EQ(info.value("r_frame_rate"), "120/1");  // the swing's rate
  EXPECT_EQ(info.value("nb_read_frames").toInt(), w->clip()->motion.num_frames);
  EXPECT_TRUE(w->statusText().contains("swing.mp4")) << w->statusText().toStdString();

  // Both at once, over a range: the same frames as images and as video.
  QTemporaryDir both;
  s.folder = both.path();
  s.images = true;
  s.first = 3;
  s.last = 14;
  ASSERT_TRUE(w->exportAnimation(s)) << w->lastError().toStdString();
  EXPECT_EQ(filesIn(both.path()).size(), 13);  // 12 images and the video
  EXPECT_EQ(probe(both.filePath("swing.mp4")).value("nb_read_frames").toInt(), 12);
}

TEST(StudioAnimation, AnMp4OfA30FpsWalkRunsAt30Fps) {
  if (ffmpegProgram().isEmpty() || QStandardPaths::findExecutable("ffprobe").isEmpty())
    GTEST_SKIP() << "SKIPPED: ffmpeg/ffprobe not on PATH (Debian package ffmpeg)";
  const QString clip = QString(MOTIONMAP_SHARED_DATA) +
                       "/other/BandaiNamcoResearchInc_dataset-1_walk_normal_001.bvh";
  if (!QFileInfo::exists(clip)) GTEST_SKIP() << "SKIPPED: " << clip.toStdString() << " not found";
  MainWindow w;
  w.setInteractive(false);
  w.resize(640, 360);
  w.show();
  w.setMethod(embed::Method::Pca);
  ASSERT_TRUE(w.openFile(clip)) << w.lastError().toStdString();
  ASSERT_TRUE(QTest::qWaitFor([&] { return w.currentMap() != nullptr; }, kTimeoutMs));
  const ExportContext c = w.exportContext();
  EXPECT_EQ(animationName(c.naming), "BandaiNamcoResearchInc_dataset-1_walk_normal_001-pca");
  EXPECT_EQ(c.last, 194);
  // An in/out range of the playback (I / O) is what the animation dialog offers.
  w.playback().setInPoint(100);
  w.playback().setOutPoint(159);
  EXPECT_EQ(w.exportContext().first, 100);
  EXPECT_EQ(w.exportContext().last, 159);
  QTemporaryDir dir;
  AnimationSettings s;
  s.folder = dir.path();
  s.name = animationName(c.naming);
  s.images = false;
  s.video = true;
  s.first = 100;
  s.last = 159;  // two seconds
  ASSERT_TRUE(w.exportAnimation(s)) << w.lastError().toStdString();
  const auto info = probe(dir.filePath(s.name + ".mp4"));
  EXPECT_EQ(info.value("r_frame_rate"), "30/1");  // Frame Time: 0.0333333
  EXPECT_EQ(info.value("nb_read_frames").toInt(), 60);
}

TEST(StudioAnimation, CancelLeavesNothingBehind) {
  auto w = smallWindow(2.0);
  QTemporaryDir dir;
  AnimationSettings s;
  s.folder = dir.path();
  s.name = "swing";
  s.images = true;
  s.video = !ffmpegProgram().isEmpty();
  int valueAtCancel = -1;
  // Cancel pressed in the progress dialog once a few frames are written.
  QTimer timer;
  timer.setInterval(2);
  QObject::connect(&timer, &QTimer::timeout, [&] {
    for (QWidget* top : QApplication::topLevelWidgets()) {
      auto* progress = qobject_cast<QProgressDialog*>(top);
      if (!progress || !progress->isVisible() || progress->value() < 5 || valueAtCancel >= 0)
        continue;
      valueAtCancel = progress->value();
      for (auto* button : progress->findChildren<QPushButton*>()) button->click();
    }
  });
  timer.start();
  EXPECT_FALSE(w->exportAnimation(s));
  ASSERT_GE(valueAtCancel, 5) << "the progress dialog was not seen";
  EXPECT_LT(valueAtCancel, w->clip()->motion.num_frames);
  EXPECT_TRUE(w->statusText().contains("cancelled")) << w->statusText().toStdString();
  EXPECT_TRUE(w->statusText().contains("removed")) << w->statusText().toStdString();
  EXPECT_EQ(filesIn(dir.path()), QStringList{}) << "no image, no partial MP4";
}

TEST(StudioAnimation, AFolderThatCannotBeMadeIsAClearError) {
  auto w = smallWindow(0.25);
  QTemporaryDir dir;
  QFile file(dir.filePath("a-file"));
  ASSERT_TRUE(file.open(QIODevice::WriteOnly));
  file.close();
  AnimationSettings s;
  s.folder = dir.filePath("a-file/frames");
  s.name = "swing";
  EXPECT_FALSE(w->exportAnimation(s));
  EXPECT_TRUE(w->lastError().contains("cannot create the folder")) << w->lastError().toStdString();
  EXPECT_TRUE(w->lastError().contains("a-file/frames")) << w->lastError().toStdString();
  if (geteuid() != 0) {  // root writes anywhere
    const QString locked = dir.filePath("locked");
    ASSERT_TRUE(QDir().mkdir(locked));
    QFile::setPermissions(locked, QFile::ReadOwner | QFile::ExeOwner);
    s.folder = locked;
    EXPECT_FALSE(w->exportAnimation(s));
    EXPECT_TRUE(w->lastError().contains("not writable")) << w->lastError().toStdString();
    QFile::setPermissions(locked, QFile::ReadOwner | QFile::WriteOwner | QFile::ExeOwner);
  }
  s.folder = dir.path();
  s.images = s.video = false;
  EXPECT_FALSE(w->exportAnimation(s));
  EXPECT_TRUE(w->lastError().contains("nothing to export")) << w->lastError().toStdString();
}

TEST(StudioAnimation, FfmpegFailingSaysWhyAndLeavesNothing) {
  // An ffmpeg that reads a little of its input, complains and fails, first on PATH.
  QTemporaryDir bin;
  const QString fake = bin.filePath("ffmpeg");
  {
    QFile script(fake);
    ASSERT_TRUE(script.open(QIODevice::WriteOnly));
    script.write(
        "#!/bin/sh\n"
        "head -c 1000 > /dev/null\n"
        "echo 'some earlier output' >&2\n"
        "echo 'Unknown encoder libx264 (test)' >&2\n"
        "exit 3\n");
  }
  QFile::setPermissions(fake, QFile::ReadOwner | QFile::WriteOwner | QFile::ExeOwner);
  PathOverride path(bin.path().toLocal8Bit() + ":" + qgetenv("PATH"));
  ASSERT_EQ(ffmpegProgram(), fake);
  auto w = smallWindow(0.5);
  QTemporaryDir dir;
  AnimationSettings s;
  s.folder = dir.path();
  s.name = "swing";
  s.images = true;
  s.video = true;
  EXPECT_FALSE(w->exportAnimation(s));
  EXPECT_TRUE(
      w->lastError().contains("ffmpeg failed (exit code 3): Unknown encoder libx264 (test)"))
      << w->lastError().toStdString();
  EXPECT_EQ(filesIn(dir.path()), QStringList{}) << "the images written before are removed too";
}

TEST(StudioAnimation, WithoutFfmpegTheDialogSaysSoAndOffersImages) {
  QTemporaryDir dir, empty;
  QSettings().setValue("lastExportDir", dir.path());
  auto w = smallWindow(0.25);
  PathOverride path(empty.path().toLocal8Bit());
  ASSERT_TRUE(ffmpegProgram().isEmpty());
  QString note;
  bool videoEnabled = true, imagesChecked = false;
  QString folder, name;
  DialogAnswerer<AnimationDialog> answer([&](AnimationDialog* d) {
    note = d->ffmpegNote()->isVisibleTo(d) ? d->ffmpegNote()->text() : QString();
    videoEnabled = d->videoBox()->isEnabled();
    imagesChecked = d->imagesBox()->isChecked();
    folder = d->folderEdit()->text();
    name = d->nameEdit()->text();
    d->accept();
  });
  w->fileMenu()->exportAnimationAction()->trigger();
  ASSERT_EQ(answer.seen, 1);
  EXPECT_EQ(note, "MP4 needs ffmpeg (Debian package ffmpeg); image sequence only.");
  EXPECT_FALSE(videoEnabled);
  EXPECT_TRUE(imagesChecked);
  EXPECT_EQ(folder, dir.path());
  EXPECT_EQ(name, "sample-swing-isomap");
  // Accepted: the image sequence of the whole motion.
  EXPECT_EQ(filesIn(dir.path()).size(), 30) << w->lastError().toStdString();
  EXPECT_TRUE(QFileInfo::exists(dir.filePath("sample-swing-isomap_0029.png")));
  // Asked for a video anyway (a script, or ffmpeg removed meanwhile): a clear error.
  AnimationSettings s;
  s.folder = dir.filePath("video");
  s.name = "swing";
  s.images = false;
  s.video = true;
  EXPECT_FALSE(w->exportAnimation(s));
  EXPECT_TRUE(w->lastError().contains("MP4 needs ffmpeg (Debian package ffmpeg)"))
      << w->lastError().toStdString();
}

TEST(StudioAnimation, TheDialogWithFfmpegOffersBoth) {
  if (ffmpegProgram().isEmpty()) GTEST_SKIP() << "SKIPPED: ffmpeg not on PATH";
  auto w = smallWindow(0.25);
  AnimationDialog d(w.get(), w->fileMenu()->context(), ffmpegProgram());
  EXPECT_TRUE(d.videoBox()->isEnabled());
  EXPECT_TRUE(d.videoBox()->isChecked());
  EXPECT_TRUE(d.imagesBox()->isChecked());
  EXPECT_FALSE(d.ffmpegNote()->isVisibleTo(&d));
  const AnimationSettings s = d.settings();
  EXPECT_EQ(s.first, 0);
  EXPECT_EQ(s.last, 29);
  EXPECT_TRUE(s.images && s.video);
  // Neither chosen: Export is disabled.
  d.imagesBox()->setChecked(false);
  d.videoBox()->setChecked(false);
  auto* ok = d.findChild<QDialogButtonBox*>()->button(QDialogButtonBox::Ok);
  EXPECT_FALSE(ok->isEnabled());
  d.videoBox()->setChecked(true);
  EXPECT_TRUE(ok->isEnabled());
}

TEST(StudioExportNames, MapAndMotionDialogsStartWithASuggestedName) {
  QTemporaryDir dir;
  QSettings().setValue("lastExportDir", dir.path());
  const QString clip = QString(MOTIONMAP_SHARED_DATA) + "/cmu/64_08.bvh";
  if (!QFileInfo::exists(clip)) GTEST_SKIP() << "SKIPPED: " << clip.toStdString() << " not found";
  MainWindow w;
  w.setInteractive(false);
  w.resize(800, 450);
  w.show();
  w.setMethod(embed::Method::Pca);
  ASSERT_TRUE(w.openFile(clip)) << w.lastError().toStdString();
  ASSERT_TRUE(QTest::qWaitFor([&] { return w.currentMap() != nullptr; }, kTimeoutMs));
  w.setFrame(190);
  QStringList offered;
  DialogAnswerer<QFileDialog> answer([&](QFileDialog* d) {
    offered << d->selectedFiles().value(0);
    d->reject();
  });
  w.fileMenu()->exportMapAction()->trigger();
  ASSERT_EQ(answer.seen, 1);
  EXPECT_EQ(offered.value(0), QDir(dir.path()).filePath("64_08-pca.png"));
  EXPECT_EQ(pictureFileName(w.exportContext().naming, PictureKind::Both), "64_08-frame0190.png");

  // A take: 64_08-Take_1.bvh (the clip's and the take's name), and its animation is 64_08-synth.
  ASSERT_TRUE(w.synthesizeAlong(pathAlong(*w.currentMap(), 20, 40, 0.2)));
  ASSERT_TRUE(QTest::qWaitFor([&] { return !w.isSynthesizing(); }, kTimeoutMs));
  w.pause();
  ASSERT_TRUE(w.fileMenu()->exportMotionAction()->isEnabled());
  w.fileMenu()->exportMotionAction()->trigger();
  ASSERT_EQ(answer.seen, 2);
  EXPECT_EQ(offered.value(1), QDir(dir.path()).filePath("64_08-Take_1.bvh"));
  const ExportContext c = w.exportContext();
  EXPECT_EQ(animationName(c.naming), "64_08-synth");
  EXPECT_EQ(c.last, w.synthesized()->motion.num_frames - 1);
}

}  // namespace
}  // namespace motionmap::studio
