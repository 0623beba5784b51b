// MotionMap Studio's timeline, keys and help (offscreen): the in/out range of Playback, the
// transport bar's frame and time fields and range band, the playback keys as window shortcuts
// (they work in an active window before any click, and not while a number field is typed in),
// the method keys and full screen, tooltips on every action and transport control, the shortcut
// list and About, the elided progress text, and the executable's --help / --version without a
// display and a --screenshot run that leaves the settings alone.
#include <gtest/gtest.h>

#include <QAbstractButton>
#include <QAbstractSpinBox>
#include <QAction>
#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QDialog>
#include <QDir>
#include <QDirIterator>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QFile>
#include <QLabel>
#include <QLineEdit>
#include <QMainWindow>
#include <QMenu>
#include <QProcess>
#include <QProgressBar>
#include <QPushButton>
#include <QRegularExpression>
#include <QSettings>
#include <QSignalSpy>
#include <QSpinBox>
#include <QStatusBar>
#include <QTableWidget>
#include <QTemporaryDir>
#include <QTest>
#include <QTimer>
#include <cmath>
#include <cstdio>

#include "app/help_dialogs.h"
#include "app/job_progress.h"
#include "app/main_window.h"
#include "map/map_view.h"
#include "motionmap/io/bvh.h"
#include "playback/playback.h"
#include "playback/playback_actions.h"
#include "playback/transport_bar.h"
#include "studio_test_util.h"

