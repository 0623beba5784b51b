// The Studio's parts without a window: MapController, SynthesisController and Playback driven by
// an event loop alone (no widget is made), checked against the library's own answers; the
// parameters' settings; and the small widgets that stand beside the window (the transport bar,
// the recent files).
#include <gtest/gtest.h>

#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QElapsedTimer>
#include <QMainWindow>
#include <QMenu>
#include <QPushButton>
#include <QSettings>
#include <QSignalSpy>
#include <QSlider>
#include <QSpinBox>
#include <QTest>
#include <cmath>

#include "app/file_menu.h"
#include "common/parameters.h"
#include "map/map_controller.h"
#include "playback/playback.h"
#include "playback/transport_bar.h"
#include "studio_test_util.h"
#include "takes/synthesis_controller.h"

namespace motionmap::studio {
namespace {

using testing::kTimeoutMs;
using testing::pathAlong;
using testing::swing;

std::shared_ptr<const std::vector<Clip>> clips(Clip clip) {
  return std::make_shared<const std::vector<Clip>>(std::vector<Clip>{std::move(clip)});
}

/// The map `maps` computes for `method` (waits for it; nullptr when it failed).
std::shared_ptr<const MapResult> computed(MapController& maps, embed::Method method,
                                          const MapParameters& parameters = {},
                                          const synth::BlendOptions& blend = {}) {
  if (maps.request(method, parameters, blend)) return maps.current();
  EXPECT_TRUE(QTest::qWaitFor([&] { return !maps.isComputing(); }, kTimeoutMs));
  QCoreApplication::processEvents();  // the result is queued to this thread
  return maps.current();
}

TEST(StudioMapController, ComputesTheSampleMapOnAWorkerAndEmitsFinished) {
  MapController maps;
  QSignalSpy started(&maps, &MapController::started);
  QSignalSpy progress(&maps, &MapController::progress);
  QSignalSpy finished(&maps, &MapController::finished);
  QSignalSpy failed(&maps, &MapController::failed);
  QSignalSpy stopped(&maps, &MapController::stopped);
  maps.setClips(clips(swing()));
  EXPECT_FALSE(maps.request(embed::Method::Isomap, {}, {}));  // not cached: computed
  EXPECT_TRUE(maps.isComputing());
  EXPECT_EQ(maps.current(), nullptr);
  ASSERT_EQ(started.count(), 1);
  EXPECT_EQ(started.front().front().value<embed::Method>(), embed::Method::Isomap);
  ASSERT_TRUE(QTest::qWaitFor([&] { return finished.count() + failed.count() > 0; }, kTimeoutMs));
  ASSERT_EQ(finished.count(), 1) << failed.value(0).value(0).toString().toStdString();
  EXPECT_EQ(stopped.count(), 1);
  EXPECT_FALSE(maps.isComputing());
  const auto result = finished.front().front().value<std::shared_ptr<const MapResult>>();
  ASSERT_NE(result, nullptr);
  EXPECT_EQ(maps.current(), result);

  // Progress came through the library's Control, in stages, never stepping back.
  ASSERT_GE(progress.count(), 2);
  double last = 0.0;
  QStringList stages;
  for (const QList<QVariant>& report : progress) {
    const double fraction = report[0].toDouble();
    EXPECT_GE(fraction, last);
    EXPECT_LE(fraction, 1.0);
    if (!report[1].toString().isEmpty() && !stages.contains(report[1].toString()))
      stages << report[1].toString();
    last = fraction;
  }
  std::printf("map progress: %d reports, stages %s\n", int(progress.count()),
              qPrintable(stages.join(", ")));
  EXPECT_TRUE(stages.contains("pose distances")) << stages.join(", ").toStdString();
  EXPECT_TRUE(stages.contains("metrics")) << stages.join(", ").toStdString();

  // The library's map of the same clip with the same options, and a blender over it.
  const Clip clip = swing();
  pipeline::ClipMapOptions options = MapParameters{}.options(embed::Method::Isomap);
  options.metrics = true;  // 240 frames: under MapController::kMaxMetricsFrames
  const pipeline::ClipMap direct = pipeline::map_clips(std::span(&clip, 1), options);
  const Eigen::MatrixXd& coordinates = result->map.embedding.coordinates;
  ASSERT_EQ(coordinates.rows(), direct.embedding.coordinates.rows());
  EXPECT_TRUE(coordinates.isApprox(direct.embedding.coordinates, 1e-9));
  ASSERT_TRUE(result->map.metrics.has_value());
  EXPECT_NEAR(result->map.metrics->neighborhood.trustworthiness,
              direct.metrics->neighborhood.trustworthiness, 1e-12);
  EXPECT_EQ(result->parameters, pipeline::describe_parameters(direct.embedding, options));
  EXPECT_EQ(result->blender->num_samples(), direct.features->num_samples());
  EXPECT_EQ(result->blender->options().mode, synth::BlendMode::Local);
  EXPECT_EQ(result->blender->sample_point(17), Eigen::Vector2d(coordinates.row(17).leftCols(2)));
  // Every frame of the clip shows its own row (the sample keeps every frame).
  ASSERT_EQ(result->rowOfFrame.size(), 1u);
  ASSERT_EQ(result->rowOfFrame[0].size(), 240u);
  for (int f : {0, 1, 120, 239})
    EXPECT_EQ(result->map.features->frame_of[std::size_t(result->rowOfFrame[0][std::size_t(f)])],
              f);
}

TEST(StudioMapController, CachesMapsByMethodAndParametersUntilTheClipsChange) {
  MapController maps;
  maps.setClips(clips(swing()));
  const auto pca = computed(maps, embed::Method::Pca);
  ASSERT_NE(pca, nullptr);
  MapParameters positions;
  positions.features = features::FeatureKind::Positions;
  const auto pcaPositions = computed(maps, embed::Method::Pca, positions);
  ASSERT_NE(pcaPositions, nullptr);
  EXPECT_NE(pcaPositions, pca);
  EXPECT_EQ(maps.cachedMaps(), 2);
  // Back to a map computed before: at once, no signal, the same result.
  QSignalSpy started(&maps, &MapController::started);
  QSignalSpy finished(&maps, &MapController::finished);
  EXPECT_TRUE(maps.request(embed::Method::Pca, {}, {}));
  EXPECT_EQ(maps.current(), pca);
  EXPECT_EQ(started.count() + finished.count(), 0);
  // Another blender is another map (the blender is part of it).
  synth::BlendOptions idw;
  idw.mode = synth::BlendMode::Idw;
  const auto pcaIdw = computed(maps, embed::Method::Pca, {}, idw);
  ASSERT_NE(pcaIdw, nullptr);
  EXPECT_EQ(pcaIdw->blender->options().mode, synth::BlendMode::Idw);
  EXPECT_EQ(pcaIdw->map.embedding.coordinates, pca->map.embedding.coordinates);
  EXPECT_EQ(maps.cachedMaps(), 3);
  // New clips: every map is forgotten (the results handed out stay valid).
  sample::SampleOptions walkOptions;
  walkOptions.seconds = 1.0;
  maps.setClips(clips(sample::make_sample_clip(sample::SampleKind::Walk, walkOptions)));
  EXPECT_EQ(maps.cachedMaps(), 0);
  EXPECT_EQ(maps.current(), nullptr);
  const auto walk = computed(maps, embed::Method::Pca);
  ASSERT_NE(walk, nullptr);
  EXPECT_EQ(walk->map.features->num_samples(), 120);
  EXPECT_EQ(pca->map.features->num_samples(), 240);
}

TEST(StudioMapController, CancelLeavesNoResult) {
  MapController maps;
  QSignalSpy progress(&maps, &MapController::progress);
  QSignalSpy finished(&maps, &MapController::finished);
  QSignalSpy cancelled(&maps, &MapController::cancelled);
  QSignalSpy stopped(&maps, &MapController::stopped);
  maps.setClips(clips(swing(50.0)));  // 6000 frames: the distance matrix alone takes seconds
  EXPECT_FALSE(maps.request(embed::Method::Isomap, {}, {}));
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return progress.count() > 0 || !maps.isComputing(); }, kTimeoutMs));
  ASSERT_TRUE(maps.isComputing()) << "the map was done before it could be cancelled";
  maps.cancel();  // returns once the worker has stopped
  EXPECT_FALSE(maps.isComputing());
  EXPECT_EQ(cancelled.count(), 1);
  EXPECT_EQ(stopped.count(), 1);
  QTest::qWait(50);  // nothing still queued from the cancelled worker arrives
  EXPECT_EQ(finished.count(), 0);
  EXPECT_EQ(maps.current(), nullptr);
  EXPECT_EQ(maps.cachedMaps(), 0);
  maps.cancel();  // nothing running: no signal
  EXPECT_EQ(cancelled.count(), 1);
}

