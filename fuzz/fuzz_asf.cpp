// libFuzzer target: ASF text → parse_asf → asf_to_skeleton. Any motionmap::Error is a valid
// outcome; crashes, hangs, sanitizer reports and other exceptions are bugs.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "motionmap/core/error.h"
#include "motionmap/io/asf.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const motionmap::io::AsfSkeleton asf = motionmap::io::parse_asf(text, "fuzz.asf");
    const motionmap::Skeleton skeleton = motionmap::io::asf_to_skeleton(asf);
    skeleton.validate();
  } catch (const motionmap::Error&) {
  }
  return 0;
}
