// libFuzzer target: the map-file reader (mapfile::read_map_file) on damaged and hostile files,
// and placing frames (embed::place) on the model of every file it accepts. libFuzzer's bytes go
// to a file of this process (HDF5 reads files). Any motionmap::Error is a valid outcome; crashes,
// hangs, sanitizer reports and other exceptions are bugs.
//
// Seeds: no map file is committed. LLVMFuzzerInitialize writes small maps of every method, on
// the dense and the landmark path, of a procedural clip into the seed folder (the last folder on
// the command line), afresh at each start so that they are of the layout this build writes.
// Byte mutations of a layout-3 file mostly meet its structure checksum first; what lies behind
// it is reached by mutations of the values and by tests/mapfile's resealed edits.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "motionmap/core/error.h"
#include "motionmap/embed/placement.h"
#include "motionmap/io/bvh.h"
#include "motionmap/io/load.h"
#include "motionmap/mapfile/map_file.h"
#include "motionmap/pipeline/clip_map.h"
#include "motionmap/sample/sample_clip.h"

namespace {

namespace fs = std::filesystem;
using namespace motionmap;

std::string scratch_file() {
  return (fs::temp_directory_path() / ("fuzz-mapfile-" + std::to_string(::getpid()) + ".mmap.h5"))
      .string();
}

void write_seeds(const fs::path& folder) {
  sample::SampleOptions options;
  options.fps = 30;
  options.seconds = 2;
  const Clip sample = sample::make_sample_clip(sample::SampleKind::Swing, options);
  const std::string clip_path =
      (fs::temp_directory_path() / ("fuzz-mapfile-seed-" + std::to_string(::getpid()) + ".bvh"))
          .string();
  io::write_bvh(io::from_motion(sample.skeleton, sample.motion), clip_path);
  const std::vector<Clip> clips{io::load_clip(clip_path)};
  const embed::Method methods[] = {embed::Method::Pca,
                                   embed::Method::Svd,
                                   embed::Method::Mds,
                                   embed::Method::Isomap,
                                   embed::Method::LaplacianEigenmap,
                                   embed::Method::Lle,
                                   embed::Method::Umap};
  for (const embed::Method method : methods) {
    for (const bool landmarks : {false, true}) {
      if (landmarks && (method == embed::Method::Pca || method == embed::Method::Svd)) continue;
      pipeline::ClipMapOptions o;
      o.embed.method = method;
      o.embed.k = 6;
      if (landmarks) o.path = pipeline::MapPath::Landmarks;
      const std::string name = std::string(embed::method_name(method)) +
                               (landmarks ? "-landmarks" : "-dense") + ".mmap.h5";
      try {
        mapfile::write_map_file((folder / name).string(),
                                mapfile::make_map_file(clips, pipeline::map_clips(clips, o), o));
      } catch (const Error& e) {  // a seed fewer, said
        std::fprintf(stderr, "fuzz_mapfile: no seed %s: %s\n", name.c_str(), e.what());
      }
    }
  }
  fs::remove(clip_path);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  for (int i = *argc - 1; i > 0; --i) {
    const std::string arg = (*argv)[i];
    std::error_code ec;
    if (!arg.empty() && arg[0] != '-' && fs::is_directory(arg, ec)) {
      try {
        write_seeds(arg);
      } catch (const Error& e) {
        std::fprintf(stderr, "fuzz_mapfile: no seeds written: %s\n", e.what());
      }
      break;
    }
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = scratch_file();
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  }
  try {
    const mapfile::MapFile map = mapfile::read_map_file(path);
    // What read_map_file() returns can be placed on without further checks.
    Eigen::MatrixXd X = Eigen::MatrixXd::Zero(3, map.x_columns);
    RowMatrix points = RowMatrix::Zero(3, map.point_columns);
    for (Eigen::Index i = 0; i < points.size(); ++i) points.data()[i] = double(i % 7) - 3.0;
    for (Eigen::Index i = 0; i < X.size(); ++i) X.data()[i] = double(i % 5) * 0.25;
    embed::place(map.model, embed::PlaceInput{&X, &points});
  } catch (const Error&) {
  }
  return 0;
}
