// Libraries of clips: folders, recursive folders and @list files expanded into clip paths in a
// fixed order, and many clips loaded at once with progress and --keep-going.
#include "motionmap/io/clip_inputs.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/core/sha256.h"
#include "support/error_message.h"
#include "support/test_data.h"

namespace motionmap::io {
namespace {

namespace fs = std::filesystem;
using test::error_message;

// Two joints, three frames: a valid clip in a few lines.
constexpr const char* kTinyBvh =
    "HIERARCHY\n"
    "ROOT Hips\n"
    "{\n"
    "  OFFSET 0 0 0\n"
    "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
    "  JOINT Spine\n"
    "  {\n"
    "    OFFSET 0 10 0\n"
    "    CHANNELS 3 Zrotation Xrotation Yrotation\n"
    "    End Site\n"
    "    {\n"
    "      OFFSET 0 5 0\n"
    "    }\n"
    "  }\n"
    "}\n"
    "MOTION\n"
    "Frames: 3\n"
    "Frame Time: 0.0333333\n"
    "0 90 0 0 0 0 0 0 0\n"
    "1 90 0 0 5 0 0 10 0\n"
    "2 90 0 0 10 0 0 20 0\n";

// A fresh folder under the test's temporary directory, removed at the end of the test.
class ClipInputs : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    m_root = fs::path(::testing::TempDir()) / (std::string("clip_inputs_") + info->name());
    fs::remove_all(m_root);
    fs::create_directories(m_root);
  }
  void TearDown() override { fs::remove_all(m_root); }

  // Writes `text` to root/relative (creating folders) and returns the path.
  std::string write(const std::string& relative, const std::string& text = kTinyBvh) const {
    const fs::path p = m_root / relative;
    fs::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }
  std::string path(const std::string& relative) const { return (m_root / relative).string(); }

  fs::path m_root;
};

TEST_F(ClipInputs, AFolderGivesItsOwnClipsSortedWithoutSkeletonsOrOtherFiles) {
  write("b.bvh");
  write("A.BVH");
  write("c_01.amc", "");
  write("c.asf", "");  // a skeleton, not a clip
  write("notes.txt", "");
  write(".hidden.bvh");
  write("sub/d.bvh");  // only with --recursive
  const auto files = clip_files_in_folder(m_root.string());
  EXPECT_EQ(files, (std::vector<std::string>{path("A.BVH"), path("b.bvh"), path("c_01.amc")}));
}

TEST_F(ClipInputs, RecursiveFoldersAreSortedTogether) {
  write("b.bvh");
  write("a/z.bvh");
  write("a/deeper/y.amc", "");
  write("c/x.bvh");
  write(".git/objects.bvh");  // hidden folders are left alone
  ExpandOptions recursive;
  recursive.recursive = true;
  const auto files = clip_files_in_folder(m_root.string(), recursive);
  EXPECT_EQ(files, (std::vector<std::string>{path("a/deeper/y.amc"), path("a/z.bvh"), path("b.bvh"),
                                             path("c/x.bvh")}));
}

