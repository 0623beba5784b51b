#pragma once
// Where the tests find real third-party clips (../shared/data beside the repository).
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace motionmap::test {

inline std::filesystem::path shared_data_dir() {
  return MOTIONMAP_SHARED_DATA;
}

/// Path of a file under ../shared/data, e.g. shared_file("cmu/64_08.bvh").
inline std::string shared_file(const std::string& relative) {
  return (shared_data_dir() / relative).string();
}

/// Every file under ../shared/data with the given extension (".bvh"), sorted.
inline std::vector<std::string> shared_files_with_extension(const std::string& ext) {
  std::vector<std::string> out;
  std::error_code ec;
  if (!std::filesystem::is_directory(shared_data_dir(), ec)) return out;
  for (const auto& e : std::filesystem::recursive_directory_iterator(shared_data_dir(), ec)) {
    if (e.is_regular_file() && e.path().extension() == ext) out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

/// A GoogleTest name for a test parameterised by a file path: the file's stem, with every
/// character that is not a letter or digit replaced by '_' ("64_08", "Bandai_walk_01").
inline std::string file_test_name(const ::testing::TestParamInfo<std::string>& info) {
  std::string name = std::filesystem::path(info.param).stem().string();
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return name;
}

}  // namespace motionmap::test

/// Skips the current test, with a visible message, when a shared data file is absent.
#define MOTIONMAP_REQUIRE_SHARED(relative)                                                     \
  do {                                                                                         \
    if (!std::filesystem::exists(::motionmap::test::shared_file(relative))) {                  \
      GTEST_SKIP() << "shared data file absent: " << ::motionmap::test::shared_file(relative); \
    }                                                                                          \
  } while (0)
