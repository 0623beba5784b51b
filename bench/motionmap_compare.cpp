// motionmap_compare: the MotionMap side of bench/compare_sklearn.py. Builds X and D of its input
// with the library, writes them for the script, runs each of the six methods a few times (timing
// the embed() call only: no I/O, no input building) and writes the maps and timings.
//
//   motionmap_compare --generate 2000 --out /tmp/cmp            # the sample swing, 2000 frames
//   motionmap_compare ../shared/data/cmu/64_08.bvh --out /tmp/cmp --repeat 5
//
// Files written to --out (raw little-endian float64, row-major, no header):
//   X.f64            #frames by #features   the feature matrix (joint-rotation quaternions)
//   P.f64            #frames by 3·#points   the heading-local point clouds
//   D.f64            #frames by #frames     the pose distances (point cloud: Euclidean of P)
//   Y_<method>.f64   #frames by 2           each method's map (pca svd mds isomap le lle)
//   result.json      sizes, parameters, per-method best and median seconds, stage times of the
//                    best run, heat used by le, peak resident memory (VmHWM) after each step
//
// Methods read X and/or D as in embed.h, with k = 20 and the other defaults, except LLE, whose
// feature matrix is P (FeatureKind::Positions): scikit-learn's LocallyLinearEmbedding picks the
// neighbours from its feature matrix, MotionMap from D, and D is exactly the Euclidean distance of
// P's rows, so both solve the same problem. (With the quaternions as X, the neighbours would
// differ; CMU's flipping thumb quaternions even split their k-NN graph.)
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "bench_inputs.h"
#include "motionmap/core/error.h"
#include "motionmap/embed/embed.h"
#include "motionmap/features/features.h"

namespace {

namespace bench = motionmap::bench;
namespace embed = motionmap::embed;
namespace features = motionmap::features;

constexpr const char* kUsage =
    "usage: motionmap_compare (--generate F | FILE...) --out DIR [--frames F] [--repeat R]\n"
    "  --generate F  the built-in sample swing of F frames at 120 fps\n"
    "  FILE...       clips (.bvh, or .amc beside its .asf) of one skeleton, concatenated\n"
    "  --frames F    keep only the first F frames of the files' features\n"
    "  --repeat R    runs per method, the best one counts (default 3; a method stops repeating\n"
    "                once its runs took 10 s together)\n"
    "  --out DIR     where X.f64, P.f64, D.f64, Y_<method>.f64 and result.json go (created)\n";

struct Args {
  int generate = 0;
  int frames = 0;
  int repeat = 3;
  std::vector<std::string> files;
  std::string out;
};

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

int positive_int(const std::string& option, const std::string& value) {
  char* end = nullptr;
  const long v = std::strtol(value.c_str(), &end, 10);
  if (value.empty() || *end != '\0' || v < 1 || v > 1000000) {
    throw UsageError(option + ": expected a positive integer, found '" + value + "'");
  }
  return static_cast<int>(v);
}

Args parse_args(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw UsageError(arg + ": missing value");
      return argv[++i];
    };
    if (arg == "--generate") {
      a.generate = positive_int(arg, value());
    } else if (arg == "--frames") {
      a.frames = positive_int(arg, value());
    } else if (arg == "--repeat") {
      a.repeat = positive_int(arg, value());
    } else if (arg == "--out") {
      a.out = value();
    } else if (arg == "-h" || arg == "--help") {
      std::fputs(kUsage, stdout);
      std::exit(0);
    } else if (!arg.empty() && arg[0] == '-') {
      throw UsageError("unknown option '" + arg + "'");
    } else {
      a.files.push_back(arg);
    }
  }
  if (a.out.empty()) throw UsageError("--out DIR is required");
  if ((a.generate > 0) == !a.files.empty()) {
    throw UsageError("give either --generate F or clip files (not both)");
  }
  return a;
}

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Peak resident memory of this process so far, in MiB: VmHWM from /proc/self/status. Not
// getrusage's ru_maxrss, which Linux carries over execve, so that a driver started from a large
// process (the Python script) would report its parent's peak.
double peak_rss_mib() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("VmHWM:", 0) == 0) return std::strtod(line.c_str() + 6, nullptr) / 1024.0;
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // KiB on Linux
}

