// motionmap — map motion-capture clips to 2D, from the command line.
// Exit codes: 0 success, 1 runtime error (bad file, failed computation), 2 usage error.
#include <iostream>

#include "commands.h"
#include "motionmap/core/error.h"

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
