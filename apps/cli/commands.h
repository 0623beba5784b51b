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

/// Escapes a string for a JSON string literal (without the quotes).
std::string json_escape(const std::string& s);

}  // namespace motionmap::cli
