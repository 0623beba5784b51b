// libFuzzer target: the map-file reader (mapfile::read_map_file) on damaged and hostile files,
// and placing frames (embed::place) on the model of every file it accepts. libFuzzer's bytes go
// to a file of this process (HDF5 reads files). Any motionmap::Error is a valid outcome; crashes,
// hangs, sanitizer reports and other exceptions are bugs.
//
// Seeds: no map file is committed. LLVMFuzzerInitialize writes small maps of every method, on
// the dense and the landmark path (map_fuzzing.h), into the seed folder (the last folder on the
// command line). Byte mutations of a layout-3 file mostly meet its structure checksum first;
// what lies behind it is reached by fuzz_mapfile_edits, whose edits are resealed.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "map_fuzzing.h"
#include "motionmap/core/error.h"
#include "motionmap/mapfile/map_file.h"

namespace {

namespace fs = std::filesystem;
using namespace motionmap;

std::string scratch_file() {
  return (fs::temp_directory_path() / ("fuzz-mapfile-" + std::to_string(::getpid()) + ".mmap.h5"))
      .string();
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  // libFuzzer ends a run with exit(): the scratch map goes with it (a crash keeps it).
  std::atexit([] {
    std::error_code ignored;
    fs::remove(scratch_file(), ignored);
  });
  for (int i = *argc - 1; i > 0; --i) {
    const std::string arg = (*argv)[i];
    std::error_code ec;
    if (!arg.empty() && arg[0] != '-' && fs::is_directory(arg, ec)) {
      try {
        const std::string clip = (fs::temp_directory_path() /
                                  ("fuzz-mapfile-seed-" + std::to_string(::getpid()) + ".bvh"))
                                     .string();
        motionmap::fuzz::write_map_seeds(arg, clip, false);
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
    motionmap::fuzz::place_on(map);
  } catch (const Error&) {
  }
  return 0;
}
