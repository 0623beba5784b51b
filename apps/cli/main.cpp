// motionmap — map motion-capture clips to 2D, from the command line.
// Exit codes: 0 success, 1 runtime error (bad file, failed computation), 2 usage error.
#include <cstdio>
#include <iostream>

#include <QGuiApplication>

#include "commands.h"
#include "motionmap/core/error.h"

namespace motionmap::cli {

namespace {

QtMessageHandler g_qt_handler = nullptr;

// Qt warns on every headless run where XDG_RUNTIME_DIR is unset (root in a container, CI):
// noise on a batch tool's stderr, since drawing into files never uses that folder.
void quiet_runtime_dir_warning(QtMsgType type, const QMessageLogContext& context,
                               const QString& message) {
  if (type == QtWarningMsg && message.startsWith(QLatin1String("QStandardPaths: XDG_RUNTIME_DIR")))
    return;
  if (g_qt_handler) return g_qt_handler(type, context, message);
  std::fprintf(stderr, "%s\n", qPrintable(qFormatLogMessage(type, context, message)));
}

}  // namespace

void ensure_gui_application() {
  if (QCoreApplication::instance() != nullptr) return;
  // Offscreen whether or not there is a display: the CLI only draws into files, so it needs no
  // display connection and draws the same everywhere. A platform the user chose is kept.
  if (qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM")) qputenv("QT_QPA_PLATFORM", "offscreen");
  g_qt_handler = qInstallMessageHandler(quiet_runtime_dir_warning);
  // Made only by the commands that draw, so the others start without loading a Qt platform.
  // Qt keeps argc/argv for the application's lifetime, hence static ones; CLI11 has already
  // parsed the real command line.
  static int argc = 1;
  static char name[] = "motionmap";
  static char* argv[] = {name, nullptr};
  // Destroyed with the other statics at exit; leaking it instead leaves fontconfig's caches
  // unreachable, which LeakSanitizer reports.
  static QGuiApplication app(argc, argv);
}

}  // namespace motionmap::cli

int main(int argc, char** argv) {
  CLI::App app{
      "motionmap — inspect, convert and map motion-capture clips (BVH, Acclaim ASF/AMC), and\n"
      "synthesize new poses and motions from the maps.\n"
      "Run `motionmap COMMAND --help` for a command's options."};
  app.require_subcommand(1);
  app.set_version_flag("--version", "motionmap 0.1.0");
  motionmap::cli::setup_info(app);
  motionmap::cli::setup_convert(app);
  motionmap::cli::setup_sample(app);
  motionmap::cli::setup_map(app);
  motionmap::cli::setup_figure(app);
  motionmap::cli::setup_pose(app);
  motionmap::cli::setup_synth(app);
  motionmap::cli::setup_inbetween(app);
  motionmap::cli::setup_reach(app);
  motionmap::cli::setup_keyposes(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);  // prints the usage error and a hint to stderr
    return 2;
  } catch (const motionmap::Error& e) {
    std::cerr << "motionmap: " << e.what() << '\n';
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "motionmap: error: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
