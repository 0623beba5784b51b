#pragma once
// Subcommands of the `motionmap` tool. Each setup_x() registers subcommand x on the app with its
// options and a callback that does the work; errors are thrown as motionmap::Error and turned
// into a message and exit code 1 by main().
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace motionmap::cli {

void setup_info(CLI::App& app);
void setup_convert(CLI::App& app);
void setup_sample(CLI::App& app);
void setup_map(CLI::App& app);
void setup_figure(CLI::App& app);
void setup_pose(CLI::App& app);
void setup_synth(CLI::App& app);
void setup_inbetween(CLI::App& app);
void setup_reach(CLI::App& app);
void setup_keyposes(CLI::App& app);

/// Escapes a string for a JSON string literal (without the quotes).
std::string json_escape(const std::string& s);

/// Creates the process's QGuiApplication on first use (main.cpp), which the render library needs
/// and never creates: the commands that draw (`map --plot`, `figure`) call it just before drawing.
/// Uses the offscreen platform unless QT_QPA_PLATFORM names one, so no display is needed, and drops
/// Qt's warning that XDG_RUNTIME_DIR is unset. Call it from the main thread.
void ensure_gui_application();

}  // namespace motionmap::cli
