// libFuzzer target: AMC text → parse_amc against a fixed skeleton. Any motionmap::Error is a
// valid outcome; crashes, hangs, sanitizer reports and other exceptions are bugs.
//
// The skeleton is CMU subject 02's (../shared/data/asfamc/02.asf) when the build passes
// MOTIONMAP_SHARED_DATA and the file is there; otherwise one written here with the bone names,
// hierarchy and dofs of every CMU skeleton, so the seed .amc files from CMU parse to the end.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "motionmap/core/error.h"
#include "motionmap/io/amc.h"
#include "motionmap/io/asf.h"

namespace {

struct BoneSpec {
  const char* name;
  const char* parent;
  const char* dofs;  // empty: none
};

constexpr BoneSpec kCmuBones[] = {
    {"lhipjoint", "root", ""},
    {"lfemur", "lhipjoint", "rx ry rz"},
    {"ltibia", "lfemur", "rx"},
    {"lfoot", "ltibia", "rx rz"},
    {"ltoes", "lfoot", "rx"},
    {"rhipjoint", "root", ""},
    {"rfemur", "rhipjoint", "rx ry rz"},
    {"rtibia", "rfemur", "rx"},
    {"rfoot", "rtibia", "rx rz"},
    {"rtoes", "rfoot", "rx"},
    {"lowerback", "root", "rx ry rz"},
    {"upperback", "lowerback", "rx ry rz"},
    {"thorax", "upperback", "rx ry rz"},
    {"lowerneck", "thorax", "rx ry rz"},
    {"upperneck", "lowerneck", "rx ry rz"},
    {"head", "upperneck", "rx ry rz"},
    {"lclavicle", "thorax", "ry rz"},
    {"lhumerus", "lclavicle", "rx ry rz"},
    {"lradius", "lhumerus", "rx"},
    {"lwrist", "lradius", "ry"},
    {"lhand", "lwrist", "rx rz"},
    {"lfingers", "lhand", "rx"},
    {"lthumb", "lwrist", "rx rz"},
    {"rclavicle", "thorax", "ry rz"},
    {"rhumerus", "rclavicle", "rx ry rz"},
    {"rradius", "rhumerus", "rx"},
    {"rwrist", "rradius", "ry"},
    {"rhand", "rwrist", "rx rz"},
    {"rfingers", "rhand", "rx"},
    {"rthumb", "rwrist", "rx rz"},
};

// A CMU-shaped ASF: every bone 1 unit long along +Y, its axis tilted so C is not the identity.
std::string cmu_like_asf() {
  std::string text =
      ":version 1.10\n:name fuzz\n:units\n  mass 1.0\n  length 0.45\n  angle deg\n:root\n"
      "  order TX TY TZ RX RY RZ\n  axis XYZ\n  position 0 0 0\n  orientation 0 0 0\n:bonedata\n";
  int id = 1;
  for (const BoneSpec& b : kCmuBones) {
    text += "  begin\n    id " + std::to_string(id++) + "\n    name " + b.name +
            "\n    direction 0 1 0\n    length 1\n    axis 10 -20 30 XYZ\n";
    if (*b.dofs) text += std::string("    dof ") + b.dofs + "\n";
    text += "  end\n";
  }
  text += ":hierarchy\n  begin\n";
  for (const BoneSpec& b : kCmuBones) text += std::string("    ") + b.parent + " " + b.name + "\n";
  text += "  end\n";
  return text;
}

motionmap::io::AsfSkeleton g_asf;

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
#ifdef MOTIONMAP_SHARED_DATA
  const std::string path = std::string(MOTIONMAP_SHARED_DATA) + "/asfamc/02.asf";
  if (std::filesystem::exists(path)) {
    g_asf = motionmap::io::read_asf(path);
    return 0;
  }
#endif
  g_asf = motionmap::io::parse_asf(cmu_like_asf(), "cmu_like.asf");
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    motionmap::io::parse_amc(text, g_asf, 120.0, "fuzz.amc");
  } catch (const motionmap::Error&) {
  }
  return 0;
}