TEST(StudioMapController, ALibraryErrorIsFailedNotFinished) {
  MapController maps;
  QSignalSpy failed(&maps, &MapController::failed);
  QSignalSpy finished(&maps, &MapController::finished);
  EXPECT_FALSE(maps.request(embed::Method::Pca, {}, {}));  // no clips: nothing happens
  EXPECT_FALSE(maps.isComputing());
  // k = 20 neighbours of a 12-frame clip: the library refuses.
  sample::SampleOptions tiny;
  tiny.seconds = 0.1;
  maps.setClips(clips(sample::make_sample_clip(sample::SampleKind::Walk, tiny)));
  EXPECT_EQ(computed(maps, embed::Method::Isomap), nullptr);
  ASSERT_EQ(failed.count(), 1);
  EXPECT_EQ(finished.count(), 0);
  const QString message = failed.front().front().toString();
  std::printf("failed: %s\n", qPrintable(message));
  EXPECT_FALSE(message.isEmpty());
  EXPECT_FALSE(maps.isComputing());
}

TEST(StudioMapController, CacheKeysTellEveryParameterApart) {
  const MapParameters m;
  const synth::BlendOptions b;
  const std::string base = MapController::cacheKey(embed::Method::Isomap, m, b);
  EXPECT_EQ(MapController::cacheKey(embed::Method::Isomap, MapParameters{}, b), base);
  std::vector<std::string> keys{base, MapController::cacheKey(embed::Method::Lle, m, b)};
  const auto withMap = [&](auto change) {
    MapParameters p;
    change(p);
    keys.push_back(MapController::cacheKey(embed::Method::Isomap, p, b));
  };
  const auto withBlend = [&](auto change) {
    synth::BlendOptions o;
    change(o);
    keys.push_back(MapController::cacheKey(embed::Method::Isomap, m, o));
  };
  withMap([](MapParameters& p) { p.k = 8; });
  withMap([](MapParameters& p) { p.heat = 2.5; });
  withMap([](MapParameters& p) { p.heat = 2.5000000000000004; });
  withMap([](MapParameters& p) { p.features = features::FeatureKind::Positions; });
  withMap([](MapParameters& p) { p.distance = features::DistanceKind::Geodesic; });
  withMap([](MapParameters& p) { p.exclude = ".*Thumb.*"; });
  withBlend([](synth::BlendOptions& o) { o.mode = synth::BlendMode::Kriging; });
  withBlend([](synth::BlendOptions& o) { o.neighbors = 13; });
  withBlend([](synth::BlendOptions& o) { o.reach = 3.5; });
  for (std::size_t i = 0; i < keys.size(); ++i) {
    for (std::size_t j = i + 1; j < keys.size(); ++j) EXPECT_NE(keys[i], keys[j]) << i << " " << j;
  }
}

