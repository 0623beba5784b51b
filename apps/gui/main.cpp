// motionmap-studio [FILE [MORE…]] [--method M] [--frame N] [--screenshot out.png]
// Opens FILE (a .bvh, or an .amc with its .asf) and shows its map (MORE: clips of the same
// skeleton added to that map), or a saved map file (lib.mmap.h5, from `motionmap map --save`)
// without refitting it; with --screenshot, renders the window once to a PNG and exits (1
// with a message on any error).
#include <QApplication>
#include <QCommandLineParser>
#include <QEventLoop>
#include <QTimer>
#include <cstdio>

#include "main_window.h"
#include "skeleton_view.h"

using motionmap::studio::MainWindow;

int main(int argc, char** argv) {
  // The 3-D view needs OpenGL 3.3 core; the default format must be set before any widget exists.
  motionmap::studio::SkeletonView::installSurfaceFormat();

  QApplication app(argc, argv);
  QApplication::setOrganizationName("MotionMap");
  QApplication::setApplicationName("MotionMap Studio");

  QCommandLineParser parser;
  parser.setApplicationDescription(
      "MotionMap Studio: every frame of a motion-capture clip as a point on a map");
  parser.addHelpOption();
  parser.addPositionalArgument(
      "file",
      "Clip to open (.bvh, or .amc with its .asf); more files of the same skeleton join its map. "
      "Or a saved map file (.mmap.h5, from `motionmap map --save`), opened without refitting",
      "[FILE [MORE…]]");
  QCommandLineOption methodOption("method", "Embedding method: pca, svd, mds, isomap, le, lle",
                                  "M");
  QCommandLineOption frameOption("frame", "Frame to show", "N");
  QCommandLineOption shotOption("screenshot", "Render the window to a PNG and exit", "PNG");
  parser.addOptions({methodOption, frameOption, shotOption});
  parser.process(app);

  auto fail = [](const QString& message) {
    std::fprintf(stderr, "motionmap-studio: %s\n", qPrintable(message));
    return 1;
  };
  const bool screenshot = parser.isSet(shotOption);
  const QStringList files = parser.positionalArguments();
  if (screenshot && files.isEmpty()) return fail("--screenshot needs a FILE");

  MainWindow window;
  if (screenshot) {
    window.setInteractive(false);  // errors go to stderr, never to a dialog
    window.resize(1280, 720);      // the same picture whatever the saved geometry
  }
  if (parser.isSet(methodOption)) {
    const auto method =
        motionmap::embed::parse_method(parser.value(methodOption).toLower().toStdString());
    if (!method)
      return fail("unknown method '" + parser.value(methodOption) +
                  "' (pca, svd, mds, isomap, le, lle)");
    window.setMethod(*method);
  }
  int frame = 0;
  if (parser.isSet(frameOption)) {
    bool ok = false;
    frame = parser.value(frameOption).toInt(&ok);
    if (!ok || frame < 0)
      return fail("--frame: '" + parser.value(frameOption) + "' is not a frame number");
  }
  window.show();

  if (!files.isEmpty()) {
    bool ok = true;
    QEventLoop loop;
    QObject::connect(&window, &MainWindow::computationFinished, &loop, [&](bool success) {
      ok = success;
      loop.quit();
    });
    bool opened = window.openFile(files.front());
    // More files join the first one's map (same skeleton).
    for (qsizetype i = 1; opened && i < files.size(); ++i) {
      if (!window.addFile(files[i]) && screenshot) return fail(window.lastError());
    }
    if (!opened) {
      if (screenshot) return fail(window.lastError());
    } else if (screenshot) {
      if (window.isComputing()) loop.exec();
      if (!ok)
        return fail(window.lastError().isEmpty() ? QStringLiteral("the map could not be computed")
                                                 : window.lastError());
      if (frame >= window.clip()->motion.num_frames) {
        return fail(QString("--frame %1: the clip has %2 frames")
                        .arg(frame)
                        .arg(window.clip()->motion.num_frames));
      }
      window.setFrame(frame);
      // Let both views paint once before grabbing.
      QTimer::singleShot(200, &loop, &QEventLoop::quit);
      loop.exec();
      const QImage image = window.screenshot();
      if (!image.save(parser.value(shotOption)))
        return fail("cannot write " + parser.value(shotOption));
      return 0;
    } else if (parser.isSet(frameOption) && window.savedMap()) {
      window.setFrame(frame);  // a saved map is shown at once
    } else if (parser.isSet(frameOption)) {
      QObject::connect(
          &window, &MainWindow::mapReady, &window, [&window, frame] { window.setFrame(frame); },
          Qt::SingleShotConnection);
    }
  }
  return app.exec();
}
