// Opening a map file of 10⁶ frames, and what verifying its checksums adds to it (issue 22's
// target: under 10 %).
//
//   build/bench/motionmap_bench --benchmark_filter='MapFileOpen'
//
// The file is the model of a landmark Isomap map of 10⁶ frames as `map --save` writes it (its
// sizes, not its values: the reader's work does not depend on them): 10⁶ × 2 coordinates, the
// samples' clips and frames, 10⁶ × 93 points (31 joints' positions), a 20-neighbour graph and
// 250 landmarks' geodesic distances to every frame — 2.9 GB, written once into the temporary
// folder (removed at exit). One iteration reads it with read_map_file, every value checked and
// every checksum verified (the reader hashes what it reads as it reads it), then hashes the same
// values again with the reader's own hasher, alone: the part of opening that verification is.
// Counters: read_s (opening, verification included), verify_s (the hashing alone), verify_share
// (verify_s ÷ (read_s − verify_s): what verifying adds to reading), GB_per_s (file bytes ÷ read_s;
// the physical bound is the page cache's memcpy rate, ~10 GB/s on one core here).
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>

#include <benchmark/benchmark.h>

#include "motionmap/mapfile/detail/checksum.h"
#include "motionmap/mapfile/map_file.h"

namespace {

namespace fs = std::filesystem;
using namespace motionmap;

constexpr int kFrames = 1000000;
constexpr int kLandmarks = 250;
constexpr int kPointColumns = 93;
constexpr int kNeighbors = 20;

mapfile::MapFile million_frames() {
  std::mt19937_64 random(22);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  auto matrix = [&](Eigen::Index r, Eigen::Index c) {
    Eigen::MatrixXd m(r, c);
    for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] = uniform(random) * 100.0;
    return m;
  };
  const int n = kFrames, clips = 1000, per = n / clips;
  mapfile::MapFile f;
  for (int c = 0; c < clips; ++c) {
    f.clips.push_back({"lib/clip_" + std::to_string(c) + ".bvh", std::string(64, 'a'), per,
                       1.0 / 30, c * per, per});
  }
  for (int i = 0; i < n; ++i) {
    f.clip_of.push_back(i / per);
    f.frame_of.push_back(i % per);
  }
  f.parameters = "method=isomap dims=2 k=20 features=quat distance=pointcloud up=y";
  f.options.embed.method = embed::Method::Isomap;
  f.options.embed.k = kNeighbors;
  f.options.embed.landmarks = kLandmarks;
  f.options.path = pipeline::MapPath::Landmarks;
  f.dense = false;
  f.k_used = kNeighbors;
  f.landmarks_used = kLandmarks;
  f.neighbor_search = "exact";
  f.graph_components = 1;
  f.skeleton = {{"Hips", "Spine", "Head"}, {-1, 0, 1}, {0, 0, 1}};
  f.joints = {"Hips", "Spine", "Head"};
  f.shared_joints = f.joints;
  f.x_columns = 124;
  f.point_columns = kPointColumns;
  f.coordinates = matrix(n, 2);
  embed::MapModel& m = f.model;
  m.method = embed::Method::Isomap;
  m.dimensions = 2;
  m.coordinates = f.coordinates;
  m.mean = matrix(1, 124);
  m.scale = matrix(1, 124).cwiseAbs();
  m.points = matrix(n, kPointColumns);
  m.metric = Metric::Euclidean;
  m.k = kNeighbors;
  embed::LandmarkFit fit;
  for (int l = 0; l < kLandmarks; ++l) fit.frames.push_back(l * (n / kLandmarks));
  fit.projection = matrix(2, kLandmarks);
  fit.mean_squared = matrix(kLandmarks, 1).cwiseAbs();
  fit.offset = matrix(2, 1);
  fit.geodesic = matrix(kLandmarks, n).cwiseAbs();
  m.landmarks = fit;
  for (int i = 0; i < n; ++i) {  // each frame joined to the next kNeighbors / 2 and previous
    m.graph.offsets.push_back(int(m.graph.targets.size()));
    for (int d = 1; d <= kNeighbors / 2; ++d) {
      for (const int j : {(i + d) % n, (i + n - d) % n}) {
        m.graph.targets.push_back(j);
        m.graph.weights.push_back(1.0 + 0.01 * d);
      }
    }
  }
  m.graph.offsets.push_back(int(m.graph.targets.size()));
  return f;
}

const std::string& million_frame_file() {
  static const std::string path = [] {
    const fs::path p = fs::temp_directory_path() / "motionmap-bench-1m-frames.mmap.h5";
    mapfile::write_map_file(p.string(), million_frames());
    std::atexit([] {
      std::error_code ec;
      fs::remove(fs::temp_directory_path() / "motionmap-bench-1m-frames.mmap.h5", ec);
    });
    return p.string();
  }();
  return path;
}

// The checksums the reader verifies, computed again over what it read.
void hash_values(const mapfile::MapFile& f) {
  using mapfile::detail::Hasher;
  auto doubles = [](const auto& m) {
    Hasher h;
    h.doubles(m.data(), std::size_t(m.size()));
    benchmark::DoNotOptimize(h.digest());
  };
  auto ints = [](const std::vector<int>& v) {
    Hasher h;
    h.int32s(v.data(), v.size());
    benchmark::DoNotOptimize(h.digest());
  };
  doubles(f.coordinates);
  doubles(f.model.points);
  doubles(f.model.landmarks->geodesic);
  doubles(Eigen::Map<const Eigen::VectorXd>(f.model.graph.weights.data(),
                                            Eigen::Index(f.model.graph.weights.size())));
  ints(f.clip_of);
  ints(f.frame_of);
  ints(f.model.graph.targets);
  ints(f.model.graph.offsets);
}

void MapFileOpen(benchmark::State& state) {
  const std::string& path = million_frame_file();
  double read_s = 0.0, verify_s = 0.0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    const mapfile::MapFile f = mapfile::read_map_file(path);
    const auto t1 = std::chrono::steady_clock::now();
    hash_values(f);
    const auto t2 = std::chrono::steady_clock::now();
    read_s += std::chrono::duration<double>(t1 - t0).count();
    verify_s += std::chrono::duration<double>(t2 - t1).count();
  }
  const double n = double(state.iterations());
  state.counters["read_s"] = read_s / n;
  state.counters["verify_s"] = verify_s / n;
  state.counters["verify_share"] = verify_s / (read_s - verify_s);
  state.counters["GB_per_s"] = double(fs::file_size(path)) / 1e9 / (read_s / n);
}
BENCHMARK(MapFileOpen)->Unit(benchmark::kSecond)->Iterations(3)->UseRealTime();

}  // namespace