TEST(StudioSynthesisController, SynthesizesTheLibrarysMotionAlongAPath) {
  MapController maps;
  maps.setClips(clips(swing()));
  const auto map = computed(maps, embed::Method::Isomap);
  ASSERT_NE(map, nullptr);
  SynthesisController synthesis;
  QSignalSpy finished(&synthesis, &SynthesisController::finished);
  QSignalSpy failed(&synthesis, &SynthesisController::failed);
  QSignalSpy stopped(&synthesis, &SynthesisController::stopped);
  EXPECT_EQ(synthesis.result(), nullptr);
  EXPECT_FALSE(synthesis.start(nullptr, {}, {}));  // no map: nothing starts

  SynthParameters parameters;
  parameters.motion.fps = 30.0;
  const synth::MapPath path = pathAlong(*map, 10, 100, 2.0);
  ASSERT_TRUE(synthesis.start(map, path, parameters));
  EXPECT_TRUE(synthesis.isRunning());
  EXPECT_EQ(synthesis.result(), nullptr);  // the result comes back through the event loop
  ASSERT_TRUE(QTest::qWaitFor([&] { return finished.count() + failed.count() > 0; }, kTimeoutMs));
  ASSERT_EQ(finished.count(), 1) << failed.value(0).value(0).toString().toStdString();
  EXPECT_EQ(stopped.count(), 1);
  ASSERT_NE(synthesis.result(), nullptr);
  EXPECT_EQ(synthesis.resultMap(), map);
  const synth::SynthResult direct = synth::synthesize(*map->blender, path, parameters.motion);
  ASSERT_EQ(synthesis.result()->motion.num_frames, 61);  // 2 s at 30 fps
  ASSERT_EQ(direct.motion.num_frames, 61);
  for (int f : {0, 30, 60}) {
    EXPECT_TRUE(
        direct.motion.rotation(f, 3).isApprox(synthesis.result()->motion.rotation(f, 3), 1e-12));
  }
  EXPECT_EQ(synthesis.result()->clamped_frames, direct.clamped_frames);

  // Not timed as drawn: the path's times are dropped, it is followed at the clip's own pace.
  parameters.timedAsDrawn = false;
  ASSERT_TRUE(synthesis.start(map, path, parameters));
  ASSERT_TRUE(QTest::qWaitFor([&] { return finished.count() > 1; }, kTimeoutMs));
  synth::MapPath untimed = path;
  untimed.times.clear();
  EXPECT_EQ(synthesis.result()->motion.num_frames,
            synth::synthesize(*map->blender, untimed, parameters.motion).motion.num_frames);
  synthesis.clear();
  EXPECT_EQ(synthesis.result(), nullptr);
  EXPECT_EQ(synthesis.resultMap(), nullptr);
}

