// libFuzzer target: the two CSV readers — path CSV (parse_path_csv, then resample_path) and map
// CSV (parse_map_csv) — on the same bytes. Any motionmap::Error is a valid outcome; crashes,
// hangs, sanitizer reports and other exceptions are bugs.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "motionmap/core/error.h"
#include "motionmap/pipeline/map_csv.h"
#include "motionmap/synth/path.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const motionmap::synth::MapPath path = motionmap::synth::parse_path_csv(text, "fuzz.csv");
    // A bounded frame count keeps a path with huge times an error, not a giant allocation.
    motionmap::synth::resample_path(path, 1.0 / 120.0, 1.0, 100000);
  } catch (const motionmap::Error&) {
  }
  try {
    motionmap::pipeline::parse_map_csv(text, "fuzz.csv");
  } catch (const motionmap::Error&) {
  }
  return 0;
}
