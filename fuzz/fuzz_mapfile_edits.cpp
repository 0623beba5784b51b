// libFuzzer target: map files changed in their structure, as another program or a hostile writer
// would leave them — datasets removed, replaced by other shapes and types, left unwritten with
// huge extents, given extreme or non-finite values, strings of any bytes, attributes changed,
// removed or added, extra datasets — then read (mapfile::read_map_file), placed on (embed::place)
// and opened for blending (mapfile::SavedMap::pose_at, which loads the map's clip). Any
// motionmap::Error is a valid outcome; crashes, hangs, sanitizer reports, other exceptions and
// memory beyond -rss_limit_mb are bugs.
//
// libFuzzer's bytes are not a file but a program of edits (read with FuzzedDataProvider): which
// seed map (map_fuzzing.h), then up to four edits of its datasets and attributes, named from the
// seed's own inventory so that nearly every edit hits something. Most programs reseal the file
// (its checksums recomputed, tests/support/map_edit.h), so that the checks behind the checksums
// are reached; the others leave the checksums as damage on a disk would.
#include <hdf5.h>
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <fuzzer/FuzzedDataProvider.h>

#include "map_fuzzing.h"
#include "motionmap/core/error.h"
#include "motionmap/mapfile/map_file.h"
#include "motionmap/mapfile/saved_map.h"
#include "support/map_edit.h"

namespace {

namespace fs = std::filesystem;
using namespace motionmap;
using motionmap::test::Edit;

// One seed map and the names an edit can aim at.
struct Seed {
  fs::path path;
  std::vector<std::string> datasets;
  std::vector<std::string> objects;     // groups and datasets, "/" first
  std::vector<std::string> attributes;  // every attribute name met in the file
};

std::vector<Seed>& seeds() {
  static std::vector<Seed> all;
  return all;
}

fs::path& folder() {
  static fs::path path;
  return path;
}

Seed inventory(const fs::path& path) {
  Seed seed{path, {}, {"/"}, {}};
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) return seed;
  H5Ovisit2(
      file, H5_INDEX_NAME, H5_ITER_NATIVE,
      [](hid_t, const char* name, const H5O_info_t* info, void* out) -> herr_t {
        Seed& s = *static_cast<Seed*>(out);
        const std::string path = std::string("/") + name;
        if (path == "/.") return 0;
        if (info->type == H5O_TYPE_DATASET) s.datasets.push_back(path);
        s.objects.push_back(path);
        return 0;
      },
      &seed, H5O_INFO_BASIC);
  for (const std::string& object : seed.objects) {
    H5Aiterate_by_name(
        file, object.c_str(), H5_INDEX_NAME, H5_ITER_NATIVE, nullptr,
        [](hid_t, const char* name, const H5A_info_t*, void* out) -> herr_t {
          auto& names = *static_cast<std::vector<std::string>*>(out);
          for (const std::string& n : names) {
            if (n == name) return 0;
          }
          names.emplace_back(name);
          return 0;
        },
        &seed.attributes, H5P_DEFAULT);
  }
  H5Fclose(file);
  return seed;
}

// A value a careless or hostile writer would put where a count, an index or a coordinate belongs.
double extreme(FuzzedDataProvider& in) {
  static const double values[] = {0.0,
                                  -1.0,
                                  1.0,
                                  2.0,
                                  0.5,
                                  -0.0,
                                  1e-300,
                                  1e9,
                                  1e300,
                                  -1e300,
                                  2147483647.0,
                                  -2147483648.0,
                                  2147483648.0,
                                  4294967296.0,
                                  std::numeric_limits<double>::quiet_NaN(),
                                  std::numeric_limits<double>::infinity(),
                                  -std::numeric_limits<double>::infinity()};
  if (in.ConsumeBool())
    return values[in.ConsumeIntegralInRange<std::size_t>(0, std::size(values) - 1)];
  return in.ConsumeFloatingPoint<double>();
}

hid_t number_type(FuzzedDataProvider& in) {
  const hid_t types[] = {H5T_IEEE_F64LE, H5T_IEEE_F32LE, H5T_STD_I32LE, H5T_STD_I64LE,
                         H5T_STD_U8LE,   H5T_STD_I8LE,   H5T_STD_U32LE, H5T_IEEE_F64BE};
  return types[in.ConsumeIntegralInRange<std::size_t>(0, std::size(types) - 1)];
}