TEST(StudioSynthesisController, CancelKeepsThePreviousMotionAndErrorsAreFailed) {
  MapController maps;
  maps.setClips(clips(swing()));
  const auto map = computed(maps, embed::Method::Pca);
  ASSERT_NE(map, nullptr);
  SynthesisController synthesis;
  QSignalSpy progress(&synthesis, &SynthesisController::progress);
  QSignalSpy finished(&synthesis, &SynthesisController::finished);
  QSignalSpy failed(&synthesis, &SynthesisController::failed);
  QSignalSpy cancelled(&synthesis, &SynthesisController::cancelled);
  ASSERT_TRUE(synthesis.start(map, pathAlong(*map, 20, 60, 1.0), {}));
  ASSERT_TRUE(QTest::qWaitFor([&] { return !synthesis.isRunning(); }, kTimeoutMs));
  QCoreApplication::processEvents();
  ASSERT_EQ(finished.count(), 1);
  const int frames = synthesis.result()->motion.num_frames;
  EXPECT_EQ(frames, 121);

  // Ten minutes of motion (72 000 frames): cancelled after its first progress report.
  progress.clear();
  ASSERT_TRUE(synthesis.start(map, pathAlong(*map, 10, 220, 600.0), {}));
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return progress.count() > 0 || !synthesis.isRunning(); }, kTimeoutMs));
  ASSERT_TRUE(synthesis.isRunning()) << "the synthesis ended before it could be cancelled";
  EXPECT_LT(progress.back().front().toDouble(), 1.0);
  synthesis.cancel();
  EXPECT_FALSE(synthesis.isRunning());
  EXPECT_EQ(cancelled.count(), 1);
  QTest::qWait(50);  // nothing still queued from the cancelled worker replaces the motion
  EXPECT_EQ(finished.count(), 1);
  ASSERT_NE(synthesis.result(), nullptr);
  EXPECT_EQ(synthesis.result()->motion.num_frames, frames);

  // Options the library rejects: its message, and the motion stays.
  SynthParameters bad;
  bad.motion.fps = -1.0;
  ASSERT_TRUE(synthesis.start(map, pathAlong(*map, 20, 60, 1.0), bad));
  ASSERT_TRUE(QTest::qWaitFor([&] { return failed.count() > 0; }, kTimeoutMs));
  EXPECT_TRUE(failed.front().front().toString().contains("fps"))
      << failed.front().front().toString().toStdString();
  EXPECT_EQ(synthesis.result()->motion.num_frames, frames);
}

