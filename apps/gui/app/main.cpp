// motionmap-studio [FILE [MORE…]] [--method M] [--frame N] [--screenshot out.png] [--shade]
// Opens FILE (a .bvh, or an .amc with its .asf) and shows its map (MORE: clips of the same
// skeleton added to that map), or a saved map file (lib.mmap.h5, from `motionmap map --save`)
// without refitting it; with --screenshot, renders the window once to a PNG and exits (1
// with a message on any error), leaving the user's settings as they were; --shade turns View →
// Shade trustworthy blends on (for a screenshot of it).
#include <QAction>
#include <QApplication>
#include <QCommandLineParser>
#include <QEventLoop>
#include <QSettings>
#include <QTemporaryDir>
#include <QTimer>
#include <cstdio>

#include "app/help_dialogs.h"
#include "app/main_window.h"
#include "scene/skeleton_view.h"

using motionmap::studio::MainWindow;

namespace {

/// Every method's name, as motionmap::embed names them: "pca, svd, …, gplvm".
QString method_names() {
  QStringList names;
  for (const motionmap::embed::Method m : motionmap::embed::all_methods())
    names << QString::fromStdString(std::string(motionmap::embed::method_name(m)));
  return names.join(", ");
}

/// The command line; `parser` holds the options once this returns.
struct Options {
  QCommandLineOption help;     // -h, --help (and --help-all)
  QCommandLineOption version;  // -v, --version
  QCommandLineOption method{"method", "Embedding method: " + method_names(), "M"};
  QCommandLineOption frame{"frame", "Frame to show", "N"};
  QCommandLineOption shot{"screenshot",
                          "Render the window to a PNG and exit (the settings are left as they "
                          "were)",
                          "PNG"};
  QCommandLineOption shade{"shade",
                           "Start with View → Shade trustworthy blends on (green where a drag "
                           "blends real frames)"};

  explicit Options(QCommandLineParser& parser)
      : help(parser.addHelpOption()), version(parser.addVersionOption()) {
    parser.setApplicationDescription(
        "MotionMap Studio: every frame of a motion-capture clip as a point on a map");
    parser.addPositionalArgument(
        "file",
        "Clip to open (.bvh, or .amc with its .asf); more files of the same skeleton join its "
        "map. Or a saved map file (.mmap.h5, from `motionmap map --save`), opened without "
        "refitting",
        "[FILE [MORE…]]");
    parser.addOptions({method, frame, shot, shade});
  }
};

void setNames() {
  QCoreApplication::setOrganizationName("MotionMap");
  QCoreApplication::setApplicationName("MotionMap Studio");
  QCoreApplication::setApplicationVersion(motionmap::studio::studioVersion());
}

/// --help and --version need no display, and a QApplication aborts without one: they are
/// answered here, by a QCoreApplication, before any QApplication exists (exits when asked).
void answerHelpAndVersion(int& argc, char** argv) {
  const QCoreApplication core(argc, argv);
  setNames();
  QCommandLineParser parser;
  const Options options(parser);
  // Errors are left to the QApplication's parse, which knows Qt's own options (-platform …).
  (void)parser.parse(QCoreApplication::arguments());
  if (parser.isSet(options.help) || parser.isSet("help-all")) parser.showHelp(0);
  if (parser.isSet(options.version)) parser.showVersion();
}

/// A screenshot run reads the user's settings (the same map and synthesis parameters as a
/// normal start) but must not change them: what the window writes (the method, the parameters,
/// recent files, geometry) goes to a copy in `dir`, dropped when the run ends.
void useScratchSettings(const QString& dir) {
  QVariantMap values;
  {
    const QSettings user;
    for (const QString& key : user.allKeys()) values.insert(key, user.value(key));
  }
  QSettings::setDefaultFormat(QSettings::IniFormat);
  QSettings::setPath(QSettings::IniFormat, QSettings::UserScope, dir);
  QSettings copy;
  for (auto it = values.cbegin(); it != values.cend(); ++it) copy.setValue(it.key(), it.value());
}

}  // namespace

int main(int argc, char** argv) {
  // The 3-D view needs OpenGL 3.3 core; the default format must be set before any widget exists.
  motionmap::studio::SkeletonView::installSurfaceFormat();

  answerHelpAndVersion(argc, argv);
  QApplication app(argc, argv);
  setNames();

  QCommandLineParser parser;
  const Options options(parser);
  parser.process(app);
  const QCommandLineOption& methodOption = options.method;
  const QCommandLineOption& frameOption = options.frame;
  const QCommandLineOption& shotOption = options.shot;

  auto fail = [](const QString& message) {
    std::fprintf(stderr, "motionmap-studio: %s\n", qPrintable(message));
    return 1;
  };
  const bool screenshot = parser.isSet(shotOption);
  const QStringList files = parser.positionalArguments();
  if (screenshot && files.isEmpty()) return fail("--screenshot needs a FILE");
  const QTemporaryDir scratch;
  if (screenshot) {
    if (!scratch.isValid()) return fail("cannot make a temporary folder for the settings");
    useScratchSettings(scratch.path());
  }

  MainWindow window;
  if (screenshot) {
    window.setInteractive(false);  // errors go to stderr, never to a dialog
    window.resize(1280, 720);      // the same picture whatever the saved geometry
  }
  if (parser.isSet(methodOption)) {
    const auto method =
        motionmap::embed::parse_method(parser.value(methodOption).toLower().toStdString());
    if (!method)
      return fail("unknown method '" + parser.value(methodOption) + "' (" + method_names() + ")");
    window.setMethod(*method);
  }
  int frame = 0;
  if (parser.isSet(frameOption)) {
    bool ok = false;
    frame = parser.value(frameOption).toInt(&ok);
    if (!ok || frame < 0)
      return fail("--frame: '" + parser.value(frameOption) + "' is not a frame number");
  }
  if (parser.isSet(options.shade)) {
    // The menu's own action, so its check mark says so too.
    if (auto* shade = window.findChild<QAction*>(QStringLiteral("shadeTrustworthyBlends")))
      shade->setChecked(true);
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
