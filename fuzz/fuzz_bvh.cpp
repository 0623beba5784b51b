// libFuzzer target for the BVH reader and writer: any input either parses or throws
// motionmap::Error; what parses converts to a Motion, writes, and parses back to the same
// document (skeleton and bit-identical values), otherwise abort().
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string_view>

#include "motionmap/core/error.h"
#include "motionmap/io/bvh.h"

namespace {

bool same_document(const motionmap::io::BvhDocument& a, const motionmap::io::BvhDocument& b) {
  if (a.num_frames != b.num_frames || a.frame_time != b.frame_time ||
      a.values.size() != b.values.size() ||
      (!a.values.empty() &&
       std::memcmp(a.values.data(), b.values.data(), a.values.size() * sizeof(double)) != 0) ||
      a.skeleton.num_joints() != b.skeleton.num_joints()) {
    return false;
  }
  for (int j = 0; j < a.skeleton.num_joints(); ++j) {
    const auto& x = a.skeleton.joints[j];
    const auto& y = b.skeleton.joints[j];
    if (x.name != y.name || x.parent != y.parent || x.offset != y.offset ||
        x.channels != y.channels || x.end_sites != y.end_sites) {
      return false;
    }
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  motionmap::io::BvhDocument doc;
  try {
    doc = motionmap::io::parse_bvh(text, "fuzz.bvh");
  } catch (const motionmap::Error&) {
    return 0;  // malformed input, reported properly
  }
  const motionmap::Motion motion = motionmap::io::to_motion(doc);
  if (motion.num_frames != doc.num_frames) std::abort();
  try {
    std::ostringstream out;
    motionmap::io::write_bvh(doc, out);  // a parsed document must always be writable
    const motionmap::io::BvhDocument back = motionmap::io::parse_bvh(out.str(), "written.bvh");
    if (!same_document(doc, back)) std::abort();
  } catch (const motionmap::Error&) {
    std::abort();  // the round trip must parse
  }
  return 0;
}