/// A Playback on a clock the test moves by hand.
struct HandClock {
  double now = 0.0;
  explicit HandClock(Playback& playback) {
    playback.setClock([this] { return now; });
  }
};

TEST(StudioPlayback, TheFrameIsTheClocksNotACountOfTicks) {
  Playback playback;
  HandClock clock(playback);
  QSignalSpy frames(&playback, &Playback::frameChanged);
  QSignalSpy playing(&playback, &Playback::playingChanged);
  playback.play();  // no motion: nothing to play
  EXPECT_FALSE(playback.isPlaying());
  playback.setFrame(3);  // nor a frame to show
  EXPECT_EQ(frames.count(), 0);

  QSignalSpy counts(&playback, &Playback::frameCountChanged);
  // Times are binary fractions of the frame time (1/128 s), half a frame past a step, so the
  // expected frames are exact.
  constexpr double dt = 1.0 / 128.0;
  playback.setMotion(100, dt);
  playback.setMotion(100, dt);
  ASSERT_EQ(counts.count(), 1);
  EXPECT_EQ(counts.front().front().toInt(), 100);
  playback.setFrame(10);
  playback.play();
  EXPECT_TRUE(playback.isPlaying());
  EXPECT_EQ(playing.count(), 1);
  EXPECT_EQ(playback.tickInterval(), 8);  // the frame time (7.8 ms), rounded
  clock.now = 15.5 * dt;
  playback.tick();
  EXPECT_EQ(playback.frame(), 25);
  playback.tick();  // the clock stood still: no new frame
  EXPECT_EQ(playback.frame(), 25);
  // Twice as fast from where it is: the ticks come more often, the clock is re-anchored.
  playback.setSpeed(2.0);
  EXPECT_EQ(playback.tickInterval(), 4);
  clock.now += 10.25 * dt;
  playback.tick();
  EXPECT_EQ(playback.frame(), 45);
  // A jump while playing goes on from there.
  playback.setFrame(80);
  clock.now += 5.25 * dt;
  playback.tick();
  EXPECT_EQ(playback.frame(), 90);
  // Past the end it loops, keeping the clock's phase: 80 + 31 frames is frame 11.
  clock.now += 10.25 * dt;
  playback.tick();
  EXPECT_EQ(playback.frame(), 11);
  // Without loop it stops on the last frame, and plays again from the start.
  playback.setLoop(false);
  clock.now += 1.0;
  playback.tick();
  EXPECT_EQ(playback.frame(), 99);
  EXPECT_FALSE(playback.isPlaying());
  EXPECT_EQ(playing.count(), 2);
  playback.play();
  EXPECT_EQ(playback.frame(), 0);
  playback.pause();
  EXPECT_EQ(frames.back().front().toInt(), 0);
  EXPECT_EQ(playing.count(), 4);
}