// M row by row (rows are frames), through a buffer of a few rows rather than a full row-major
// copy, which for D would double the memory this program reports.
void write_raw(const std::filesystem::path& path, const Eigen::MatrixXd& M) {
  std::ofstream out(path, std::ios::binary);
  constexpr Eigen::Index kRows = 64;
  features::RowMatrix buffer;
  for (Eigen::Index r0 = 0; r0 < M.rows(); r0 += kRows) {
    buffer = M.middleRows(r0, std::min(kRows, M.rows() - r0));
    out.write(reinterpret_cast<const char*>(buffer.data()),
              static_cast<std::streamsize>(sizeof(double) * buffer.size()));
  }
  if (!out) throw motionmap::Error("cannot write " + path.string());
}

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string json_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

// Best and median seconds of up to `repeat` calls of `run` (fewer once 10 s are spent).
struct Timing {
  double best = 0.0;
  double median = 0.0;
  int runs = 0;
};

Timing time_runs(int repeat, const std::function<void()>& run) {
  std::vector<double> seconds;
  double spent = 0.0;
  for (int r = 0; r < repeat && (r == 0 || spent < 10.0); ++r) {
    const double t0 = now();
    run();
    seconds.push_back(now() - t0);
    spent += seconds.back();
  }
  std::sort(seconds.begin(), seconds.end());
  return {seconds.front(), seconds[seconds.size() / 2], static_cast<int>(seconds.size())};
}

int run(const Args& args) {
  const std::filesystem::path out_dir = args.out;
  std::filesystem::create_directories(out_dir);
  std::ostringstream json;

  // Input: the library's pipeline, timed once (it is not part of the comparison).
  const double t0 = now();
  bench::Input in = args.generate > 0
                        ? bench::make_input({bench::sample_clip(args.generate)})
                        : bench::make_input(bench::load_clips(args.files), args.frames);
  const double features_seconds = now() - t0;
  const double rss_features = peak_rss_mib();
  write_raw(out_dir / "X.f64", in.X);
  write_raw(out_dir / "P.f64", in.P);
  write_raw(out_dir / "D.f64", in.D);
  std::fprintf(stderr, "%s: %d frames, %d features, build_features %.3f s\n", in.source.c_str(),
               in.frames(), static_cast<int>(in.X.cols()), features_seconds);

  json << "{\n  \"source\": " << json_string(in.source) << ",\n  \"frames\": " << in.frames()
       << ",\n  \"features\": " << in.X.cols() << ",\n  \"points\": " << in.P.cols()
       << ",\n  \"k\": " << bench::kNeighbours
       << ",\n  \"threads\": " << std::max(1u, std::thread::hardware_concurrency())
       << ",\n  \"features_seconds\": " << json_number(features_seconds) << ",\n  \"methods\": {";
  std::vector<std::pair<std::string, double>> rss = {{"features", rss_features}};
  bool first = true;
  for (embed::Method method : embed::all_methods()) {
    const std::string name(embed::method_name(method));
    embed::EmbedOptions options;
    options.method = method;
    options.k = bench::kNeighbours;
    const embed::EmbedInput input{.features = method == embed::Method::Lle ? &in.P : &in.X,
                                  .distances = &in.D};
    embed::Embedding map, best;
    double best_seconds = 1e300;
    const Timing t = time_runs(args.repeat, [&] {
      const double s0 = now();
      map = embed::embed(input, options);
      if (now() - s0 < best_seconds) {
        best_seconds = now() - s0;
        best = map;
      }
    });
    rss.emplace_back(name, peak_rss_mib());
    write_raw(out_dir / ("Y_" + name + ".f64"), best.coordinates);
    std::fprintf(stderr, "  %-6s best %.4f s, median %.4f s of %d\n", name.c_str(), t.best,
                 t.median, t.runs);
    json << (first ? "" : ",") << "\n    " << json_string(name)
         << ": {\"best\": " << json_number(t.best) << ", \"median\": " << json_number(t.median)
         << ", \"runs\": " << t.runs << ", \"heat_used\": " << json_number(best.heat_used)
         << ", \"warnings\": " << best.warnings.size() << ", \"stages\": {";
    for (std::size_t s = 0; s < best.timings.size(); ++s) {
      json << (s ? ", " : "") << json_string(best.timings[s].stage) << ": "
           << json_number(best.timings[s].seconds);
    }
    json << "}}";
    first = false;
  }
  json << "\n  },\n  \"peak_rss_mib\": {";
  for (std::size_t i = 0; i < rss.size(); ++i) {
    json << (i ? ", " : "") << json_string(rss[i].first) << ": " << json_number(rss[i].second);
  }
  json << "}\n}\n";
  std::ofstream(out_dir / "result.json") << json.str();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(parse_args(argc, argv));
  } catch (const UsageError& e) {
    std::fprintf(stderr, "motionmap_compare: %s\n%s", e.what(), kUsage);
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "motionmap_compare: error: %s\n", e.what());
    return 1;
  }
}
