// SHA-256 against FIPS 180-4's examples, against itself fed in pieces, and against the system's
// `sha256sum` on files whose lengths sit at every padding boundary and on the real clips.
#include "motionmap/core/sha256.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "support/error_message.h"
#include "support/test_data.h"

namespace motionmap {
namespace {

TEST(Sha256, KnownAnswers) {
  // FIPS 180-4 examples (NIST's "SHA256.pdf", "SHA256_2.pdf") and the empty message.
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(sha256_hex(std::string(1000000, 'a')),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sha256, PiecesGiveTheSameDigestAsTheWhole) {
  std::string message;
  for (int i = 0; i < 300; ++i) message += char(i * 7 + 3);
  const std::string whole = sha256_hex(message);
  for (std::size_t cut = 0; cut <= message.size(); cut += 13) {
    for (std::size_t cut2 = cut; cut2 <= message.size(); cut2 += 29) {
      Sha256 h;
      h.update(std::string_view(message).substr(0, cut));
      h.update(std::string_view(message).substr(cut, cut2 - cut));
      h.update(std::string_view(message).substr(cut2));
      ASSERT_EQ(h.hex(), whole) << "cut at " << cut << " and " << cut2;
    }
  }
}

// What `sha256sum PATH` prints (its first word), or "" when the tool is not there.
std::string system_sha256(const std::string& path) {
  const std::string command = "sha256sum '" + path + "' 2>/dev/null";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return {};
  char buf[128] = {};
  const std::size_t n = std::fread(buf, 1, sizeof buf - 1, pipe);
  pclose(pipe);
  const std::string out(buf, n);
  const auto space = out.find(' ');
  return space == 64 ? out.substr(0, 64) : std::string();
}

TEST(Sha256, FilesMatchSha256sum) {
  if (system_sha256("/dev/null").empty()) GTEST_SKIP() << "sha256sum is not available";
  const auto dir =
      std::filesystem::temp_directory_path() / ("motionmap-sha256-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  // Lengths around the 55/56-byte padding boundary and the 64-byte block, and a multi-block file.
  for (const std::size_t length : {0, 1, 55, 56, 57, 63, 64, 65, 119, 120, 128, 1000, 3000001}) {
    const std::string path = (dir / ("f" + std::to_string(length))).string();
    {
      std::ofstream out(path, std::ios::binary);
      for (std::size_t i = 0; i < length; ++i) out.put(char((i * 131 + length) & 0xff));
    }
    EXPECT_EQ(sha256_file(path), system_sha256(path)) << length << " bytes";
  }
  std::filesystem::remove_all(dir);
  int checked = 0;
  for (const std::string& clip : test::shared_files_with_extension(".bvh")) {
    EXPECT_EQ(sha256_file(clip), system_sha256(clip)) << clip;
    ++checked;
  }
  if (checked == 0) std::printf("note: no shared clips; checked the generated files only\n");
}

TEST(Sha256, UnreadableFilesAreErrorsNamingThePath) {
  EXPECT_EQ(test::error_message([] { sha256_file("/nonexistent/take.bvh"); }),
            "/nonexistent/take.bvh: error: cannot open: No such file or directory");
  const std::string dir = std::filesystem::temp_directory_path().string();
  EXPECT_EQ(test::error_message([&] { sha256_file(dir); }),
            dir + ": error: is a directory, expected a file");
}

}  // namespace
}  // namespace motionmap