TEST(StudioPlayback, FramesAreClampedSteppedAndShownAgainOnRequest) {
  Playback playback;
  HandClock clock(playback);
  playback.setMotion(50, 1.0 / 120.0);
  QSignalSpy frames(&playback, &Playback::frameChanged);
  playback.setFrame(1000);
  EXPECT_EQ(playback.frame(), 49);
  playback.setFrame(-5);
  EXPECT_EQ(playback.frame(), 0);
  // The same number again is shown again: the motion behind it may be another one.
  playback.setFrame(0);
  EXPECT_EQ(frames.count(), 3);
  playback.play();
  playback.step(+1);  // the arrow keys: pause, then one frame
  EXPECT_FALSE(playback.isPlaying());
  EXPECT_EQ(playback.frame(), 1);
  playback.step(-2);
  EXPECT_EQ(playback.frame(), 0);
  // A shorter motion: the frame stays until the next jump clamps it.
  playback.setFrame(40);
  playback.setMotion(20, 1.0 / 30.0);
  EXPECT_EQ(playback.frame(), 40);
  playback.setFrame(playback.frame());
  EXPECT_EQ(playback.frame(), 19);
  // Speeds are clamped; a speed that is not a number is 1×.
  QSignalSpy speeds(&playback, &Playback::speedChanged);
  playback.setSpeed(100.0);
  EXPECT_EQ(playback.speed(), 8.0);
  playback.setSpeed(std::nan(""));
  EXPECT_EQ(playback.speed(), 1.0);
  playback.setSpeed(0.0);
  EXPECT_EQ(playback.speed(), 0.05);
  EXPECT_EQ(speeds.count(), 3);
  playback.play();
  EXPECT_EQ(playback.tickInterval(), Playback::kMaxTickMs);  // at least every 16 ms
}

TEST(StudioPlayback, ItsTimerPlaysAtTheMotionsRate) {
  Playback playback;
  playback.setMotion(100000, 1.0 / 120.0);
  playback.setFrame(0);
  QElapsedTimer clock;
  clock.start();
  playback.play();
  ASSERT_TRUE(QTest::qWaitFor([&] { return playback.frame() >= 30; }, kTimeoutMs));
  const double elapsed = double(clock.nsecsElapsed()) * 1e-9;
  const int frame = playback.frame();
  playback.pause();
  std::printf("playback: frame %d after %.3f s (the motion has 120 fps)\n", frame, elapsed);
  EXPECT_LE(frame, int(std::floor(elapsed * 120.0)) + 1);  // never ahead of the clock
}

TEST(StudioParameters, SettingsRoundTripAndBadValuesFallBackToDefaults) {
  MapParameters m;
  m.k = 7;
  m.heat = 0.125;
  m.features = features::FeatureKind::Positions;
  m.distance = features::DistanceKind::Features;
  m.exclude = ".*Toe.*";
  SynthParameters s;
  s.blend.mode = synth::BlendMode::Kriging;
  s.blend.neighbors = 9;
  s.blend.reach = 4.5;
  s.motion.speed = 0.25;
  s.motion.fps = 24.0;
  s.motion.smooth = 0.2;
  s.timedAsDrawn = false;
  {
    QSettings settings;
    writeParameters(settings, m, s);
  }
  const QSettings settings;
  EXPECT_EQ(readMapParameters(settings), m);
  const SynthParameters read = readSynthParameters(settings);
  EXPECT_EQ(read.blend.mode, s.blend.mode);
  EXPECT_EQ(read.blend.neighbors, 9);
  EXPECT_EQ(read.blend.reach, 4.5);
  EXPECT_EQ(read.motion.speed, 0.25);
  EXPECT_EQ(read.motion.fps, 24.0);
  EXPECT_EQ(read.motion.smooth, 0.2);
  EXPECT_FALSE(read.timedAsDrawn);

  QSettings edited;
  edited.setValue("map/k", 2.5);
  edited.setValue("map/heat", "auto");
  edited.setValue("map/features", "joints");
  edited.setValue("synth/reach", -1);
  edited.setValue("synth/smooth", 1e9);  // beyond the library's longest smoothing
  const MapParameters defaults;
  EXPECT_EQ(readMapParameters(edited).k, defaults.k);
  EXPECT_FALSE(readMapParameters(edited).heat.has_value());
  EXPECT_EQ(readMapParameters(edited).features, defaults.features);
  EXPECT_EQ(readMapParameters(edited).distance, m.distance);  // still good: kept
  EXPECT_EQ(readSynthParameters(edited).blend.reach, synth::BlendOptions{}.reach);
  // One motion option the library rejects leaves them all at the defaults.
  EXPECT_EQ(readSynthParameters(edited).motion.fps, synth::SynthOptions{}.fps);
  EXPECT_EQ(readSynthParameters(edited).motion.smooth, synth::SynthOptions{}.smooth);
  EXPECT_EQ(methodLabel(embed::Method::LaplacianEigenmap), "LE");
}

