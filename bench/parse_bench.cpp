// BVH parse (and write) throughput on the real files of ../shared/data, in memory, and on a
// ~20 MB file made by repeating the motion rows of the largest one, so that the figure is not
// dominated by per-file overhead.
//   motionmap_bench --benchmark_filter=Bvh
#include <benchmark/benchmark.h>

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "motionmap/core/error.h"
#include "motionmap/core/files.h"
#include "motionmap/io/bvh.h"
#include "motionmap/io/load.h"

namespace {

struct TextFile {
  std::string name;
  std::string text;
};

const std::vector<TextFile>& real_files() {
  static const std::vector<TextFile> files = [] {
    std::vector<TextFile> out;
    std::error_code ec;
    const std::filesystem::path dir = MOTIONMAP_SHARED_DATA;
    for (const auto& e : std::filesystem::recursive_directory_iterator(dir, ec)) {
      if (e.is_regular_file() && e.path().extension() == ".bvh") {
        out.push_back({e.path().lexically_relative(dir).string(),
                       motionmap::read_text_file(e.path().string())});
      }
    }
    std::sort(out.begin(), out.end(),
              [](const TextFile& a, const TextFile& b) { return a.name < b.name; });
    return out;
  }();
  return files;
}

// The largest real file with its motion rows repeated to about `target_bytes`.
const std::string& large_file() {
  static const std::string text = [] {
    constexpr std::size_t kTargetBytes = 20u << 20;
    const auto& files = real_files();
    if (files.empty()) return std::string();
    const TextFile& big = *std::max_element(
        files.begin(), files.end(),
        [](const TextFile& a, const TextFile& b) { return a.text.size() < b.text.size(); });
    const int frames = motionmap::io::parse_bvh(big.text).num_frames;
    const std::size_t frames_at = big.text.find("Frames:");
    const std::size_t time_at = big.text.find("Frame Time:", frames_at);
    const std::size_t rows_at = big.text.find('\n', time_at) + 1;
    std::string rows = big.text.substr(rows_at);
    if (rows.empty() || rows.back() != '\n') rows += '\n';
    const std::size_t copies = std::max<std::size_t>(1, kTargetBytes / rows.size());
    std::string out = big.text.substr(0, frames_at) + "Frames: " + std::to_string(frames * copies) +
                      "\n" + big.text.substr(time_at, rows_at - time_at);
    out.reserve(out.size() + rows.size() * copies);
    for (std::size_t i = 0; i < copies; ++i) out += rows;
    return out;
  }();
  return text;
}

void parse_texts(benchmark::State& state, const std::vector<const std::string*>& texts) {
  if (texts.empty() || texts.front()->empty()) {
    state.SkipWithError("no .bvh files under " MOTIONMAP_SHARED_DATA);
    return;
  }
  std::size_t bytes = 0;
  for (const auto* t : texts) bytes += t->size();
  for (auto _ : state) {
    for (const auto* t : texts) {
      auto doc = motionmap::io::parse_bvh(*t);
      benchmark::DoNotOptimize(doc.values.data());
    }
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(bytes));
}

void BM_BvhParseAllRealFiles(benchmark::State& state) {
  std::vector<const std::string*> texts;
  for (const auto& f : real_files()) texts.push_back(&f.text);
  parse_texts(state, texts);
}
BENCHMARK(BM_BvhParseAllRealFiles)->Unit(benchmark::kMillisecond);

void BM_BvhParseLarge(benchmark::State& state) {
  parse_texts(state, {&large_file()});
  state.counters["MB"] = static_cast<double>(large_file().size()) / 1e6;
}
BENCHMARK(BM_BvhParseLarge)->Unit(benchmark::kMillisecond);

void BM_BvhWriteLarge(benchmark::State& state) {
  if (large_file().empty()) {
    state.SkipWithError("no .bvh files under " MOTIONMAP_SHARED_DATA);
    return;
  }
  const auto doc = motionmap::io::parse_bvh(large_file());
  std::size_t bytes = 0;
  for (auto _ : state) {
    std::ostringstream out;
    motionmap::io::write_bvh(doc, out);
    bytes = out.str().size();
    benchmark::DoNotOptimize(bytes);
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(bytes));
}
BENCHMARK(BM_BvhWriteLarge)->Unit(benchmark::kMillisecond);

// One benchmark per real file, registered at start-up.
[[maybe_unused]] const bool kPerFileRegistered = [] {
  for (const auto& f : real_files()) {
    benchmark::RegisterBenchmark(("BM_BvhParseFile/" + f.name).c_str(),
                                 [&f](benchmark::State& state) { parse_texts(state, {&f.text}); })
        ->Unit(benchmark::kMicrosecond);
  }
  return true;
}();

}  // namespace
