#pragma once
// What the ASF reader (asf.cpp) and the AMC reader (amc.cpp) both need to know about a Dof. Not
// public API: only the io stage's sources include it.
#include <array>
#include <string_view>

#include "motionmap/io/asf.h"

namespace motionmap::io {

/// The dof's name as ASF and AMC files write it, lower case: "rx" … "tz", "l".
inline std::string_view dof_name(Dof d) {
  static constexpr std::array<std::string_view, 7> kNames = {"rx", "ry", "rz", "tx",
                                                             "ty", "tz", "l"};
  return kNames[static_cast<int>(d)];
}

inline bool is_rotation(Dof d) {
  return d == Dof::RX || d == Dof::RY || d == Dof::RZ;
}

inline bool is_translation(Dof d) {
  return d == Dof::TX || d == Dof::TY || d == Dof::TZ;
}

/// The axis index of a rotation or translation dof: RX, TX → 0, RY, TY → 1, RZ, TZ → 2.
inline int dof_axis(Dof d) {
  return static_cast<int>(d) % 3;
}

}  // namespace motionmap::io