TEST(StudioTransportBar, FollowsThePlaybackBothWays) {
  Playback playback;
  TransportBar bar(&playback);
  EXPECT_FALSE(bar.slider()->isEnabled());
  playback.setMotion(240, 1.0 / 120.0);
  EXPECT_TRUE(bar.slider()->isEnabled());
  EXPECT_EQ(bar.slider()->maximum(), 239);
  playback.setFrame(42);
  EXPECT_EQ(bar.slider()->value(), 42);
  bar.slider()->setValue(100);  // a drag of the slider
  EXPECT_EQ(playback.frame(), 100);
  bar.playButton()->click();
  EXPECT_TRUE(playback.isPlaying());
  EXPECT_EQ(bar.playButton()->text(), "Pause");
  playback.pause();
  EXPECT_EQ(bar.playButton()->text(), "Play");
  playback.setSpeed(2.0);
  EXPECT_EQ(bar.speedBox()->currentData().toDouble(), 2.0);
  bar.speedBox()->setCurrentIndex(0);
  EXPECT_EQ(playback.speed(), 0.25);
  playback.setLoop(false);
  EXPECT_FALSE(bar.loopBox()->isChecked());
  bar.loopBox()->setChecked(true);
  EXPECT_TRUE(playback.loop());
  // Only the number fields take the keyboard focus, and only by a click (to type in them);
  // Space and the arrows are the window's everywhere else.
  for (QWidget* w : bar.findChildren<QWidget*>()) {
    const bool field = w == static_cast<QWidget*>(bar.frameBox()) ||
                       w == static_cast<QWidget*>(bar.timeBox()) ||
                       bar.frameBox()->isAncestorOf(w) || bar.timeBox()->isAncestorOf(w);
    EXPECT_EQ(w->focusPolicy(), field ? Qt::ClickFocus : Qt::NoFocus)
        << w->metaObject()->className();
  }
}

TEST(StudioFileMenu, RemembersTheLastFilesNewestFirst) {
  QMainWindow window;
  FileMenu files(&window);
  EXPECT_TRUE(files.recentFiles().isEmpty());
  for (int i = 0; i < FileMenu::kMaxRecent + 2; ++i) files.remember(QString("/data/%1.bvh").arg(i));
  files.remember("/data/3.bvh");
  QStringList recent = files.recentFiles();
  ASSERT_EQ(recent.size(), FileMenu::kMaxRecent);
  EXPECT_EQ(recent.front(), "/data/3.bvh");
  EXPECT_EQ(recent.count("/data/3.bvh"), 1);
  EXPECT_EQ(recent[1], "/data/9.bvh");
  EXPECT_FALSE(recent.contains("/data/0.bvh"));
  EXPECT_EQ(files.lastDir(), "/data");
  EXPECT_EQ(QSettings().value("lastDir").toString(), "/data");
  // The menu lists them; choosing one asks to open it.
  QMenu* menu = nullptr;
  for (QMenu* m : window.findChildren<QMenu*>()) {
    if (m->title() == "Open &recent") menu = m;
  }
  ASSERT_NE(menu, nullptr);
  ASSERT_EQ(menu->actions().size(), FileMenu::kMaxRecent);
  QSignalSpy open(&files, &FileMenu::openRequested);
  menu->actions()[1]->trigger();
  ASSERT_EQ(open.count(), 1);
  EXPECT_EQ(open.front().front().toString(), "/data/9.bvh");
}

}  // namespace
}  // namespace motionmap::studio