const std::string& pick(FuzzedDataProvider& in, const std::vector<std::string>& names) {
  return names[in.ConsumeIntegralInRange<std::size_t>(0, names.size() - 1)];
}

// The edits, on stderr when MOTIONMAP_FUZZ_VERBOSE is set (to see what a crashing input does).
template <class... A>
void say(const char* format, A... args) {
  static const bool verbose = std::getenv("MOTIONMAP_FUZZ_VERBOSE") != nullptr;
  if (!verbose) return;
  std::fprintf(stderr, "edit: ");
  std::fprintf(stderr, format, args...);
  std::fprintf(stderr, "\n");
}

// One edit; false when no edit may follow (a value written into a huge unwritten dataset would
// make HDF5 allocate its whole extent in the file, and fail to close it).
bool edit(FuzzedDataProvider& in, const Seed& seed, Edit& e) {
  static const std::string kExtra = "/extra";
  const std::string& dataset = seed.datasets.empty() ? kExtra : pick(in, seed.datasets);
  switch (in.ConsumeIntegralInRange(0, 9)) {
    case 0:
      e.remove(dataset);
      say("remove %s", dataset.c_str());
      break;
    case 1: {  // another shape and number type, one value everywhere (bounded: the edit allocates)
      const auto rows = in.ConsumeIntegralInRange<hsize_t>(0, 300);
      const auto cols = in.ConsumeIntegralInRange<hsize_t>(0, 40);
      const double value = extreme(in);
      e.replace(dataset, rows, cols, number_type(in), value);
      say("replace %s by %llu x %llu of %g", dataset.c_str(), rows, cols, value);
      break;
    }
    case 2:
    case 3:  // one value changed in place: the commonest damage behind a resealed checksum
    {
      const auto index = in.ConsumeIntegralInRange<hsize_t>(0, 4096);
      const double value = extreme(in);
      e.set_flat(dataset, index, value);
      say("set %s[%llu] = %g", dataset.c_str(), index, value);
      break;
    }
    case 4: {  // an extent the reader must refuse before allocating it
      const hsize_t huge[] = {0, 1, 3, 1000, 1u << 20, hsize_t(1) << 31, hsize_t(1) << 40};
      const hsize_t rows = huge[in.ConsumeIntegralInRange<std::size_t>(0, std::size(huge) - 1)];
      const auto cols = in.ConsumeIntegralInRange<hsize_t>(0, 70);
      e.unwritten(dataset, rows, cols);
      say("unwritten %s of %llu x %llu", dataset.c_str(), rows, cols);
      if (rows * cols > (hsize_t(1) << 20)) {
        e.unsealed();  // values too many to hash here
        return false;
      }
      break;
    }
    case 5:
      if (!seed.attributes.empty()) {
        const std::string& object = pick(in, seed.objects);
        const std::string& name = pick(in, seed.attributes);
        const auto value = in.ConsumeIntegral<long long>();
        e.int_attribute(object, name, value);
        say("attribute %s of %s = %lld", name.c_str(), object.c_str(), value);
      }
      break;
    case 6:
      if (!seed.attributes.empty()) {
        const std::string text = in.ConsumeRandomLengthString(64);
        const std::string& object = pick(in, seed.objects);
        const std::string& name = pick(in, seed.attributes);
        e.text_attribute(object, name, text.c_str());
        say("attribute %s of %s = text of %zu bytes", name.c_str(), object.c_str(), text.size());
      }
      break;
    case 7:
      if (!seed.attributes.empty()) {
        const std::string& object = pick(in, seed.objects);
        const std::string& name = pick(in, seed.attributes);
        e.remove_attribute(object, name);
        say("remove attribute %s of %s", name.c_str(), object.c_str());
      }
      break;
    case 8: {  // strings of any bytes where numbers or names were
      std::vector<std::string> values(in.ConsumeIntegralInRange<std::size_t>(0, 8));
      for (std::string& v : values) v = in.ConsumeRandomLengthString(40);
      e.fixed_strings(dataset, values);
      say("strings %s: %zu", dataset.c_str(), values.size());
      break;
    }
    default: {  // a dataset the layout does not have, beside the others or inside a group
      const std::string name = pick(in, seed.objects) == "/" ? kExtra : dataset + "_extra";
      e.replace(name, in.ConsumeIntegralInRange<hsize_t>(0, 50),
                in.ConsumeIntegralInRange<hsize_t>(0, 5), number_type(in), extreme(in));
      say("extra %s", name.c_str());
      break;
    }
  }
  return true;
}

