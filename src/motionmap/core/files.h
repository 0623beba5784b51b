#pragma once
// Files as the library reads and names them: a whole file into memory, and a path's last part
// for messages and CSV comments.
#include <fstream>
#include <string>
#include <string_view>

namespace motionmap {

/// `path` opened for binary reading. @throws Error "path: error: is a directory, expected a
/// file", or "path: error: cannot open: <the system's reason>".
std::ifstream open_file(const std::string& path);

/// Reads a whole file into memory. @throws Error naming the path and the system's reason.
std::string read_text_file(const std::string& path);

/// The part of `path` after its last '/' ("data/64_08.bvh" → "64_08.bvh"); `path` itself when it
/// has none.
std::string base_name(std::string_view path);

}  // namespace motionmap
