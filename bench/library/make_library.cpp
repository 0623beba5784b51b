// motionmap-make-library: a seeded synthetic motion library from real clips, for the scale
// measurements of issue 11 (bench/scale_table.py). See synthetic_library.h for what each clip is.
//
//   motionmap-make-library --frames 72000 --clip-frames 6000 --seed 1 --out /tmp/lib72k
//   motionmap map /tmp/lib72k/*.bvh -m pca -o /dev/null
//
// Exit codes as the motionmap tool: 0 success, 1 runtime error, 2 usage error.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <iostream>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "motionmap/core/error.h"
#include "synthetic_library.h"

namespace {

using motionmap::bench::LibraryOptions;

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Args {
  LibraryOptions options;
  std::string source = MOTIONMAP_SHARED_DATA "/cmu";
  std::string out;
  bool force = false;
  bool quiet = false;
};

const char* const kHelp =
    R"(motionmap-make-library: a seeded synthetic motion library made from real clips.

Each output clip is a chain of segments of the source clips: each segment time-warped (a smooth
monotone warp, slerp for rotations, linear for translations), mirrored left/right with some
probability, put on the output clip's skeleton and joined to the previous segment; the whole clip
gets small smooth noise. Files clip_00000.bvh, ... of --clip-frames frames each (the last holds
the rest) and manifest.txt (options and segments) go to --out. Same options, same bytes.

Usage: motionmap-make-library --frames N --out DIR [options]

  --frames N               total frames (required)
  --out DIR                output directory (required; must be empty or absent unless --force)
  --clip-frames N          frames per file (default 6000)
  --seed S                 random seed (default 1)
  --source DIR             directory of .bvh clips sharing one hierarchy (default: the CMU clips
                           in ../shared/data/cmu beside the repository)
  --max-rate R             time-warp rates within [1/R, R] (default 1.25; 1: no warp)
  --mirror-probability P   chance that a segment is mirrored (default 0.5)
  --noise-degrees D        rotation noise amplitude in degrees (default 1)
  --noise-translation T    root position noise amplitude, fraction of hip height (default 0.005)
  --segment-frames A:B     output frames per segment, from A to B (default 60:480)
  --blend-frames B         frames blended into the previous segment (default 12)
  --decimals K             decimals of the written values (default 4, as CMU's files; -1: full)
  --force                  replace clip_*.bvh and manifest.txt already in --out
  -q, --quiet              no progress on stderr
  -h, --help               this text
)";

template <class T>
T number(const std::string& option, const std::string& text) {
  try {
    std::size_t used = 0;
    T value;
    if constexpr (std::is_same_v<T, double>) {
      value = std::stod(text, &used);
    } else if constexpr (std::is_same_v<T, std::uint64_t>) {
      if (!text.empty() && text[0] == '-') throw std::invalid_argument("negative");
      value = std::stoull(text, &used);
    } else {
      const long long v = std::stoll(text, &used);
      if (v < std::numeric_limits<T>::min() || v > std::numeric_limits<T>::max()) {
        throw std::out_of_range("range");
      }
      value = static_cast<T>(v);
    }
    if (used != text.size()) throw std::invalid_argument("trailing");
    return value;
  } catch (const std::exception&) {
    throw UsageError(option + ": expected a number, found '" + text + "'");
  }
}

Args parse_args(int argc, char** argv) {
  Args args;
  bool have_frames = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw UsageError(arg + ": missing value");
      return argv[++i];
    };
    LibraryOptions& o = args.options;
    if (arg == "-h" || arg == "--help") {
      std::cout << kHelp;
      std::exit(0);
    } else if (arg == "--frames") {
      o.frames = number<std::int64_t>(arg, value());
      have_frames = true;
    } else if (arg == "--out") {
      args.out = value();
    } else if (arg == "--clip-frames") {
      o.clip_frames = number<int>(arg, value());
    } else if (arg == "--seed") {
      o.seed = number<std::uint64_t>(arg, value());
    } else if (arg == "--source") {
      args.source = value();
    } else if (arg == "--max-rate") {
      o.max_rate = number<double>(arg, value());
    } else if (arg == "--mirror-probability") {
      o.mirror_probability = number<double>(arg, value());
    } else if (arg == "--noise-degrees") {
      o.noise_degrees = number<double>(arg, value());
    } else if (arg == "--noise-translation") {
      o.noise_translation = number<double>(arg, value());
    } else if (arg == "--segment-frames") {
      const std::string v = value();
      const auto colon = v.find(':');
      if (colon == std::string::npos) throw UsageError(arg + ": expected A:B, found '" + v + "'");
      o.segment_min = number<int>(arg, v.substr(0, colon));
      o.segment_max = number<int>(arg, v.substr(colon + 1));
    } else if (arg == "--blend-frames") {
      o.blend_frames = number<int>(arg, value());
    } else if (arg == "--decimals") {
      o.decimals = number<int>(arg, value());
    } else if (arg == "--force") {
      args.force = true;
    } else if (arg == "-q" || arg == "--quiet") {
      args.quiet = true;
    } else {
      throw UsageError("unknown argument '" + arg + "' (see --help)");
    }
  }
  if (!have_frames) throw UsageError("--frames is required (see --help)");
  if (args.out.empty()) throw UsageError("--out is required (see --help)");
  try {
    args.options.validate();
  } catch (const motionmap::ParameterError& e) {
    throw UsageError(e.what());
  }
  return args;
}

// An existing --out must hold nothing but an earlier library, which --force replaces: a smaller
// library written over a larger one must not leave the larger one's last files behind.
void prepare_output(const Args& args) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(args.out, ec)) return;
  if (!fs::is_directory(args.out, ec)) throw motionmap::Error(args.out + ": not a directory");
  std::vector<fs::path> ours;
  for (const auto& entry : fs::directory_iterator(args.out)) {
    const std::string name = entry.path().filename().string();
    const bool clip = name.rfind("clip_", 0) == 0 && entry.path().extension() == ".bvh";
    if (!clip && name != "manifest.txt") {
      throw motionmap::Error(args.out + ": holds '" + name +
                             "', which is not part of a library; choose an empty directory");
    }
    ours.push_back(entry.path());
  }
  if (ours.empty()) return;
  if (!args.force) {
    throw motionmap::Error(args.out + ": already holds a library (" + std::to_string(ours.size()) +
                           " files); --force replaces it");
  }
  for (const fs::path& p : ours) fs::remove(p);
}

int run(const Args& args) {
  std::vector<std::string> notes;
  const auto sources = motionmap::bench::load_sources(args.source, &notes);
  if (!args.quiet) {
    for (const std::string& n : notes) std::cerr << "note: " << n << '\n';
  }
  prepare_output(args);
  // A progress line on a terminal only (as the motionmap tool), so logs stay clean.
  const bool show = !args.quiet && isatty(STDERR_FILENO);
  const auto progress = [&](std::int64_t done, std::int64_t total) {
    if (show) std::cerr << "\rclips " << done << "/" << total << std::flush;
  };
  const auto paths = motionmap::bench::write_library(sources, args.options, args.out, progress);
  if (show) std::cerr << '\n';
  std::cout << "wrote " << paths.size() << " clips, " << args.options.frames << " frames, to "
            << args.out << " (seed " << args.options.seed << ", " << sources.size()
            << " sources)\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(parse_args(argc, argv));
  } catch (const UsageError& e) {
    std::cerr << "motionmap-make-library: " << e.what() << '\n';
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << '\n';
    return 1;
  }
}
