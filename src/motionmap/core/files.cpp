#include "motionmap/core/files.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "motionmap/core/error.h"

namespace motionmap {

std::ifstream open_file(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw Error(path + ": error: is a directory, expected a file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": error: cannot open: " + std::strerror(errno));
  return in;
}

std::string read_text_file(const std::string& path) {
  std::ifstream in = open_file(path);
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw Error(path + ": error: cannot read: " + std::strerror(errno));
  return std::move(buffer).str();
}

std::string base_name(std::string_view path) {
  const auto slash = path.find_last_of('/');
  return std::string(slash == std::string_view::npos ? path : path.substr(slash + 1));
}

}  // namespace motionmap