// Programs of edits to start from, longer than libFuzzer would grow its first inputs to in a
// short run: 64 of 48 bytes (seeded), into the seed folder (the last folder on the command line).
void write_programs(int argc, char** argv) {
  for (int i = argc - 1; i > 0; --i) {
    const std::string arg = argv[i];
    std::error_code ec;
    if (arg.empty() || arg[0] == '-' || !fs::is_directory(arg, ec)) continue;
    std::mt19937 random(20261128);
    for (int p = 0; p < 64; ++p) {
      std::string program(48, '\0');
      for (char& c : program) c = static_cast<char>(random() & 0xff);
      std::ofstream(fs::path(arg) / ("program-" + std::to_string(p)), std::ios::binary) << program;
    }
    return;
  }
}

// Nothing of HDF5 left open, on any path: a handle left behind keeps its file open for good.
void expect_nothing_open(const char* after) {
  const ssize_t open = H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL);
  if (open == 0) return;
  std::fprintf(stderr, "fuzz_mapfile_edits: %zd HDF5 objects left open after %s:\n", open, after);
  std::vector<hid_t> ids(static_cast<std::size_t>(open));
  H5Fget_obj_ids(H5F_OBJ_ALL, H5F_OBJ_ALL, ids.size(), ids.data());
  for (const hid_t id : ids)
    std::fprintf(stderr, "  HDF5 object of type %d\n", int(H5Iget_type(id)));
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  write_programs(*argc, *argv);
  folder() = fs::temp_directory_path() / ("fuzz-mapfile-edits-" + std::to_string(::getpid()));
  fs::create_directories(folder());
  // libFuzzer ends a run with exit(): the seeds and the edited copy go with it (a crash keeps
  // them, beside the crashing input).
  std::atexit([] {
    std::error_code ignored;
    fs::remove_all(folder(), ignored);
  });
  try {
    for (const fs::path& path :
         motionmap::fuzz::write_map_seeds(folder(), (folder() / "swing.bvh").string(), true)) {
      seeds().push_back(inventory(path));
    }
  } catch (const Error& e) {
    std::fprintf(stderr, "fuzz_mapfile_edits: no seeds written: %s\n", e.what());
  }
  if (seeds().empty()) {
    std::fprintf(stderr, "fuzz_mapfile_edits: no seed map could be written\n");
    std::abort();
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  const Seed& seed = seeds()[in.ConsumeIntegralInRange<std::size_t>(0, seeds().size() - 1)];
  say("seed %s", seed.path.filename().c_str());
  static const fs::path path = folder() / "edited.mmap.h5";
  fs::copy_file(seed.path, path, fs::copy_options::overwrite_existing);
  try {
    Edit e(path.string(),
           in.ConsumeIntegralInRange(0, 3) == 0 ? Edit::Damage::Unsealed : Edit::Damage::Sealed);
    const int edits = in.ConsumeIntegralInRange(1, 4);
    for (int i = 0; i < edits && in.remaining_bytes() > 0; ++i) {
      if (!edit(in, seed, e)) break;
    }
    e.finish();
  } catch (const Error&) {  // what the edits left cannot be sealed: not a file to read
    expect_nothing_open("sealing");
    return 0;
  }
  try {
    mapfile::MapFile map = mapfile::read_map_file(path.string());
    // Placing is the slow part (a search tree per call): half the programs skip it.
    if (in.ConsumeBool()) motionmap::fuzz::place_on(map);
    const mapfile::SavedMap saved(std::move(map));
    const Eigen::Vector2d p(in.ConsumeFloatingPointInRange(-3.0, 3.0),
                            in.ConsumeFloatingPointInRange(-3.0, 3.0));
    saved.pose_at(p, in.ConsumeIntegralInRange(1, 16));
  } catch (const Error&) {
  }
  expect_nothing_open("reading");
  return 0;
}
