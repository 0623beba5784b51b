#include "motionmap/core/error.h"

#include <cstdio>

namespace motionmap {

namespace {
std::string format_location(const std::string& path, std::size_t line, std::size_t column,
                            const std::string& message) {
  return path + ":" + std::to_string(line) + ":" + std::to_string(column) + ": error: " + message;
}
}  // namespace

ParseError::ParseError(std::string path, std::size_t line, std::size_t column,
                       const std::string& message)
    : Error(format_location(path, line, column, message)),
      m_path(std::move(path)),
      m_line(line),
      m_column(column),
      m_message(message) {}

std::string quote_token(std::string_view token) {
  constexpr std::size_t kMaxShown = 40;
  std::string out;
  for (std::size_t i = 0; i < token.size() && i < kMaxShown; ++i) {
    const auto c = static_cast<unsigned char>(token[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02X", c);
      out += buf;
    }
  }
  if (token.size() > kMaxShown) out += "...";
  return out;
}

}  // namespace motionmap
