#pragma once
// Numbers in messages: whole numbers below 1e15 in full ("100000", not "1e+05"), others in their
// shortest round-trip form, so a message shows exactly the value that was rejected; or rounded to
// a few digits where the value is a measurement.
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace motionmap {

inline std::string format_number(double v) {
  if (std::isfinite(v) && v == std::floor(v) && std::abs(v) < 1e15) {
    return std::to_string(static_cast<long long>(v));
  }
  std::array<char, 64> buf{};
  const auto result = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  return std::string(buf.data(), result.ptr);
}

/// v with `significant` significant digits (printf's %g), for figures in notes and warnings
/// where the exact value is noise; −0 is written 0.
inline std::string format_number(double v, int significant) {
  std::array<char, 64> buf{};
  std::snprintf(buf.data(), buf.size(), "%.*g", significant, v == 0.0 ? 0.0 : v);
  return buf.data();
}

/// A count with its digits grouped by three and a space between groups ("183 000"), for progress
/// lines and notes.
inline std::string format_count(long long n) {
  const auto magnitude = static_cast<unsigned long long>(n);
  std::string digits = std::to_string(n < 0 ? 0ULL - magnitude : magnitude), out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ' ';
    out += digits[i];
  }
  return n < 0 ? "-" + out : out;
}

/// "a", "a, b, c": at most `most` names, then " and N more", for messages that list joints or
/// clips.
inline std::string name_list(const std::vector<std::string>& names, std::size_t most = 12) {
  std::string out;
  const std::size_t shown = std::min(names.size(), most);
  for (std::size_t i = 0; i < shown; ++i) out += (i ? ", " : "") + names[i];
  if (names.size() > shown) out += " and " + std::to_string(names.size() - shown) + " more";
  return out;
}

}  // namespace motionmap