TEST_F(ClipInputs, AFolderWithoutClipsIsAnErrorThatMentionsRecursive) {
  write("sub/d.bvh");
  write("readme.txt", "");
  const std::string message = error_message([&] { clip_files_in_folder(m_root.string()); });
  EXPECT_NE(message.find(m_root.string() + ": error: no clip (.bvh or .amc file) in this folder"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("--recursive"), std::string::npos) << message;
  ExpandOptions recursive;
  recursive.recursive = true;
  EXPECT_EQ(clip_files_in_folder(m_root.string(), recursive).size(), 1u);
  fs::remove(path("sub/d.bvh"));
  EXPECT_NE(error_message([&] {
              clip_files_in_folder(m_root.string(), recursive);
            }).find("no clip (.bvh or .amc file) in this folder or its subfolders"),
            std::string::npos);
}

TEST_F(ClipInputs, ListFilesSkipCommentsAndBlankLinesAndResolveRelativePaths) {
  write("clips/one.bvh");
  write("two.bvh");
  write("folder/three.bvh");
  write("folder/four.bvh");
  const std::string absolute = write("elsewhere/five.bvh");
  const std::string list = path("clips/list.txt");
  const std::string text =
      "# the takes\r\n"
      "one.bvh\r\n"
      "\r\n"
      "   ../two.bvh  \n"
      "  # indented comment\n"
      "../folder\n" +
      absolute + "\n";
  const auto files = parse_clip_list(text, list);
  const fs::path dir = fs::path(list).parent_path();
  EXPECT_EQ(files,
            (std::vector<std::string>{(dir / "one.bvh").string(), (dir / "../two.bvh").string(),
                                      (dir / "../folder/four.bvh").string(),
                                      (dir / "../folder/three.bvh").string(), absolute}));
}

TEST_F(ClipInputs, AMissingListEntryNamesTheListLineAndColumn) {
  write("one.bvh");
  const std::string list = path("list.txt");
  const std::string message = error_message<ParseError>(
      [&] { parse_clip_list("# header\none.bvh\n\n  missing.bvh\n", list); });
  EXPECT_EQ(message.rfind(list + ":4:3: error: no such file or folder: 'missing.bvh'", 0), 0u)
      << message;
  EXPECT_NE(message.find(path("missing.bvh")), std::string::npos) << message;

  EXPECT_EQ(error_message([&] { parse_clip_list("# nothing\n\n", list); }),
            list + ": error: the list names no clip");
  EXPECT_NE(error_message([&] { read_clip_list(path("absent.txt")); }).find(path("absent.txt")),
            std::string::npos);
}

TEST_F(ClipInputs, ExpandKeepsTheOrderOfTheInputs) {
  write("dir/b.bvh");
  write("dir/a.bvh");
  const std::string single = write("z.bvh");
  write("list.txt", "dir/a.bvh\nz.bvh\n");
  const std::vector<std::string> inputs{single, path("dir"), "@" + path("list.txt")};
  EXPECT_EQ(expand_clip_inputs(inputs),
            (std::vector<std::string>{single, path("dir/a.bvh"), path("dir/b.bvh"),
                                      path("dir/a.bvh"), path("z.bvh")}));
  const std::vector<std::string> missing{path("nope.bvh")};
  EXPECT_EQ(error_message([&] { expand_clip_inputs(missing); }),
            path("nope.bvh") + ": error: no such file or folder");
  const std::vector<std::string> missing_list{"@" + path("nope.txt")};
  EXPECT_NE(error_message([&] { expand_clip_inputs(missing_list); }).find(path("nope.txt")),
            std::string::npos);
}

TEST_F(ClipInputs, LoadClipsReportsClipsAndFrames) {
  const std::vector<std::string> paths{write("a.bvh"), write("b.bvh"), write("c.bvh")};
  std::vector<std::string> stages;
  std::vector<double> fractions;
  const Control control([&](double f, std::string_view stage) {
    if (stages.empty() || stages.back() != stage) stages.emplace_back(stage);
    fractions.push_back(f);
  });
  const LoadedClips loaded = load_clips(paths, {}, control);
  ASSERT_EQ(loaded.clips.size(), 3u);
  EXPECT_EQ(loaded.clips[1].path, paths[1]);
  EXPECT_EQ(loaded.frames, 9);
  EXPECT_TRUE(loaded.failures.empty());
  // Clips load a clip per thread, so the frames counted when the k-th starts vary with the timing.
  ASSERT_GE(stages.size(), 2u);
  EXPECT_EQ(stages.front(), "loading 1/3 clips (0 frames)");
  EXPECT_EQ(stages.back(), "loaded 3 clips (9 frames)");
  std::vector<std::string> between;  // a clip's frames are counted once it has loaded
  for (const char* started : {"2", "3"}) {
    for (const char* frames : {"3", "6", "9"}) {
      between.push_back(std::string("loading ") + started + "/3 clips (" + frames + " frames)");
    }
  }
  for (std::size_t i = 1; i + 1 < stages.size(); ++i) {
    EXPECT_NE(std::find(between.begin(), between.end(), stages[i]), between.end()) << stages[i];
  }

  EXPECT_EQ(fractions.back(), 1.0);
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
}

TEST_F(ClipInputs, ABrokenClipIsAnErrorUnlessKeepGoing) {
  std::string broken = kTinyBvh;
  broken.replace(broken.find("1 90 0 0 5"), 1, "x");  // line 20, column 1
  const std::vector<std::string> paths{write("a.bvh"), write("broken.bvh", broken), write("c.bvh")};
  EXPECT_EQ(error_message<ParseError>([&] {
              load_clips(paths);
            }).rfind(paths[1] + ":20:1: error: expected a number", 0),
            0u);

  LoadClipsOptions keep_going;
  keep_going.keep_going = true;
  const LoadedClips loaded = load_clips(paths, keep_going);
  ASSERT_EQ(loaded.clips.size(), 2u);
  EXPECT_EQ(loaded.clips[0].path, paths[0]);
  EXPECT_EQ(loaded.clips[1].path, paths[2]);
  ASSERT_EQ(loaded.failures.size(), 1u);
  EXPECT_EQ(loaded.failures[0].rfind(paths[1] + ":20:1: error:", 0), 0u) << loaded.failures[0];
  EXPECT_EQ(loaded.frames, 6);

  // Every clip failing is an error even so, naming the first failure.
  const std::vector<std::string> all_broken{paths[1], write("not-a-clip.txt", "")};
  const std::string message = error_message([&] { load_clips(all_broken, keep_going); });
  EXPECT_NE(message.find("no clip could be loaded (2 of 2 failed)"), std::string::npos) << message;
  EXPECT_NE(message.find(paths[1] + ":20:1: error:"), std::string::npos) << message;
  EXPECT_THROW(load_clips(std::vector<std::string>{}), ParameterError);

  // Clips load a clip per thread; of several failures, the first in path order is the error,
  // whichever thread met it first.
  const std::vector<std::string> two_broken{paths[0], write("b-empty.bvh", ""), paths[1], paths[2]};
  for (int run = 0; run < 5; ++run) {
    const std::string first = error_message([&] { load_clips(two_broken); });
    EXPECT_EQ(first.rfind(two_broken[1] + ":", 0), 0u) << first;
  }
  const LoadedClips skipped = load_clips(two_broken, keep_going);
  ASSERT_EQ(skipped.failures.size(), 2u);
  EXPECT_EQ(skipped.failures[0].rfind(two_broken[1] + ":", 0), 0u) << skipped.failures[0];
  EXPECT_EQ(skipped.failures[1].rfind(paths[1] + ":20:1: error:", 0), 0u) << skipped.failures[1];
}

TEST_F(ClipInputs, LoadingCanBeCancelledBetweenClips) {
  const std::vector<std::string> paths{write("a.bvh"), write("b.bvh")};
  int reports = 0;
  const Control control([&](double, std::string_view) { ++reports; }, [&] { return reports > 1; });
  EXPECT_THROW(load_clips(paths, {}, control), Cancelled);
}

TEST(ClipInputsFormat, CountsAreGroupedByThree) {
  EXPECT_EQ(format_count(0), "0");
  EXPECT_EQ(format_count(999), "999");
  EXPECT_EQ(format_count(1000), "1 000");
  EXPECT_EQ(format_count(183000), "183 000");
  EXPECT_EQ(format_count(-1234567), "-1 234 567");
}

TEST(ClipInputsRealData, TheCmuFolderHoldsThreeClipsOfOneSkeleton) {
  MOTIONMAP_REQUIRE_SHARED("cmu/64_08.bvh");
  const auto files = clip_files_in_folder(test::shared_file("cmu"));
  EXPECT_EQ(files, (std::vector<std::string>{test::shared_file("cmu/02_03.bvh"),
                                             test::shared_file("cmu/64_08.bvh"),
                                             test::shared_file("cmu/64_09.bvh")}));
  // The ASF/AMC folder: the two motions, each finding 02.asf beside it.
  MOTIONMAP_REQUIRE_SHARED("asfamc/02.asf");
  const auto amc = clip_files_in_folder(test::shared_file("asfamc"));
  ASSERT_EQ(amc.size(), 2u);
  const LoadedClips loaded = load_clips(amc);
  EXPECT_EQ(loaded.clips.size(), 2u);
  EXPECT_EQ(loaded.frames, 298 + 173);
}

TEST(ClipInputsRealData, AClipsSha256IsTakenOfItsFileWhenAskedFor) {
  // What a map file records of its clips (LoadOptions::sha256); without it, nothing is hashed.
  MOTIONMAP_REQUIRE_SHARED("cmu/64_08.bvh");
  MOTIONMAP_REQUIRE_SHARED("asfamc/02_03.amc");
  const std::vector<std::string> paths{test::shared_file("cmu/64_08.bvh"),
                                       test::shared_file("asfamc/02_03.amc")};
  LoadClipsOptions hashed;
  hashed.load.sha256 = true;
  const LoadedClips with = load_clips(paths, hashed), without = load_clips(paths);
  for (std::size_t i = 0; i < paths.size(); ++i) {
    SCOPED_TRACE(paths[i]);
    // 64 hex digits, what `sha256sum` prints of the file (the .amc's, not its .asf's).
    EXPECT_EQ(with.clips[i].sha256, sha256_file(paths[i]));
    EXPECT_EQ(with.clips[i].sha256.size(), 64u);
    EXPECT_TRUE(without.clips[i].sha256.empty());
    EXPECT_EQ(with.clips[i].motion.rotations, without.clips[i].motion.rotations);
  }
}

}  // namespace
}  // namespace motionmap::io