namespace motionmap::studio {
namespace {

using testing::kTimeoutMs;
using testing::swing;
using testing::windowWithMap;

/// A Playback on a clock the test moves by hand.
struct HandClock {
  double now = 0.0;
  explicit HandClock(Playback& playback) {
    playback.setClock([this] { return now; });
  }
};

TEST(StudioTimelinePlayback, PlayingAndLoopingStayWithinTheInOutRange) {
  Playback playback;
  HandClock clock(playback);
  constexpr double dt = 1.0 / 128.0;  // binary fractions: the frames below are exact
  playback.setMotion(100, dt);
  QSignalSpy ranges(&playback, &Playback::rangeChanged);
  EXPECT_EQ(playback.rangeStart(), 0);
  EXPECT_EQ(playback.rangeEnd(), 99);
  playback.setInPoint(20);
  playback.setOutPoint(30);
  EXPECT_EQ(ranges.count(), 2);
  EXPECT_EQ(playback.inPoint(), 20);
  EXPECT_EQ(playback.outPoint(), 30);
  // Outside the range, play starts at the in point.
  playback.setFrame(5);
  playback.play();
  EXPECT_EQ(playback.frame(), 20);
  clock.now = 5.5 * dt;
  playback.tick();
  EXPECT_EQ(playback.frame(), 25);
  // Past the out point it loops back to the in point, keeping the clock's phase: 20 + 12 frames
  // is one past the range's 11 frames, frame 21.
  clock.now = 12.5 * dt;
  playback.tick();
  EXPECT_EQ(playback.frame(), 21);
  clock.now = 21.5 * dt;  // 20 + 21 = 41 → 20 + (21 mod 11) = 30
  playback.tick();
  EXPECT_EQ(playback.frame(), 30);
  // Without loop it stops on the out point, and plays again from the in point.
  playback.setLoop(false);
  clock.now += 1.0;
  playback.tick();
  EXPECT_EQ(playback.frame(), 30);
  EXPECT_FALSE(playback.isPlaying());
  playback.play();
  EXPECT_EQ(playback.frame(), 20);
  playback.pause();
  // Stepping goes anywhere, the range stays.
  playback.setFrame(30);
  playback.step(+1);
  EXPECT_EQ(playback.frame(), 31);
  playback.step(-10);
  EXPECT_EQ(playback.frame(), 21);
  EXPECT_EQ(playback.rangeEnd(), 30);
  // A range of one frame does not play.
  playback.setOutPoint(20);
  EXPECT_EQ(playback.rangeStart(), 20);
  EXPECT_EQ(playback.rangeEnd(), 20);
  playback.play();
  EXPECT_FALSE(playback.isPlaying());
  // An in point after the out point drops the out point, and the other way round.
  playback.setInPoint(40);
  EXPECT_EQ(playback.inPoint(), 40);
  EXPECT_FALSE(playback.outPoint());
  EXPECT_EQ(playback.rangeEnd(), 99);
  playback.setOutPoint(10);
  EXPECT_FALSE(playback.inPoint());
  EXPECT_EQ(playback.rangeStart(), 0);
  EXPECT_EQ(playback.rangeEnd(), 10);
  // Points are clamped to the motion.
  playback.setOutPoint(1000);
  EXPECT_EQ(playback.outPoint(), 99);
  playback.clearOutPoint();
  playback.clearOutPoint();  // nothing to clear: no signal
  playback.setInPoint(-3);
  EXPECT_EQ(playback.inPoint(), 0);
  playback.clearInPoint();
  EXPECT_FALSE(playback.inPoint() || playback.outPoint());
  EXPECT_EQ(ranges.count(), 9);
}

TEST(StudioTimelinePlayback, HomeAndEndGoToTheRangeThenToTheMotionsEnds) {
  Playback playback;
  HandClock clock(playback);
  playback.setMotion(100, 1.0 / 120.0);
  playback.setFrame(50);
  playback.goToStart();
  EXPECT_EQ(playback.frame(), 0);
  playback.goToEnd();
  EXPECT_EQ(playback.frame(), 99);
  playback.setInPoint(20);
  playback.setOutPoint(60);
  playback.setFrame(50);
  playback.goToStart();
  EXPECT_EQ(playback.frame(), 20);
  playback.goToStart();  // pressed again at the in point: the motion's first frame
  EXPECT_EQ(playback.frame(), 0);
  playback.goToEnd();
  EXPECT_EQ(playback.frame(), 60);
  playback.goToEnd();
  EXPECT_EQ(playback.frame(), 99);
  // While playing, Home jumps and playing goes on from there.
  playback.setFrame(30);
  playback.play();
  playback.goToStart();
  EXPECT_TRUE(playback.isPlaying());
  clock.now += 5.5 / 120.0;
  playback.tick();
  EXPECT_EQ(playback.frame(), 25);
  playback.pause();
}

TEST(StudioTimelinePlayback, TheRangeStaysForTheSameMotionAndGoesWithAnother) {
  Playback playback;
  playback.setMotion(100, 1.0 / 30.0);
  playback.setInPoint(10);
  playback.setOutPoint(20);
  QSignalSpy ranges(&playback, &Playback::rangeChanged);
  playback.setMotion(100, 1.0 / 30.0);  // the window tells the same clip again
  EXPECT_EQ(playback.inPoint(), 10);
  EXPECT_EQ(playback.outPoint(), 20);
  EXPECT_EQ(ranges.count(), 0);
  playback.setMotion(100, 1.0 / 120.0);  // another rate: another motion
  EXPECT_FALSE(playback.inPoint() || playback.outPoint());
  EXPECT_EQ(ranges.count(), 1);
  playback.setOutPoint(50);
  playback.setMotion(40, 1.0 / 120.0);  // another length
  EXPECT_FALSE(playback.outPoint());
  EXPECT_EQ(playback.rangeEnd(), 39);
  EXPECT_EQ(ranges.count(), 3);
}

TEST(StudioTimelineBar, ShowsAndEditsTheFrameTimeLengthAndRange) {
  Playback playback;
  TransportBar bar(&playback);
  bar.resize(900, bar.sizeHint().height());
  bar.show();
  EXPECT_FALSE(bar.frameBox()->isEnabled());
  EXPECT_EQ(bar.lengthLabel()->text(), "no motion");
  playback.setMotion(240, 1.0 / 120.0);
  EXPECT_TRUE(bar.frameBox()->isEnabled());
  EXPECT_EQ(bar.lengthLabel()->text(), "240 frames · 2.000 s");
  EXPECT_EQ(bar.frameBox()->maximum(), 239);
  EXPECT_NEAR(bar.timeBox()->maximum(), 239.0 / 120.0, 0.0005);  // 3 decimals
  playback.setFrame(42);
  EXPECT_EQ(bar.frameBox()->value(), 42);
  EXPECT_NEAR(bar.timeBox()->value(), 0.35, 1e-9);
  EXPECT_EQ(bar.timeBox()->text(), "0.350 s");
  // A frame typed (committed) moves the clock; a time goes to the nearest frame and shows its
  // time.
  bar.frameBox()->setValue(100);
  EXPECT_EQ(playback.frame(), 100);
  EXPECT_EQ(bar.slider()->value(), 100);
  bar.timeBox()->setValue(1.004);  // 120.48 frames
  EXPECT_EQ(playback.frame(), 120);
  EXPECT_NEAR(bar.timeBox()->value(), 1.0, 1e-9);
  EXPECT_EQ(bar.frameBox()->value(), 120);
  // Focus on a field pauses: what is typed would be lost under a running frame.
  playback.play();
  QApplication::setActiveWindow(&bar);
  bar.frameBox()->setFocus();
  EXPECT_TRUE(QTest::qWaitFor([&] { return !playback.isPlaying(); }, 2000));

  // The range: in the length text and as a band on the slider from the in to the out point.
  EXPECT_TRUE(bar.slider()->bandRect().isEmpty());
  playback.setInPoint(60);
  playback.setOutPoint(180);
  EXPECT_EQ(bar.lengthLabel()->text(), "240 frames · 2.000 s · range 60–180");
  const QRect band = bar.slider()->bandRect();
  ASSERT_FALSE(band.isEmpty());
  EXPECT_NEAR(band.left(), bar.slider()->xOfValue(60), 2);
  EXPECT_NEAR(band.right(), bar.slider()->xOfValue(180), 2);
  EXPECT_LT(bar.slider()->xOfValue(60), bar.slider()->xOfValue(180));
  const QImage image = bar.slider()->grab().toImage();
  const int y = band.center().y();
  auto isBand = [&](int x) {
    return image.pixelColor(x * image.width() / bar.slider()->width(),
                            y * image.height() / bar.slider()->height()) ==
           RangeSlider::bandColor();
  };
  EXPECT_TRUE(isBand(bar.slider()->xOfValue(120)));
  EXPECT_FALSE(isBand(bar.slider()->xOfValue(20)));
  EXPECT_FALSE(isBand(bar.slider()->xOfValue(220)));
  playback.clearInPoint();
  playback.clearOutPoint();
  EXPECT_TRUE(bar.slider()->bandRect().isEmpty());
  EXPECT_EQ(bar.lengthLabel()->text(), "240 frames · 2.000 s");
}

/// The window of `w`, active, as a user's would be after it was shown (no click into it).
void activate(MainWindow* w) {
  // activateWindow asks the platform (under a bare X server without a window manager nothing
  // else would give the window the input focus); setActiveWindow is enough offscreen.
  w->activateWindow();
  QApplication::setActiveWindow(w);
  ASSERT_TRUE(QTest::qWaitForWindowActive(w));
}

/// A key pressed on the keyboard: through the platform window, to whatever has the focus (the
/// shortcut map first), as a real key press travels.
void press(MainWindow* w, Qt::Key key, Qt::KeyboardModifiers modifiers = Qt::NoModifier) {
  QTest::keyClick(w->windowHandle(), key, modifiers);
}

TEST(StudioTimelineKeys, SpaceWithoutAClickPlaysInTheActiveWindow) {
  auto w = windowWithMap();
  activate(w.get());
  // Nothing in the window has the focus: no view was clicked.
  if (QWidget* focus = QApplication::focusWidget()) focus->clearFocus();
  ASSERT_EQ(QApplication::focusWidget(), nullptr);
  w->setFrame(0);
  press(w.get(), Qt::Key_Space);
  EXPECT_TRUE(w->isPlaying());
  EXPECT_TRUE(QTest::qWaitFor([&] { return w->currentFrame() >= 10; }, kTimeoutMs));
  press(w.get(), Qt::Key_Space);
  EXPECT_FALSE(w->isPlaying());
  const int frame = w->currentFrame();
  QTest::qWait(100);
  EXPECT_EQ(w->currentFrame(), frame);  // paused
}

TEST(StudioTimelineKeys, SpacePlaysWhileTheFirstMapIsComputedAndDoesNotCancelIt) {
  // As a start with a clip on the command line: the window is shown and activated while its
  // map is computed, the Cancel button showing in the status bar.
  MainWindow w;
  w.setInteractive(false);
  w.resize(1000, 600);
  w.setMethod(embed::Method::Isomap);
  w.openClip(swing(30.0));  // 3 600 frames: the map takes a while
  w.show();
  activate(&w);
  ASSERT_TRUE(w.isComputing());
  const QWidget* focus = QApplication::focusWidget();
  EXPECT_TRUE(focus == nullptr || focus->focusPolicy() == Qt::NoFocus ||
              !qobject_cast<const QAbstractButton*>(focus))
      << focus->metaObject()->className();
  w.setFrame(0);
  press(&w, Qt::Key_Space);
  EXPECT_TRUE(w.isPlaying());
  EXPECT_TRUE(w.isComputing());  // not cancelled
  press(&w, Qt::Key_Space);
  EXPECT_FALSE(w.isPlaying());
  const int frame = w.currentFrame();
  press(&w, Qt::Key_Right);
  EXPECT_EQ(w.currentFrame(), frame + 1);
  EXPECT_TRUE(w.isComputing());
  w.cancelComputation();
}

TEST(StudioTimelineKeys, PlaybackKeysWorkWhateverViewHasTheFocus) {
  auto w = windowWithMap();
  activate(w.get());
  const int last = w->clip()->motion.num_frames - 1;
  for (QWidget* focus : {static_cast<QWidget*>(w->mapView()), static_cast<QWidget*>(nullptr)}) {
    SCOPED_TRACE(focus ? "focus on the map view" : "focus on nothing");
    if (focus) {
      focus->setFocusPolicy(Qt::StrongFocus);
      focus->setFocus();
      ASSERT_TRUE(QTest::qWaitFor([&] { return focus->hasFocus(); }, 2000));
    } else if (QWidget* f = QApplication::focusWidget()) {
      f->clearFocus();
    }
    w->setFrame(50);
    press(w.get(), Qt::Key_Right);
    EXPECT_EQ(w->currentFrame(), 51);
    press(w.get(), Qt::Key_Left);
    EXPECT_EQ(w->currentFrame(), 50);
    press(w.get(), Qt::Key_Right, Qt::ShiftModifier);
    EXPECT_EQ(w->currentFrame(), 60);
    press(w.get(), Qt::Key_Left, Qt::ShiftModifier);
    press(w.get(), Qt::Key_Left, Qt::ShiftModifier);
    EXPECT_EQ(w->currentFrame(), 40);
    press(w.get(), Qt::Key_End);
    EXPECT_EQ(w->currentFrame(), last);
    press(w.get(), Qt::Key_Home);
    EXPECT_EQ(w->currentFrame(), 0);
    // I and O set the range at the current frame; Home and End then go to its ends.
    w->setFrame(30);
    press(w.get(), Qt::Key_I);
    w->setFrame(90);
    press(w.get(), Qt::Key_O);
    press(w.get(), Qt::Key_Home);
    EXPECT_EQ(w->currentFrame(), 30);
    press(w.get(), Qt::Key_End);
    EXPECT_EQ(w->currentFrame(), 90);
    // Playing stays within it: without loop, from the in point when at its end, to its end.
    w->setLoop(false);
    press(w.get(), Qt::Key_Space);
    EXPECT_GE(w->currentFrame(), 30);  // (a slow display may have shown a frame or two since)
    EXPECT_LT(w->currentFrame(), 45);
    EXPECT_TRUE(QTest::qWaitFor([&] { return !w->isPlaying(); }, kTimeoutMs));
    EXPECT_EQ(w->currentFrame(), 90);
    w->setLoop(true);
    press(w.get(), Qt::Key_I, Qt::AltModifier);
    press(w.get(), Qt::Key_O, Qt::AltModifier);
    press(w.get(), Qt::Key_End);
    EXPECT_EQ(w->currentFrame(), last);
  }
}

TEST(StudioTimelineKeys, NumberKeysPickTheEightMethods) {
  auto w = windowWithMap(embed::Method::Pca);
  activate(w.get());
  const std::vector<embed::Method>& methods = embed::all_methods();
  ASSERT_EQ(methods.size(), 8U);  // the six spectral maps, umap (7) and gplvm (8)
  // Each key picks its method (the map is then computed, or taken from the cache).
  for (int i = 7; i >= 0; --i) {
    press(w.get(), Qt::Key(Qt::Key_1 + i));
    EXPECT_EQ(w->method(), methods[std::size_t(i)]) << "key " << i + 1;
  }
  EXPECT_TRUE(QTest::qWaitFor([&] { return !w->isComputing(); }, kTimeoutMs));
}

TEST(StudioTimelineKeys, ANumberFieldKeepsItsKeysWhileTypedInAndEnterGivesThemBack) {
  auto w = windowWithMap(embed::Method::Pca);
  activate(w.get());
  auto* bar = w->findChild<TransportBar*>();
  ASSERT_NE(bar, nullptr);
  w->setFrame(10);
  QLineEdit* edit = bar->frameBox()->findChild<QLineEdit*>();
  ASSERT_NE(edit, nullptr);
  QTest::mouseClick(edit, Qt::LeftButton);
  ASSERT_TRUE(QTest::qWaitFor([&] { return edit->hasFocus(); }, 2000));
  edit->selectAll();
  // Digits are typed, not methods picked; ← moves the text cursor, not the frame; Space is no
  // play.
  press(w.get(), Qt::Key_7);
  press(w.get(), Qt::Key_5);
  press(w.get(), Qt::Key_Left);
  press(w.get(), Qt::Key_Space);
  EXPECT_EQ(w->method(), embed::Method::Pca);
  EXPECT_EQ(w->currentFrame(), 10);
  EXPECT_FALSE(w->isPlaying());
  EXPECT_EQ(edit->text(), "Frame 75");  // the field refuses the space
  press(w.get(), Qt::Key_Return);
  EXPECT_EQ(w->currentFrame(), 75);
  EXPECT_FALSE(edit->hasFocus());
  // The keys are the window's again.
  press(w.get(), Qt::Key_Right);
  EXPECT_EQ(w->currentFrame(), 76);
  // Esc leaves the field without moving the frame.
  QTest::mouseClick(edit, Qt::LeftButton);
  ASSERT_TRUE(QTest::qWaitFor([&] { return edit->hasFocus(); }, 2000));
  edit->selectAll();
  press(w.get(), Qt::Key_3);
  press(w.get(), Qt::Key_Escape);
  EXPECT_FALSE(edit->hasFocus());
  EXPECT_EQ(w->currentFrame(), 76);
  EXPECT_EQ(bar->frameBox()->value(), 76);
}

TEST(StudioTimelineKeys, F11TogglesFullScreen) {
  auto w = windowWithMap(embed::Method::Pca);
  activate(w.get());
  ASSERT_FALSE(w->windowState().testFlag(Qt::WindowFullScreen));
  press(w.get(), Qt::Key_F11);
  EXPECT_TRUE(w->windowState().testFlag(Qt::WindowFullScreen));
  press(w.get(), Qt::Key_F11);
  EXPECT_FALSE(w->windowState().testFlag(Qt::WindowFullScreen));
}

/// Every action a user can reach: menu entries and window actions (not separators, nor the
/// actions that stand for submenus).
QList<QAction*> userActions(const QMainWindow& w) {
  QList<QAction*> actions;
  for (QAction* a : w.findChildren<QAction*>()) {
    if (!a->isSeparator() && !a->menu()) actions << a;
  }
  return actions;
}

TEST(StudioTimelineHelp, EveryActionAndTransportControlHasATooltip) {
  MainWindow w;
  w.setInteractive(false);
  const QList<QAction*> actions = userActions(w);
  EXPECT_GT(actions.size(), 30);
  // The rule: a tooltip that says more than the entry's text (Qt's default tooltip is the text).
  for (const QAction* a : actions) {
    EXPECT_FALSE(a->toolTip().isEmpty()) << a->text().toStdString();
    EXPECT_NE(a->toolTip(), plainText(a->text())) << "no tooltip: " << a->text().toStdString();
  }
  for (const QMenu* menu : w.findChildren<QMenu*>())
    EXPECT_TRUE(menu->toolTipsVisible()) << menu->title().toStdString();
  auto* bar = w.findChild<TransportBar*>();
  ASSERT_NE(bar, nullptr);
  const QList<QWidget*> controls = bar->findChildren<QWidget*>(Qt::FindDirectChildrenOnly);
  EXPECT_EQ(controls.size(), 7);
  for (const QWidget* c : controls)
    EXPECT_FALSE(c->toolTip().isEmpty()) << c->metaObject()->className();
  for (const QPushButton* b : w.statusBar()->findChildren<QPushButton*>())
    EXPECT_FALSE(b->toolTip().isEmpty()) << b->text().toStdString();
}

TEST(StudioTimelineHelp, EveryFieldOfTheParameterDialogsAndEveryPanelButtonHasATooltip) {
  MainWindow w;
  w.setInteractive(false);
  w.show();
  // Each dialog is opened from its Motion-menu entry; a timer reads its fields, then closes it.
  for (const QString& entry : {QStringLiteral("&Parameters…"), QStringLiteral("S&ynthesis…")}) {
    QAction* open = nullptr;
    for (QAction* a : w.findChildren<QAction*>())
      if (a->text() == entry) open = a;
    ASSERT_NE(open, nullptr) << entry.toStdString();
    int fields = 0;
    QTimer::singleShot(0, [&] {
      QWidget* dialog = QApplication::activeModalWidget();
      ASSERT_NE(dialog, nullptr);
      for (const QWidget* field : dialog->findChildren<QWidget*>()) {
        if (!qobject_cast<const QAbstractSpinBox*>(field) &&
            !qobject_cast<const QComboBox*>(field) && !qobject_cast<const QLineEdit*>(field))
          continue;
        if (qobject_cast<const QAbstractSpinBox*>(field->parentWidget())) continue;  // its editor
        ++fields;
        EXPECT_FALSE(field->toolTip().isEmpty())
            << entry.toStdString() << ": " << field->metaObject()->className();
      }
      static_cast<QDialog*>(dialog)->reject();
    });
    open->trigger();
    EXPECT_GE(fields, 5) << entry.toStdString();
  }
  for (const QDockWidget* dock : w.findChildren<QDockWidget*>()) {
    for (const QAbstractButton* b : dock->widget()->findChildren<QAbstractButton*>())
      EXPECT_FALSE(b->toolTip().isEmpty())
          << dock->windowTitle().toStdString() << ": " << b->text().toStdString();
  }
}

TEST(StudioTimelineHelp, TheShortcutListHasEveryActionsKeysAndTheGestures) {
  MainWindow w;
  w.setInteractive(false);
  w.show();
  w.activateWindow();
  QApplication::setActiveWindow(&w);
  ASSERT_TRUE(QTest::qWaitForWindowActive(&w));
  press(&w, Qt::Key_F1);
  auto* dialog = w.findChild<ShortcutsDialog*>();
  ASSERT_NE(dialog, nullptr);
  EXPECT_TRUE(dialog->isVisible());
  const QTableWidget* table = dialog->table();
  auto hasRow = [&](const QString& keys, const QString& what) {
    for (int r = 0; r < table->rowCount(); ++r) {
      if (table->item(r, 0)->text() == keys && table->item(r, 1)->text() == what) return true;
    }
    return false;
  };
  QStringList listed;
  for (const QAction* a : userActions(w)) {
    if (a->shortcuts().isEmpty()) continue;
    QStringList keys;
    for (const QKeySequence& k : a->shortcuts()) keys << k.toString(QKeySequence::NativeText);
    EXPECT_TRUE(hasRow(keys.join(", "), plainText(a->text())))
        << keys.join(", ").toStdString() << " " << a->text().toStdString();
    listed << keys;
  }
  // The keys the issue asks for are among them.
  for (const char* key :
       {"Space", "Left",  "Right", "Shift+Left", "Shift+Right", "Home", "End", "I",
        "O",     "Alt+I", "Alt+O", "1",          "2",           "3",    "4",   "5",
        "6",     "F11",   "F1",    "Ctrl+O",     "S",           "M"})
    EXPECT_TRUE(listed.contains(key)) << key;
  // Playback entries are listed under their menu, and the mouse gestures follow the keys.
  bool underPlayback = false;
  for (int r = 0; r < table->rowCount(); ++r) {
    if (table->item(r, 0)->text() == "Space")
      underPlayback = table->item(r, 2)->text() == "Playback";
  }
  EXPECT_TRUE(underPlayback);
  EXPECT_TRUE(hasRow("Shift+drag, or drag in sketch mode",
                     "Sketches a path; on release the motion along it is synthesized and "
                     "played"));
  EXPECT_EQ(table->rowCount(), int(shortcutRows(&w).size() + gestureRows().size()));
  dialog->close();
}

TEST(StudioTimelineHelp, AboutNamesTheProjectVersionAndTheLibraries) {
  // The version is the CMake project's.
  QFile cmake(QStringLiteral(MOTIONMAP_SOURCE_DIR "/CMakeLists.txt"));
  ASSERT_TRUE(cmake.open(QIODevice::ReadOnly));
  const auto match = QRegularExpression(R"(project\(MotionMap VERSION ([0-9.]+))")
                         .match(QString::fromUtf8(cmake.readAll()));
  ASSERT_TRUE(match.hasMatch());
  EXPECT_EQ(studioVersion(), match.captured(1));
  const QString about = aboutText();
  std::printf("%s\n", qPrintable(about));
  EXPECT_TRUE(about.contains("MotionMap Studio " + match.captured(1)));
  EXPECT_TRUE(about.contains(QString("running on Qt ") + qVersion()));
  for (const char* library : {"Eigen 3.", "Spectra 1.", "nanoflann 1.", "HDF5 1."})
    EXPECT_TRUE(about.contains(library)) << library << " in " << about.toStdString();
  EXPECT_FALSE(about.contains("not known"));
}

TEST(StudioTimelineProgress, ALongProgressTextIsElidedAndWholeInItsTooltip) {
  QMainWindow window;
  window.resize(700, 200);
  JobProgress progress(window.statusBar(), "Cancel");
  window.statusBar()->addWidget(new QLabel("clip 1 of 2 · 365 frames · 120 fps"), 1);
  window.show();
  progress.start();
  const QString stage =
      "shortest paths over the k-nearest-neighbour graph of 10 000 frames with geodesic "
      "distances between all pairs of poses";
  progress.setProgress(0.42, stage + " %p%");
  const QString whole = stage + " 42%";
  ASSERT_TRUE(QTest::qWaitFor([&] { return progress.label()->isVisible(); }, 2000));
  QTest::qWait(20);  // the layout
  EXPECT_EQ(progress.label()->fullText(), whole);
  EXPECT_EQ(progress.label()->toolTip(), whole);
  EXPECT_EQ(progress.bar()->toolTip(), whole);
  EXPECT_NE(progress.label()->text(), whole);
  EXPECT_TRUE(progress.label()->text().endsWith(QChar(0x2026)))
      << progress.label()->text().toStdString();
  EXPECT_LE(progress.label()->width(), ElidedLabel::kMaxWidth);
  EXPECT_EQ(progress.bar()->value(), 420);
  EXPECT_FALSE(progress.cancelButton()->toolTip().isEmpty());
  // A short text is shown whole; a new job starts from the first text, not the last stage.
  progress.setProgress(0.5, "stress %p%");
  QTest::qWait(20);
  EXPECT_EQ(progress.label()->text(), "stress 50%");
  progress.stop();
  EXPECT_FALSE(progress.label()->isVisible());
  progress.start();
  EXPECT_EQ(progress.label()->fullText(), "0%");
}

/// The environment of a process run without any display.
QProcessEnvironment withoutDisplay() {
  QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
  env.remove("DISPLAY");
  env.remove("WAYLAND_DISPLAY");
  env.insert("QT_QPA_PLATFORM", "");
  return env;
}

TEST(StudioExecutableTimeline, HelpAndVersionWorkWithoutADisplay) {
  QProcess studio;
  studio.setProcessEnvironment(withoutDisplay());
  studio.start(MOTIONMAP_STUDIO_EXE, {"--help"});
  ASSERT_TRUE(studio.waitForFinished(kTimeoutMs));
  const QString help = QString::fromUtf8(studio.readAllStandardOutput());
  EXPECT_EQ(studio.exitStatus(), QProcess::NormalExit);
  EXPECT_EQ(studio.exitCode(), 0) << studio.readAllStandardError().toStdString();
  EXPECT_TRUE(help.contains("Usage:")) << help.toStdString();
  for (const char* option : {"--method", "--frame", "--screenshot", "--shade", "--version"})
    EXPECT_TRUE(help.contains(option)) << option;

  studio.start(MOTIONMAP_STUDIO_EXE, {"--version"});
  ASSERT_TRUE(studio.waitForFinished(kTimeoutMs));
  EXPECT_EQ(studio.exitCode(), 0) << studio.readAllStandardError().toStdString();
  EXPECT_EQ(QString::fromUtf8(studio.readAllStandardOutput()).trimmed(),
            "MotionMap Studio " + studioVersion());
}

/// Every file under `dir` with its contents.
std::map<QString, QByteArray> filesUnder(const QString& dir) {
  std::map<QString, QByteArray> files;
  QDirIterator it(dir, QDir::Files | QDir::Hidden, QDirIterator::Subdirectories);
  while (it.hasNext()) {
    QFile file(it.next());
    EXPECT_TRUE(file.open(QIODevice::ReadOnly));
    files[file.fileName()] = file.readAll();
  }
  return files;
}

// --shade starts with View → Shade trustworthy blends on: a screenshot with it has the green
// shading (and its key) where one without has white.
TEST(StudioExecutableTimeline, ShadeStartsWithTheTrustworthyBlendShadingOn) {
  QTemporaryDir dir;
  const QString clip = dir.filePath("swing.bvh");
  const Clip sample = swing(1.0);
  io::write_bvh(io::from_motion(sample.skeleton, sample.motion), clip.toStdString());
  QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
  env.insert("XDG_CONFIG_HOME", dir.filePath("config"));
  QImage shots[2];
  for (int shade = 0; shade < 2; ++shade) {
    QProcess studio;
    studio.setProcessEnvironment(env);
    const QString png = dir.filePath(QString("shot%1.png").arg(shade));
    QStringList args{clip, "--method", "pca", "--screenshot", png};
    if (shade) args << "--shade";
    studio.start(MOTIONMAP_STUDIO_EXE, args);
    ASSERT_TRUE(studio.waitForFinished(kTimeoutMs));
    ASSERT_EQ(studio.exitCode(), 0) << studio.readAllStandardError().toStdString();
    shots[shade] = QImage(png).convertToFormat(QImage::Format_RGB32);
    ASSERT_FALSE(shots[shade].isNull());
  }
  ASSERT_EQ(shots[0].size(), shots[1].size());
  int greened = 0;  // white without, green-tinted with
  for (int y = 0; y < shots[0].height(); ++y)
    for (int x = 0; x < shots[0].width(); ++x) {
      const QColor off = shots[0].pixelColor(x, y), on = shots[1].pixelColor(x, y);
      greened += off == QColor(Qt::white) && on.green() > on.red() + 30 && on.green() > on.blue();
    }
  EXPECT_GT(greened, 1000);
}

TEST(StudioExecutableTimeline, AScreenshotRunLeavesTheSettingsAsTheyWere) {
  QTemporaryDir dir;
  const QString clip = dir.filePath("swing.bvh");
  const Clip sample = swing(1.0);
  io::write_bvh(io::from_motion(sample.skeleton, sample.motion), clip.toStdString());
  const QString config = dir.filePath("config");
  // The user's settings: last method LLE, one recent file, a window geometry.
  {
    QSettings user(config + "/MotionMap/MotionMap Studio.conf", QSettings::IniFormat);
    user.setValue("method", "lle");
    user.setValue("recentFiles", QStringList{"/data/walk.bvh"});
    user.setValue("geometry", QByteArray("01234"));
  }
  const std::map<QString, QByteArray> before = filesUnder(config);
  ASSERT_EQ(before.size(), 1U);
  QProcess studio;
  QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
  env.insert("XDG_CONFIG_HOME", config);
  studio.setProcessEnvironment(env);
  const QString png = dir.filePath("shot.png");
  studio.start(MOTIONMAP_STUDIO_EXE, {clip, "--method", "pca", "--screenshot", png});
  ASSERT_TRUE(studio.waitForFinished(kTimeoutMs));
  ASSERT_EQ(studio.exitCode(), 0) << studio.readAllStandardError().toStdString();
  EXPECT_FALSE(QImage(png).isNull());
  EXPECT_EQ(filesUnder(config), before);
  const QSettings after(config + "/MotionMap/MotionMap Studio.conf", QSettings::IniFormat);
  EXPECT_EQ(after.value("method").toString(), "lle");
  EXPECT_EQ(after.value("recentFiles").toStringList(), QStringList{"/data/walk.bvh"});

  // Without settings, a screenshot run leaves none behind.
  QDir(config).removeRecursively();
  studio.start(MOTIONMAP_STUDIO_EXE, {clip, "--method", "pca", "--screenshot", png});
  ASSERT_TRUE(studio.waitForFinished(kTimeoutMs));
  ASSERT_EQ(studio.exitCode(), 0) << studio.readAllStandardError().toStdString();
  EXPECT_TRUE(filesUnder(config).empty());
}

}  // namespace
}  // namespace motionmap::studio
