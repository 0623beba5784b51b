#pragma once
// Numbers in messages: whole numbers below 1e15 in full ("100000", not "1e+05"), others in their
// shortest round-trip form, so a message shows exactly the value that was rejected.
#include <array>
#include <charconv>
#include <cmath>
#include <string>

namespace motionmap {

inline std::string format_number(double v) {
  if (std::isfinite(v) && v == std::floor(v) && std::abs(v) < 1e15) {
    return std::to_string(static_cast<long long>(v));
  }
  std::array<char, 64> buf{};
  const auto result = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  return std::string(buf.data(), result.ptr);
}

}  // namespace motionmap
