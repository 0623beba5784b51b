#include "motionmap/io/bvh.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "motionmap/core/text_cursor.h"
#include "motionmap/skeleton/forward_kinematics.h"

namespace motionmap::io {
namespace {

// Two joints and an End Site, one frame per row; used (with edits) by most tests below.
constexpr const char* kSmall =
    "HIERARCHY\n"
    "ROOT Hips\n"
    "{\n"
    "\tOFFSET 0 0 0\n"
    "\tCHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation\n"
    "\tJOINT Spine\n"
    "\t{\n"
    "\t\tOFFSET 0 5 0\n"
    "\t\tCHANNELS 3 Zrotation Xrotation Yrotation\n"
    "\t\tEnd Site\n"
    "\t\t{\n"
    "\t\t\tOFFSET 0 2 0\n"
    "\t\t}\n"
    "\t}\n"
    "}\n"
    "MOTION\n"
    "Frames: 2\n"
    "Frame Time: 0.0333333\n"
    "1 2 3 10 20 30 40 50 60\n"
    "4 5 6 -10 -20 -30 -40 -50 -60\n";

ParseError parse_error(std::string_view text) {
  try {
    parse_bvh(text, "t.bvh");
  } catch (const ParseError& e) {
    return e;
  }
  ADD_FAILURE() << "no ParseError for:\n" << text;
  return ParseError("", 0, 0, "");
}

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// `text` up to (not including) the first occurrence of `at`: a file cut short there.
std::string upto(const std::string& text, const std::string& at) {
  const auto pos = text.find(at);
  EXPECT_NE(pos, std::string::npos) << at;
  return text.substr(0, pos);
}

std::string written(const BvhDocument& doc) {
  std::ostringstream out;
  write_bvh(doc, out);
  return out.str();
}

// Same skeleton (names, parents, offsets, channels, end sites) and bit-identical values.
void expect_same_document(const BvhDocument& a, const BvhDocument& b) {
  ASSERT_EQ(a.skeleton.num_joints(), b.skeleton.num_joints());
  for (int j = 0; j < a.skeleton.num_joints(); ++j) {
    const Joint& x = a.skeleton.joints[j];
    const Joint& y = b.skeleton.joints[j];
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.parent, y.parent);
    EXPECT_EQ(x.offset, y.offset) << x.name;
    EXPECT_EQ(x.channels, y.channels) << x.name;
    EXPECT_EQ(x.end_sites, y.end_sites) << x.name;
  }
  EXPECT_EQ(a.num_frames, b.num_frames);
  EXPECT_EQ(a.frame_time, b.frame_time);
  ASSERT_EQ(a.values.size(), b.values.size());
  // memcmp: bit-exact, so −0 and 0 differ (and no null pointers reach it for empty values).
  EXPECT_TRUE(a.values.empty() ||
              std::memcmp(a.values.data(), b.values.data(), a.values.size() * sizeof(double)) == 0);
}

Eigen::Quaterniond about(const Eigen::Vector3d& axis, double degrees) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(deg_to_rad(degrees), axis));
}

// --- reading ---------------------------------------------------------------------------------

TEST(BvhParse, ReadsHierarchyChannelsAndValues) {
  const BvhDocument doc = parse_bvh(kSmall);
  ASSERT_EQ(doc.skeleton.num_joints(), 2);
  const Joint& hips = doc.skeleton.joints[0];
  const Joint& spine = doc.skeleton.joints[1];
  EXPECT_EQ(hips.name, "Hips");
  EXPECT_EQ(hips.parent, -1);
  EXPECT_EQ(spine.name, "Spine");
  EXPECT_EQ(spine.parent, 0);
  EXPECT_EQ(spine.offset, Eigen::Vector3d(0, 5, 0));
  EXPECT_EQ(hips.channels,
            (std::vector<ChannelType>{ChannelType::Xposition, ChannelType::Yposition,
                                      ChannelType::Zposition, ChannelType::Zrotation,
                                      ChannelType::Yrotation, ChannelType::Xrotation}));
  EXPECT_EQ(spine.channels,
            (std::vector<ChannelType>{ChannelType::Zrotation, ChannelType::Xrotation,
                                      ChannelType::Yrotation}));
  ASSERT_EQ(spine.end_sites.size(), 1u);
  EXPECT_EQ(spine.end_sites[0], Eigen::Vector3d(0, 2, 0));
  EXPECT_TRUE(hips.end_sites.empty());
  EXPECT_EQ(doc.num_frames, 2);
  EXPECT_EQ(doc.num_channels(), 9);
  EXPECT_EQ(doc.frame_time, 0.0333333);
  EXPECT_EQ(doc.value(0, 0), 1.0);
  EXPECT_EQ(doc.value(0, 8), 60.0);
  EXPECT_EQ(doc.value(1, 3), -10.0);
  EXPECT_TRUE(doc.warnings.empty());
}

TEST(BvhParse, WhitespaceVariantsGiveTheSameDocument) {
  const BvhDocument reference = parse_bvh(kSmall);
  std::string crlf, cr, spaced;
  for (const char c : std::string(kSmall)) {
    crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
    cr += c == '\n' ? '\r' : c;
    spaced += c == ' '    ? std::string(" \t  ")
              : c == '\n' ? std::string("  \n\n")
                          : std::string(1, c);
  }
  // Mixed line ends as in the CMU conversions (CRLF with a few LF lines), a BOM, no final newline.
  std::string mixed = "\xEF\xBB\xBF" + crlf;
  mixed = replace(mixed, "Frames: 2\r\n", "Frames:\t2\n");
  mixed.resize(mixed.size() - 2);
  for (const std::string& text : {crlf, cr, spaced, mixed}) {
    expect_same_document(parse_bvh(text), reference);
  }
}

TEST(BvhParse, NumberFormatsOfRealExporters) {
  std::string text = replace(kSmall, "1 2 3 10 20 30 40 50 60",
                             "\t-0.0000 .0083333 1.5e-07 +2 -3.25E+01 0 0 0 0   ");
  text = replace(text, "Frame Time: 0.0333333", "Frame Time:\t0.016666666666666666");
  const BvhDocument doc = parse_bvh(text);
  EXPECT_EQ(doc.value(0, 0), 0.0);
  EXPECT_TRUE(std::signbit(doc.value(0, 0)));
  EXPECT_EQ(doc.value(0, 1), 0.0083333);
  EXPECT_EQ(doc.value(0, 2), 1.5e-07);
  EXPECT_EQ(doc.value(0, 3), 2.0);
  EXPECT_EQ(doc.value(0, 4), -32.5);
  EXPECT_EQ(doc.frame_time, 0.016666666666666666);
}

TEST(BvhParse, NamesWithColonsSpacesAndBraceOnTheSameLine) {
  std::string text = replace(kSmall, "ROOT Hips\n{", "ROOT mixamorig:Hips {");
  text = replace(text, "JOINT Spine", "JOINT Left Up Leg  ");
  const BvhDocument doc = parse_bvh(text);
  EXPECT_EQ(doc.skeleton.joints[0].name, "mixamorig:Hips");
  EXPECT_EQ(doc.skeleton.joints[1].name, "Left Up Leg");
  expect_same_document(parse_bvh(written(doc)), doc);
}

TEST(BvhParse, SeveralRootsLeafJointWithoutEndSiteAndChannelsBeforeOffset) {
  const BvhDocument doc = parse_bvh(
      "HIERARCHY\n"
      "ROOT A\n{\n OFFSET 1 0 0\n CHANNELS 3 Xposition Yposition Zposition\n"
      " JOINT A1\n {\n  CHANNELS 1 Yrotation\n  OFFSET 0 1 0\n }\n}\n"
      "ROOT B\n{\n OFFSET 0 0 1\n CHANNELS 0\n End Site\n {\n OFFSET 0 0 1\n }\n"
      " End Site\n {\n OFFSET 0 1 1\n }\n}\n"
      "ROOT C\n{\n OFFSET 0 0 2\n}\n"
      "MOTION\nFrames: 1\nFrame Time: 1\n1 2 3 45\n");
  ASSERT_EQ(doc.skeleton.num_joints(), 4);
  EXPECT_EQ(doc.skeleton.roots(), (std::vector<int>{0, 2, 3}));
  EXPECT_EQ(doc.skeleton.joints[1].parent, 0);
  EXPECT_EQ(doc.skeleton.joints[1].offset, Eigen::Vector3d(0, 1, 0));
  EXPECT_EQ(doc.skeleton.joints[2].end_sites.size(), 2u);
  EXPECT_TRUE(doc.skeleton.joints[3].channels.empty());
  EXPECT_EQ(doc.num_channels(), 4);
  expect_same_document(parse_bvh(written(doc)), doc);
}

TEST(BvhParse, ZeroFramesIsASkeletonWithoutMotion) {
  BvhDocument doc = parse_bvh(
      replace(kSmall, "Frames: 2", "Frames: 0").substr(0, std::string(kSmall).find("1 2 3")));
  EXPECT_EQ(doc.num_frames, 0);
  EXPECT_TRUE(doc.values.empty());
  EXPECT_TRUE(doc.warnings.empty());
  const Motion m = to_motion(doc);
  EXPECT_EQ(m.num_frames, 0);
  EXPECT_EQ(m.num_joints, 2);
  expect_same_document(parse_bvh(written(doc)), doc);
}

TEST(BvhParse, SkeletonWithoutChannelsHasEmptyRows) {
  const char* text =
      "HIERARCHY\nROOT A\n{\nOFFSET 1 2 3\n}\nMOTION\nFrames: 3\nFrame Time: 0.5\n\n\n\n";
  const BvhDocument doc = parse_bvh(text);
  EXPECT_EQ(doc.num_frames, 3);
  EXPECT_EQ(doc.num_channels(), 0);
  const Motion m = to_motion(doc);
  ASSERT_EQ(m.num_frames, 3);
  EXPECT_EQ(m.translation(2, 0), Eigen::Vector3d(1, 2, 3));
  expect_same_document(parse_bvh(written(doc)), doc);
}

TEST(BvhParse, ExtraRowsAreIgnoredWithAWarningNamingTheirLine) {
  const std::string text = std::string(kSmall) + "7 8 9 1 1 1 1 1 1\n\n  \n7 8 9 1 1 1 1 1 1\r\n";
  const BvhDocument doc = parse_bvh(text, "walk.bvh");
  EXPECT_EQ(doc.num_frames, 2);
  EXPECT_EQ(doc.values.size(), 18u);
  ASSERT_EQ(doc.warnings.size(), 1u);
  EXPECT_EQ(doc.warnings[0],
            "walk.bvh:21: warning: 2 extra motion rows after the declared 2 frames ignored");
  const BvhDocument one = parse_bvh(std::string(kSmall) + "1", "w.bvh");
  ASSERT_EQ(one.warnings.size(), 1u);
  EXPECT_EQ(one.warnings[0],
            "w.bvh:21: warning: 1 extra motion row after the declared 2 frames ignored");
}

TEST(BvhParse, BlankLinesBetweenRowsAreSkipped) {
  const BvhDocument doc = parse_bvh(replace(kSmall, "60\n4", "60\n\n \t\n4"));
  EXPECT_EQ(doc.value(1, 0), 4.0);
  EXPECT_TRUE(doc.warnings.empty());
}

// --- what real exporters write ---------------------------------------------------------------
// Each text is also a fuzz seed, fuzz/seeds/bvh/<name> (checked by SeedFilesAreTheseTexts).

// The hierarchy opened with JOINT.
constexpr const char* kJointRoot =
    "HIERARCHY\n"
    "JOINT Hips\n"
    "{\n"
    "  OFFSET 0 0 0\n"
    "  CHANNELS 3 Xposition Yposition Zposition\n"
    "  JOINT Spine\n"
    "  {\n"
    "    OFFSET 0 5 0\n"
    "    CHANNELS 1 Zrotation\n"
    "    End Site\n"
    "    {\n"
    "      OFFSET 0 2 0\n"
    "    }\n"
    "  }\n"
    "}\n"
    "MOTION\n"
    "Frames: 2\n"
    "Frame Time: 0.5\n"
    "1 2 3 10\n"
    "4 5 6 20\n";

// HeadTop: a leaf JOINT with CHANNELS 0, an End Site written as a joint. Clavicle: CHANNELS 0 with
// a child, a static joint.
constexpr const char* kChannelsZeroLeaf =
    "HIERARCHY\n"
    "ROOT Hips\n"
    "{\n"
    "  OFFSET 0 0 0\n"
    "  CHANNELS 3 Xposition Yposition Zposition\n"
    "  JOINT Head\n"
    "  {\n"
    "    OFFSET 0 5 0\n"
    "    CHANNELS 1 Yrotation\n"
    "    JOINT HeadTop\n"
    "    {\n"
    "      OFFSET 0 2 0\n"
    "      CHANNELS 0\n"
    "    }\n"
    "  }\n"
    "  JOINT Clavicle\n"
    "  {\n"
    "    OFFSET 1 4 0\n"
    "    CHANNELS 0\n"
    "    JOINT Hand\n"
    "    {\n"
    "      OFFSET 3 0 0\n"
    "      CHANNELS 1 Zrotation\n"
    "      End Site\n"
    "      {\n"
    "        OFFSET 1 0 0\n"
    "      }\n"
    "    }\n"
    "  }\n"
    "}\n"
    "MOTION\n"
    "Frames: 2\n"
    "Frame Time: 0.5\n"
    "1 2 3 10 20\n"
    "4 5 6 30 40\n";

// A root declared with JOINT and end sites written as leaf `JOINT Site` blocks with CHANNELS 0,
// as one real exporter's T-pose files do: every end site has the same name.
constexpr const char* kJointSiteEndSites =
    "HIERARCHY\n"
    "JOINT Hips\n"
    "{\n"
    "  OFFSET 0 90 0\n"
    "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
    "  JOINT Head\n"
    "  {\n"
    "    OFFSET 0 60 0\n"
    "    CHANNELS 3 Zrotation Xrotation Yrotation\n"
    "    JOINT Site\n"
    "    {\n"
    "      OFFSET 0 15 0\n"
    "      CHANNELS 0\n"
    "    }\n"
    "  }\n"
    "  JOINT LeftFoot\n"
    "  {\n"
    "    OFFSET 10 -80 0\n"
    "    CHANNELS 3 Zrotation Xrotation Yrotation\n"
    "    JOINT Site\n"
    "    {\n"
    "      OFFSET 0 0 12\n"
    "      CHANNELS 0\n"
    "    }\n"
    "  }\n"
    "}\n"
    "MOTION\n"
    "Frames: 2\n"
    "Frame Time: 0.0333333\n"
    "0 90 0 0 0 0 0 0 0 0 0 0\n"
    "1 90 0 0 10 0 5 0 0 0 0 -5\n";

// Cut inside a joint's block.
constexpr const char* kEndsInHierarchy =
    "HIERARCHY\n"
    "ROOT Hips\n"
    "{\n"
    "  OFFSET 0 0 0\n"
    "  CHANNELS 3 Xposition Yposition Zposition\n"
    "  JOINT LeftArm\n"
    "  {\n"
    "    OFFSET 1 0 0\n"
    "    CHANNELS 1 Zrotation\n";

// Cut inside frame 2 of 3, without a final line end.
constexpr const char* kEndsInMotion =
    "HIERARCHY\n"
    "ROOT Hips\n"
    "{\n"
    "  OFFSET 0 0 0\n"
    "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
    "  End Site\n"
    "  {\n"
    "    OFFSET 0 1 0\n"
    "  }\n"
    "}\n"
    "MOTION\n"
    "Frames: 3\n"
    "Frame Time: 0.5\n"
    "1 2 3 10 20 30\n"
    "4 5 6";

TEST(BvhTolerant, RootDeclaredWithJointIsReadAsRootWithAWarning) {
  const BvhDocument doc = parse_bvh(kJointRoot, "joint_root.bvh");
  ASSERT_EQ(doc.skeleton.num_joints(), 2);
  EXPECT_EQ(doc.skeleton.joints[0].name, "Hips");
  EXPECT_EQ(doc.skeleton.roots(), (std::vector<int>{0}));
  EXPECT_EQ(doc.skeleton.joints[1].parent, 0);
  EXPECT_EQ(doc.skeleton.num_end_sites(), 1);
  EXPECT_EQ(doc.num_channels(), 4);
  EXPECT_EQ(doc.values, (std::vector<double>{1, 2, 3, 10, 4, 5, 6, 20}));
  EXPECT_EQ(doc.warnings, (std::vector<std::string>{
                              "joint_root.bvh:2:1: warning: root declared with JOINT instead of "
                              "ROOT; read as ROOT"}));
  // The same document as with ROOT, which is what gets written back.
  const BvhDocument with_root = parse_bvh(replace(kJointRoot, "JOINT Hips", "ROOT Hips"));
  EXPECT_TRUE(with_root.warnings.empty());
  expect_same_document(doc, with_root);
  const std::string text = written(doc);
  EXPECT_EQ(text.substr(0, 20), "HIERARCHY\nROOT Hips\n");
  const BvhDocument back = parse_bvh(text);
  expect_same_document(back, doc);
  EXPECT_TRUE(back.warnings.empty());
  // Later roots may be declared with JOINT too; each gets its warning.
  const std::string two = replace(kJointRoot, "MOTION", "JOINT Prop\n{\n  OFFSET 9 0 0\n}\nMOTION");
  const BvhDocument both = parse_bvh(two, "two.bvh");
  EXPECT_EQ(both.skeleton.roots(), (std::vector<int>{0, 2}));
  ASSERT_EQ(both.warnings.size(), 2u);
  EXPECT_EQ(both.warnings[1],
            "two.bvh:16:1: warning: root declared with JOINT instead of ROOT; read as ROOT");
}

TEST(BvhTolerant, LeafJointWithChannelsZeroIsReadAsAnEndSite) {
  const BvhDocument doc = parse_bvh(kChannelsZeroLeaf, "channels_zero_leaf.bvh");
  ASSERT_EQ(doc.skeleton.num_joints(), 4);
  const Skeleton& skel = doc.skeleton;
  EXPECT_EQ(skel.joints[0].name, "Hips");
  EXPECT_EQ(skel.joints[1].name, "Head");
  EXPECT_EQ(skel.joints[2].name, "Clavicle");  // CHANNELS 0 with a child: a static joint
  EXPECT_EQ(skel.joints[3].name, "Hand");
  EXPECT_EQ(skel.joints[2].parent, 0);
  EXPECT_TRUE(skel.joints[2].channels.empty());
  EXPECT_EQ(skel.joints[3].parent, 2);
  EXPECT_EQ(skel.joints[1].end_sites, (std::vector<Eigen::Vector3d>{{0, 2, 0}}));
  EXPECT_EQ(skel.joints[3].end_sites, (std::vector<Eigen::Vector3d>{{1, 0, 0}}));
  EXPECT_EQ(skel.num_end_sites(), 2);
  EXPECT_EQ(doc.num_channels(), 5);
  EXPECT_EQ(doc.values, (std::vector<double>{1, 2, 3, 10, 20, 4, 5, 6, 30, 40}));
  EXPECT_EQ(doc.warnings, (std::vector<std::string>{
                              "channels_zero_leaf.bvh:10:5: warning: joint 'HeadTop' has CHANNELS "
                              "0 and no children; read as an end site"}));
  // Exactly as if the file had written an End Site.
  const BvhDocument end_site = parse_bvh(replace(kChannelsZeroLeaf,
                                                 "JOINT HeadTop\n    {\n      OFFSET 0 2 0\n"
                                                 "      CHANNELS 0\n",
                                                 "End Site\n    {\n      OFFSET 0 2 0\n"));
  EXPECT_TRUE(end_site.warnings.empty());
  expect_same_document(doc, end_site);
  // Written back as an End Site; the columns still line up, and nothing is left to warn about.
  const std::string text = written(doc);
  EXPECT_EQ(text.find("HeadTop"), std::string::npos);
  EXPECT_NE(text.find("\t\tCHANNELS 1 Yrotation\n\t\tEnd Site\n\t\t{\n\t\t\tOFFSET 0 2 0\n"),
            std::string::npos)
      << text;
  const BvhDocument back = parse_bvh(text);
  expect_same_document(back, doc);
  EXPECT_TRUE(back.warnings.empty());
  const WorldPose pose = forward_kinematics(back.skeleton, to_motion(back), 1);
  // Hips at (4, 5, 6), Head 5 above it, the End Site 2 above Head (Yrotation keeps it there).
  EXPECT_LT((pose.end_sites[0] - Eigen::Vector3d(4, 12, 6)).norm(), 1e-12);

  // With an End Site of its own, or as a root, a joint with CHANNELS 0 stays a joint.
  const BvhDocument with_site =
      parse_bvh(replace(kChannelsZeroLeaf, "      CHANNELS 0\n",
                        "      CHANNELS 0\n      End Site { OFFSET 0 1 0 }\n"));
  EXPECT_EQ(with_site.skeleton.num_joints(), 5);
  EXPECT_TRUE(with_site.warnings.empty());
  const BvhDocument root = parse_bvh(
      "HIERARCHY\nROOT R\n{\nOFFSET 0 0 0\nCHANNELS 0\n}\n"
      "MOTION\nFrames: 1\nFrame Time: 1\n\n");
  EXPECT_EQ(root.skeleton.num_joints(), 1);
  EXPECT_TRUE(root.warnings.empty());
}

TEST(BvhTolerant, FileEndingInsideTheHierarchySaysFileEndsEarly) {
  const ParseError e = parse_error(kEndsInHierarchy);
  EXPECT_EQ(std::string(e.what()),
            "t.bvh:10:1: error: file ends early: expected '}' closing joint 'LeftArm'");
}

TEST(BvhTolerant, FileEndingInsideAFrameSaysFileEndsEarly) {
  // 3 frames of 6 values cannot fit in the 20 bytes left: the rows are read without storing them
  // (nothing allocated), up to where the file ends.
  const ParseError e = parse_error(kEndsInMotion);
  EXPECT_EQ(std::string(e.what()),
            "t.bvh:15:6: error: file ends early: expected 3 more values of frame 2, then 1 more "
            "frame");
  // With a line end after the short row, the file still ends inside frame 2.
  EXPECT_EQ(std::string(parse_error(std::string(kEndsInMotion) + "\n").what()),
            "t.bvh:16:1: error: file ends early: expected 3 more values of frame 2, then 1 more "
            "frame");
}

// Wherever a file is cut between two tokens, it either parses (only the complete file minus its
// last line end) or says "file ends early" at its end, never "found end of file".
TEST(BvhTolerant, EveryCutBetweenTokensSaysFileEndsEarlyAtTheEnd) {
  for (const std::string& full : {std::string(kSmall), std::string(kJointRoot),
                                  std::string(kChannelsZeroLeaf), std::string(kEndsInMotion)}) {
    for (std::size_t n = std::string("HIERARCHY").size(); n < full.size(); ++n) {
      if (!is_space(full[n]) && !is_space(full[n - 1])) continue;  // inside a token
      const std::string cut = full.substr(0, n);
      std::size_t line = 1, column = 1;
      for (const char c : cut) {
        column = c == '\n' ? 1 : column + 1;
        line += c == '\n';
      }
      try {
        parse_bvh(cut, "t.bvh");
        EXPECT_EQ(n + 1, full.size()) << "parsed:\n" << cut;
      } catch (const ParseError& e) {
        EXPECT_EQ(e.message().rfind("file ends early: expected ", 0), 0u) << e.what();
        EXPECT_EQ(e.line(), line) << e.what();
        EXPECT_EQ(e.column(), column) << e.what();
      }
    }
  }
}

// Leaf joints with no channels and no children are end sites whatever they are called, so their
// names need not be unique: "JOINT Site" thirteen times is thirteen end sites.
TEST(BvhTolerant, LeafJointsNamedSiteAreEndSitesSharingTheName) {
  const BvhDocument small = parse_bvh(kJointSiteEndSites, "t.bvh");
  EXPECT_EQ(small.skeleton.num_joints(), 3);
  EXPECT_EQ(small.skeleton.num_end_sites(), 2);
  EXPECT_EQ(small.skeleton.num_channels(), 12);
  EXPECT_EQ(small.skeleton.joints[2].end_sites.at(0), Eigen::Vector3d(0, 0, 12));

  // The exporter's T-pose file: a JOINT root, 13 chains of 4 joints each ending in `JOINT Site`.
  std::string text =
      "HIERARCHY\nJOINT Root\n{\n OFFSET 0 0 0\n CHANNELS 6 Xposition Yposition "
      "Zposition Zrotation Xrotation Yrotation\n";
  for (int chain = 0; chain < 13; ++chain) {
    for (int j = 0; j < 4; ++j) {
      text += "JOINT C" + std::to_string(chain) + "_" + std::to_string(j) +
              "\n{\n OFFSET 0 1 0\n CHANNELS 3 Zrotation Xrotation Yrotation\n";
    }
    text += "JOINT Site\n{\n OFFSET 0 1 0\n CHANNELS 0\n}\n";
    for (int j = 0; j < 4; ++j) text += "}\n";
  }
  text += "}\nMOTION\nFrames: 1\nFrame Time: 0.0333333\n";
  for (int c = 0; c < 162; ++c) text += c == 0 ? "0" : " 0";
  text += "\n";
  const BvhDocument doc = parse_bvh(text, "tpose.bvh");
  EXPECT_EQ(doc.skeleton.num_joints(), 53);
  EXPECT_EQ(doc.skeleton.num_end_sites(), 13);
  EXPECT_EQ(doc.skeleton.num_channels(), 162);
  EXPECT_EQ(doc.warnings.size(), 14u);  // the JOINT root and the 13 end sites

  // A joint that stays a joint (it has channels) still needs a name of its own, named where
  // it is written, with the line of the first use.
  const std::string twice = replace(kJointSiteEndSites, "JOINT LeftFoot", "JOINT Head");
  try {
    parse_bvh(twice, "t.bvh");
    ADD_FAILURE() << "a second joint 'Head' was accepted";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 16u);
    EXPECT_EQ(e.column(), 9u);
    EXPECT_NE(e.message().find("a joint name not used before (line 6)"), std::string::npos)
        << e.what();
  }
  // And a joint may take the name an end site had.
  const std::string site_then_joint = replace(kJointSiteEndSites, "JOINT LeftFoot", "JOINT Site");
  EXPECT_EQ(parse_bvh(site_then_joint, "t.bvh").skeleton.joints[2].name, "Site");
}

// A file cut inside a keyword (`CHANNELS` cut to `C`) says "file ends early", at the end of the
// text, as a file cut between words does.
TEST(BvhTolerant, EveryCutInsideAKeywordSaysFileEndsEarly) {
  const std::vector<std::string> keywords = {
      "HIERARCHY", "ROOT",      "JOINT",     "OFFSET",    "CHANNELS", "End",
      "Site",      "MOTION",    "Frames:",   "Frame",     "Time:",    "Xposition",
      "Yposition", "Zposition", "Xrotation", "Yrotation", "Zrotation"};
  int cuts = 0;
  for (const std::string& full :
       {std::string(kSmall), std::string(kJointRoot), std::string(kChannelsZeroLeaf),
        std::string(kJointSiteEndSites)}) {
    for (std::size_t start = 0; start < full.size(); ++start) {
      if (start > 0 && !is_space(full[start - 1])) continue;
      std::size_t end = start;
      while (end < full.size() && !is_space(full[end])) ++end;
      const std::string word = full.substr(start, end - start);
      if (std::find(keywords.begin(), keywords.end(), word) == keywords.end()) continue;
      for (std::size_t n = start + 1; n < end; ++n) {
        const std::string cut = full.substr(0, n);
        try {
          parse_bvh(cut, "t.bvh");
          ADD_FAILURE() << "parsed:\n" << cut;
        } catch (const ParseError& e) {
          ++cuts;
          EXPECT_EQ(e.message().rfind("file ends early: expected ", 0), 0u) << e.what();
          EXPECT_EQ(e.line(),
                    static_cast<std::size_t>(std::count(cut.begin(), cut.end(), '\n')) + 1)
              << e.what();
        }
      }
    }
  }
  EXPECT_GT(cuts, 100);
  try {
    parse_bvh(std::string(kSmall).substr(0, std::string(kSmall).find("CHANNELS") + 1), "t.bvh");
  } catch (const ParseError& e) {
    EXPECT_EQ(e.message(), "file ends early: expected 'CHANNELS' of joint 'Hips'");
  }
}

TEST(BvhTolerant, SeedFilesAreTheseTexts) {
  const std::filesystem::path dir = std::filesystem::path(MOTIONMAP_SOURCE_DIR) / "fuzz/seeds/bvh";
  const std::pair<const char*, const char*> seeds[] = {
      {"joint_root.bvh", kJointRoot},
      {"channels_zero_leaf.bvh", kChannelsZeroLeaf},
      {"ends_in_hierarchy.bvh", kEndsInHierarchy},
      {"ends_in_motion.bvh", kEndsInMotion},
      {"joint_site_end_sites.bvh", kJointSiteEndSites}};
  for (const auto& [name, text] : seeds) {
    std::ifstream in(dir / name, std::ios::binary);
    ASSERT_TRUE(in) << dir / name;
    std::ostringstream content;
    content << in.rdbuf();
    EXPECT_EQ(content.str(), text) << name;
  }
}

// --- errors ----------------------------------------------------------------------------------

struct ErrorCase {
  const char* name;
  std::string text;
  std::size_t line;
  std::size_t column;
  std::string message;
};

void PrintTo(const ErrorCase& c, std::ostream* os) {
  *os << c.name;
}

class BvhParseError : public ::testing::TestWithParam<ErrorCase> {};

TEST_P(BvhParseError, ReportsLineColumnAndMessage) {
  const ErrorCase& c = GetParam();
  const ParseError e = parse_error(c.text);
  EXPECT_EQ(e.message(), c.message);
  EXPECT_EQ(e.line(), c.line);
  EXPECT_EQ(e.column(), c.column);
  EXPECT_EQ(e.path(), "t.bvh");
  EXPECT_EQ(std::string(e.what()), "t.bvh:" + std::to_string(c.line) + ":" +
                                       std::to_string(c.column) + ": error: " + c.message);
}

std::vector<ErrorCase> error_cases() {
  const std::string s = kSmall;
  const std::string hierarchy_only = s.substr(0, s.find("MOTION"));
  std::string deep = "HIERARCHY\n";
  for (int i = 0; i <= kBvhMaxDepth; ++i)
    deep += (i ? "JOINT j" : "ROOT j") + std::to_string(i) + "\n{\nOFFSET 0 0 0\n";
  return {
      {"EmptyFile", "", 1, 1, "expected 'HIERARCHY', found end of file"},
      {"OnlyWhitespace", " \r\n\t\n", 3, 1, "expected 'HIERARCHY', found end of file"},
      {"BinaryGarbage",
       std::string("\x7f"
                   "ELF\x02\x01\x01\x00\x00",
                   9),
       1, 1, "expected 'HIERARCHY', found '\\x7FELF\\x02\\x01\\x01\\x00\\x00'"},
      {"NoRoot", "HIERARCHY\nMOTION\nFrames: 0\nFrame Time: 1\n", 2, 1,
       "expected 'ROOT', found 'MOTION'"},
      {"RootWithoutName", replace(s, "ROOT Hips", "ROOT  "), 2, 7,
       "expected a joint name, found end of line"},
      {"RootNameOnlyBrace", replace(s, "ROOT Hips\n{", "ROOT {"), 2, 6,
       "expected a joint name, found '{'"},
      {"MissingOpeningBrace", replace(s, "\t{\n\t\tOFFSET 0 5", "\t\tOFFSET 0 5"), 7, 3,
       "expected '{', found 'OFFSET'"},
      {"MissingClosingBrace", replace(s, "\t}\n}\n", "\t}\n"), 15, 1,
       "expected 'JOINT', 'End Site' or '}', found 'MOTION'"},
      {"ExtraClosingBrace", replace(s, "\t}\n}\n", "\t}\n}\n}\n"), 16, 1,
       "expected 'ROOT' or 'MOTION', found '}'"},
      {"UnknownKeyword", replace(s, "\tJOINT Spine", "\tJOINTS Spine"), 6, 2,
       "expected 'JOINT', 'End Site' or '}', found 'JOINTS'"},
      {"EndWithoutSite", replace(s, "End Site", "End Sight"), 10, 7,
       "expected 'Site', found 'Sight'"},
      {"MissingOffset", replace(s, "\t\tOFFSET 0 5 0\n", ""), 9, 3,
       "expected 'OFFSET', found 'End'"},
      {"OffsetMissingNumber", replace(s, "OFFSET 0 5 0", "OFFSET 0 5"), 8, 13,
       "expected OFFSET z, found end of line"},
      {"OffsetNotANumber", replace(s, "OFFSET 0 5 0", "OFFSET 0 five 0"), 8, 12,
       "expected OFFSET y, found 'five'"},
      {"OffsetTooManyNumbers", replace(s, "OFFSET 0 5 0", "OFFSET 0 5 0 1"), 8, 16,
       "expected only 3 OFFSET values, found '1'"},
      {"OffsetNan", replace(s, "OFFSET 0 2 0", "OFFSET 0 nan 0"), 12, 13,
       "expected OFFSET y (a finite number), found 'nan'"},
      {"EndSiteWithoutOffset", replace(s, "\t\t\tOFFSET 0 2 0\n", ""), 12, 3,
       "expected 'OFFSET', found '}'"},
      {"ChannelsCountAboveNames", replace(s, "CHANNELS 3 Zrotation", "CHANNELS 4 Zrotation"), 9, 43,
       "expected 4 channel names as CHANNELS declares, found end of line"},
      {"ChannelsCountBelowNames", replace(s, "CHANNELS 3 Zrotation", "CHANNELS 2 Zrotation"), 9, 34,
       "expected only 2 channel names as CHANNELS declares, found 'Yrotation'"},
      {"ChannelsCountNotANumber", replace(s, "CHANNELS 3 Z", "CHANNELS three Z"), 9, 12,
       "expected a channel count, found 'three'"},
      {"ChannelsCountNegative", replace(s, "CHANNELS 3 Z", "CHANNELS -3 Z"), 9, 12,
       "expected a channel count, found '-3'"},
      {"BadChannelName", replace(s, "Xrotation Yrotation\n", "Xrotation yrotation\n"), 9, 34,
       "expected a channel name (Xposition, Yposition, Zposition, Xrotation, Yrotation or "
       "Zrotation), found 'yrotation'"},
      {"DuplicateJointName", replace(s, "JOINT Spine", "JOINT Hips"), 6, 8,
       "expected a joint name not used before (line 2), found 'Hips'"},
      {"MissingMotion", hierarchy_only, 16, 1, "file ends early: expected 'MOTION'"},
      {"MissingFrames", replace(s, "Frames: 2\n", ""), 17, 1, "expected 'Frames:', found 'Frame'"},
      {"FramesNotANumber", replace(s, "Frames: 2", "Frames: two"), 17, 9,
       "expected a frame count, found 'two'"},
      {"FramesNegative", replace(s, "Frames: 2", "Frames: -2"), 17, 9,
       "expected a frame count, found '-2'"},
      {"MissingFrameTime", replace(s, "Frame Time: 0.0333333\n", ""), 18, 1,
       "expected 'Frame', found '1'"},
      {"FrameTimeZero", replace(s, "0.0333333", "0"), 18, 13,
       "expected a frame time > 0, found '0'"},
      {"FrameTimeNegative", replace(s, "0.0333333", "-0.01"), 18, 13,
       "expected a frame time > 0, found '-0.01'"},
      {"FrameTimeInf", replace(s, "0.0333333", "inf"), 18, 13,
       "expected a frame time (a finite number), found 'inf'"},
      {"FrameTimeTrailingJunk", replace(s, "0.0333333", "0.0333333 s"), 18, 23,
       "expected end of line after the frame time, found 's'"},
      // More frames than the rest of the file can hold: the rows are checked without storing
      // them, so the file is reported where it ends (or at its first bad row).
      {"FramesBeyondFileSize", replace(s, "Frames: 2", "Frames: 1000000000"), 21, 1,
       "file ends early: expected 999999998 more frames (Frames: declares 1000000000, the file "
       "holds 2)"},
      {"FramesTimesChannelsHuge", replace(s, "Frames: 2", "Frames: 2147483647"), 21, 1,
       "file ends early: expected 2147483645 more frames (Frames: declares 2147483647, the file "
       "holds 2)"},
      {"FramesBeyondFileSizeBadRowFirst",
       replace(replace(s, "Frames: 2", "Frames: 1000000000"), "-20 -30", "-20 abc"), 20, 15,
       "expected a number (value 6 of motion row 2), found 'abc'"},
      {"FramesBeyondInt", replace(s, "Frames: 2", "Frames: 2147483648"), 17, 9,
       "expected a frame count, found '2147483648'"},
      {"FewerRowsThanFrames", replace(s, "Frames: 2", "Frames: 3"), 21, 1,
       "file ends early: expected 1 more frame (Frames: declares 3, the file holds 2)"},
      {"RowTooShort", replace(s, "1 2 3 10 20 30 40 50 60", "1 2 3 10 20 30 40 50"), 19, 21,
       "expected 9 values on motion row 1 (one per channel), not 8, found end of line"},
      {"LastRowTooShortAtEndOfFile",
       replace(s, "4 5 6 -10 -20 -30 -40 -50 -60", "4 5 6 -10 -20 -30 -40 -50"), 21, 1,
       "file ends early: expected 1 more value of frame 2"},
      {"RowTooLong", replace(s, "40 50 60", "40 50 60 70"), 19, 25,
       "expected end of motion row 1 after its 9 values, found '70'"},
      {"RowSplitOverTwoLines", replace(s, "30 40 50 60", "30\n40 50 60"), 19, 15,
       "expected 9 values on motion row 1 (one per channel), not 6, found end of line"},
      {"RowNotANumber", replace(s, "-20 -30", "-20 abc"), 20, 15,
       "expected a number (value 6 of motion row 2), found 'abc'"},
      {"RowNumberWithJunk", replace(s, "-20 -30", "-20 -30x"), 20, 15,
       "expected a number (value 6 of motion row 2), found '-30x'"},
      {"RowNan", replace(s, "-20 -30", "-20 nan"), 20, 15,
       "expected a finite number (value 6 of motion row 2), found 'nan'"},
      {"RowInf", replace(s, "-20 -30", "-20 -inf"), 20, 15,
       "expected a finite number (value 6 of motion row 2), found '-inf'"},
      {"RowOverflow", replace(s, "-20 -30", "-20 1e999"), 20, 15,
       "expected a finite number (value 6 of motion row 2), found '1e999'"},
      {"RowWithCrlfReportsRightLine", replace(s, "\n4 5 6", "\r\n\r\n4 5 x"), 21, 5,
       "expected a number (value 3 of motion row 2), found 'x'"},
      // The file ends (nothing but whitespace left) inside the hierarchy or the motion block.
      {"EndsAfterHierarchy", "HIERARCHY\n", 2, 1, "file ends early: expected 'ROOT'"},
      {"EndsAfterRootKeyword", "HIERARCHY\nROOT", 2, 5, "file ends early: expected a joint name"},
      {"EndsAfterRootName", upto(s, "{"), 3, 1,
       "file ends early: expected '{' opening joint 'Hips'"},
      {"EndsBeforeOffset", upto(s, "\tOFFSET 0 0 0"), 4, 1,
       "file ends early: expected 'OFFSET' of joint 'Hips'"},
      {"EndsInsideOffset", upto(s, " 0\n\tCHANNELS 6"), 4, 12,
       "file ends early: expected OFFSET z"},
      {"EndsAfterChannelsKeyword", upto(s, " 6 Xposition"), 5, 10,
       "file ends early: expected a channel count"},
      {"EndsInsideChannelNames", upto(s, " Zposition"), 5, 32,
       "file ends early: expected 6 channel names as CHANNELS declares"},
      {"EndsInsideJoint", upto(s, "\t}\n}\nMOTION"), 14, 1,
       "file ends early: expected '}' closing joint 'Spine'"},
      {"EndsInsideRoot", upto(s, "}\nMOTION"), 15, 1,
       "file ends early: expected '}' closing joint 'Hips'"},
      {"EndsAfterEnd", upto(s, " Site"), 10, 6, "file ends early: expected 'Site'"},
      {"EndsAfterEndSite", upto(s, "\t\t{\n\t\t\tOFFSET 0 2 0"), 11, 1,
       "file ends early: expected '{' opening an End Site of joint 'Spine'"},
      {"EndsBeforeEndSiteOffset", upto(s, "\t\t\tOFFSET 0 2 0"), 12, 1,
       "file ends early: expected 'OFFSET' of an End Site of joint 'Spine'"},
      {"EndsBeforeEndSiteBrace", upto(s, "\t\t}\n\t}"), 13, 1,
       "file ends early: expected '}' closing an End Site of joint 'Spine'"},
      {"EndsAfterMotion", upto(s, "Frames:"), 17, 1, "file ends early: expected 'Frames:'"},
      {"EndsAfterFramesLabel", upto(s, " 2\nFrame Time"), 17, 8,
       "file ends early: expected a frame count"},
      {"EndsBeforeFrameTime", upto(s, "Frame Time"), 18, 1,
       "file ends early: expected 'Frame Time:'"},
      {"EndsInsideFrameTimeLabel", upto(s, " Time:"), 18, 6,
       "file ends early: expected 'Frame Time:'"},
      {"EndsAfterFrameTimeLabel", upto(s, " 0.0333333"), 18, 12,
       "file ends early: expected a frame time"},
      {"EndsBeforeTheRows", upto(s, "1 2 3"), 19, 1,
       "file ends early: expected 2 more frames (Frames: declares 2, the file holds 0)"},
      {"EndsInsideTheLastFrame", upto(s, " -10 -20"), 20, 6,
       "file ends early: expected 6 more values of frame 2"},
      {"EndsInsideAFrameWithMoreToCome", upto(replace(s, "Frames: 2", "Frames: 12"), " -10 -20"),
       20, 6, "file ends early: expected 6 more values of frame 2, then 10 more frames"},
      {"EndsInsideCrlfRows", upto(replace(s, "60\n4 5 6", "60\r\n\r\n4 5 6"), " -10 -20") + "\r\n",
       22, 1, "file ends early: expected 6 more values of frame 2"},
      {"TooDeep", deep, static_cast<std::size_t>(2 + 3 * kBvhMaxDepth), 1,
       "expected at most 1000 nested joints, found 'JOINT'"},
  };
}

INSTANTIATE_TEST_SUITE_P(Cases, BvhParseError, ::testing::ValuesIn(error_cases()),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(BvhParse, FramesTimesJointsBeyondTheFileIsRejectedBeforeAllocating) {
  // One channel but 100 joints: 50000 rows of "0" (100 kB) would be 5M transforms in to_motion.
  std::string text = "HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\nCHANNELS 1 Xrotation\n";
  for (int i = 1; i < 100; ++i) text += "JOINT j" + std::to_string(i) + "\n{\nOFFSET 0 1 0\n}\n";
  text += "}\nMOTION\n";
  const auto line = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) + 1;
  text += "Frames: 50000\nFrame Time: 1\n";
  for (int f = 0; f < 50000; ++f) text += "0\n";
  const ParseError e = parse_error(text);
  EXPECT_EQ(e.line(), line);
  EXPECT_EQ(e.column(), 9u);
  EXPECT_EQ(e.message(),
            "expected a frame count the rest of the file can hold (50000 frames of 100 joints "
            "need at least 5000000 bytes, 100000 remain), found '50000'");
  // The same with fewer frames (below 4M transforms) is fine.
  const std::string small = replace(text, "Frames: 50000", "Frames: 40000");
  EXPECT_EQ(parse_bvh(small, "t.bvh").num_frames, 40000);
}

TEST(BvhParse, NestingUpToTheLimitIsAccepted) {
  std::string text = "HIERARCHY\n";
  for (int i = 0; i < kBvhMaxDepth; ++i) {
    text += (i ? "JOINT j" : "ROOT j") + std::to_string(i) +
            "\n{\nOFFSET 0 1 0\nCHANNELS 1 Xrotation\n";
  }
  for (int i = 0; i < kBvhMaxDepth; ++i) text += "}\n";
  text += "MOTION\nFrames: 1\nFrame Time: 1\n";
  for (int i = 0; i < kBvhMaxDepth; ++i) text += "1 ";
  const BvhDocument doc = parse_bvh(text);
  EXPECT_EQ(doc.skeleton.num_joints(), kBvhMaxDepth);
  EXPECT_EQ(doc.skeleton.joints.back().parent, kBvhMaxDepth - 2);
  expect_same_document(parse_bvh(written(doc)), doc);
}

TEST(BvhParse, ReadBvhNamesThePathInErrors) {
  const auto path = std::filesystem::temp_directory_path() / "motionmap_bvh_test_bad.bvh";
  {
    std::ofstream out(path, std::ios::binary);
    out << replace(kSmall, "-20 -30", "-20 ?");
  }
  try {
    read_bvh(path.string());
    ADD_FAILURE() << "no error";
  } catch (const ParseError& e) {
    EXPECT_EQ(std::string(e.what()), path.string() +
                                         ":20:15: error: expected a number (value 6 of motion "
                                         "row 2), found '?'");
  }
  std::filesystem::remove(path);
  EXPECT_THROW(read_bvh(path.string()), Error);
}

// --- writing ---------------------------------------------------------------------------------

TEST(BvhWrite, WritesTabsLfOriginalChannelOrderAndShortestNumbers) {
  BvhDocument doc = parse_bvh(kSmall);
  doc.values[0] = 0.1;
  doc.values[1] = -0.0;
  doc.values[2] = 1.0 / 3.0;
  doc.values[3] = 1e-300;
  EXPECT_EQ(written(doc),
            "HIERARCHY\n"
            "ROOT Hips\n"
            "{\n"
            "\tOFFSET 0 0 0\n"
            "\tCHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation\n"
            "\tJOINT Spine\n"
            "\t{\n"
            "\t\tOFFSET 0 5 0\n"
            "\t\tCHANNELS 3 Zrotation Xrotation Yrotation\n"
            "\t\tEnd Site\n"
            "\t\t{\n"
            "\t\t\tOFFSET 0 2 0\n"
            "\t\t}\n"
            "\t}\n"
            "}\n"
            "MOTION\n"
            "Frames: 2\n"
            "Frame Time: 0.0333333\n"
            "0.1 -0 0.3333333333333333 1e-300 20 30 40 50 60\n"
            "4 5 6 -10 -20 -30 -40 -50 -60\n");
  expect_same_document(parse_bvh(written(doc)), doc);
}

TEST(BvhWrite, NonDepthFirstJointOrderIsWrittenDepthFirstWithItsColumns) {
  // Breadth-first: A, B (child of A), C (child of A), D (child of B). File order: A B D C.
  Skeleton skel;
  skel.joints = {Joint{"A", -1, {0, 0, 0}, {ChannelType::Xposition}, {}},
                 Joint{"B", 0, {1, 0, 0}, {ChannelType::Xrotation}, {}},
                 Joint{"C", 0, {2, 0, 0}, {ChannelType::Yrotation}, {}},
                 Joint{"D", 1, {3, 0, 0}, {ChannelType::Zrotation}, {{0, 1, 0}}}};
  BvhDocument doc;
  doc.skeleton = skel;
  doc.frame_time = 0.5;
  doc.num_frames = 1;
  doc.values = {10, 20, 30, 40};  // A B C D
  const BvhDocument back = parse_bvh(written(doc));
  ASSERT_EQ(back.skeleton.num_joints(), 4);
  EXPECT_EQ(back.skeleton.joints[2].name, "D");
  EXPECT_EQ(back.skeleton.joints[2].parent, 1);
  EXPECT_EQ(back.skeleton.joints[3].name, "C");
  EXPECT_EQ(back.skeleton.joints[3].parent, 0);
  EXPECT_EQ(back.values, (std::vector<double>{10, 20, 40, 30}));
}

TEST(BvhWrite, AJointWithoutChannelsOrChildrenIsWrittenWithoutChannelsLine) {
  // `CHANNELS 0` would make the leaf an End Site when read back; without the line it stays a joint.
  const BvhDocument doc = parse_bvh(
      "HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 1 Xrotation\nJOINT B\n{\nOFFSET 0 1 0\n}\n}\n"
      "MOTION\nFrames: 1\nFrame Time: 1\n5\n");
  ASSERT_EQ(doc.skeleton.num_joints(), 2);
  const std::string text = written(doc);
  EXPECT_NE(text.find("\tJOINT B\n\t{\n\t\tOFFSET 0 1 0\n\t}\n}\n"), std::string::npos) << text;
  const BvhDocument back = parse_bvh(text);
  expect_same_document(back, doc);
  EXPECT_TRUE(back.warnings.empty());
}

TEST(BvhWrite, RejectsDocumentsThatCannotBeValidBvh) {
  const BvhDocument good = parse_bvh(kSmall);
  const auto message_of = [&](auto edit) {
    BvhDocument doc = good;
    edit(doc);
    try {
      written(doc);
    } catch (const ParameterError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message_of([](BvhDocument& d) { d.values.pop_back(); }),
            "write_bvh: 17 values for 2 frames of 9 channels");
  EXPECT_EQ(message_of([](BvhDocument& d) { d.values[4] = NAN; }),
            "write_bvh: value 4 is not finite");
  EXPECT_EQ(message_of([](BvhDocument& d) { d.frame_time = 0; }),
            "write_bvh: frame time 0.000000 is not a finite number > 0");
  EXPECT_EQ(message_of([](BvhDocument& d) { d.skeleton.joints[1].offset.x() = INFINITY; }),
            "write_bvh: joint 'Spine' has a non-finite offset");
  EXPECT_EQ(message_of([](BvhDocument& d) { d.skeleton.joints[1].name = "Hips"; }),
            "write_bvh: joint name 'Hips' is used twice");
  for (const char* bad : {"", " a", "a\t", "a\nb", "a {", "{"}) {
    EXPECT_EQ(message_of([&](BvhDocument& d) { d.skeleton.joints[1].name = bad; }),
              "write_bvh: joint 1 has the name '" + quote_token(bad) +
                  "', which BVH cannot hold (empty, leading/trailing blanks, a line end or a "
                  "trailing ' {')")
        << bad;
  }
  EXPECT_EQ(message_of([](BvhDocument& d) { d.skeleton.joints[1].name = "a{"; }), "no error");
}

TEST(BvhWrite, ToFileAndUnwritablePath) {
  const BvhDocument doc = parse_bvh(kSmall);
  const auto path = std::filesystem::temp_directory_path() / "motionmap_bvh_test_out.bvh";
  write_bvh(doc, path.string());
  expect_same_document(read_bvh(path.string()), doc);
  std::filesystem::remove(path);
  EXPECT_THROW(write_bvh(doc, "/nonexistent-dir/x.bvh"), Error);
}

// --- conversion ------------------------------------------------------------------------------

TEST(BvhToMotion, RotationsComposeInTheWrittenOrderForAllSixOrders) {
  const char* names[] = {"X", "Y", "Z"};
  const Eigen::Vector3d axes[] = {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
                                  Eigen::Vector3d::UnitZ()};
  const int orders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (const auto& o : orders) {
    const std::string text = std::string("HIERARCHY\nROOT r\n{\nOFFSET 1 2 3\nCHANNELS 3 ") +
                             names[o[0]] + "rotation " + names[o[1]] + "rotation " + names[o[2]] +
                             "rotation\n}\nMOTION\nFrames: 1\nFrame Time: 1\n"
                             "30 -50 70\n";
    const Motion m = to_motion(parse_bvh(text));
    const Eigen::Quaterniond expected =
        about(axes[o[0]], 30) * about(axes[o[1]], -50) * about(axes[o[2]], 70);
    EXPECT_LT(rotation_angle(m.rotation(0, 0), expected), 1e-12) << text;
    EXPECT_EQ(m.translation(0, 0), Eigen::Vector3d(1, 2, 3));
  }
}

TEST(BvhToMotion, PositionChannelsReplaceOffsetComponentsOnAnyJoint) {
  // Like Bandai Namco's files: a child with position channels, the offset's y (93.9) replaced.
  const BvhDocument doc = parse_bvh(
      "HIERARCHY\nROOT root\n{\nOFFSET 0 0 0\nCHANNELS 0\n"
      "JOINT Hips\n{\nOFFSET 1 93.9 -3\nCHANNELS 4 Yposition Zrotation Xposition Xrotation\n"
      "End Site\n{\nOFFSET 0 1 0\n}\n}\n}\n"
      "MOTION\nFrames: 1\nFrame Time: 1\n90 90 7 0\n");
  const Motion m = to_motion(doc);
  EXPECT_EQ(m.translation(0, 1), Eigen::Vector3d(7, 90, -3));
  EXPECT_EQ(m.translation(0, 0), Eigen::Vector3d(0, 0, 0));
  EXPECT_LT(rotation_angle(m.rotation(0, 1), about(Eigen::Vector3d::UnitZ(), 90)), 1e-12);
  EXPECT_EQ(m.frame_time, 1.0);
}

TEST(BvhToMotion, RepeatedAndSingleAxes) {
  const Motion m = to_motion(parse_bvh(
      "HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\nCHANNELS 4 Zrotation Xrotation Zrotation Xposition\n"
      "JOINT c\n{\nOFFSET 0 1 0\nCHANNELS 1 Yrotation\n}\n}\n"
      "MOTION\nFrames: 1\nFrame Time: 1\n10 20 30 5 -40\n"));
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), z = Eigen::Vector3d::UnitZ();
  EXPECT_LT(rotation_angle(m.rotation(0, 0), about(z, 10) * about(x, 20) * about(z, 30)), 1e-12);
  EXPECT_LT(rotation_angle(m.rotation(0, 1), about(Eigen::Vector3d::UnitY(), -40)), 1e-12);
  EXPECT_EQ(m.translation(0, 0), Eigen::Vector3d(5, 0, 0));
}

// A skeleton exercising every from_motion case: 3 distinct axes (+ a repeat), 2 axes, 1 axis, none.
Skeleton layout_skeleton() {
  using C = ChannelType;
  Skeleton s;
  s.joints = {
      Joint{"root",
            -1,
            {0, 0, 0},
            {C::Xposition, C::Yposition, C::Zposition, C::Yrotation, C::Xrotation, C::Zrotation},
            {}},
      Joint{"three_repeat",
            0,
            {0, 1, 0},
            {C::Zrotation, C::Xrotation, C::Zrotation, C::Yrotation},
            {}},
      Joint{"two", 1, {0, 1, 0}, {C::Zrotation, C::Xrotation}, {}},
      Joint{"one", 2, {0, 1, 0}, {C::Yrotation}, {}},
      Joint{"none", 3, {0, 1, 0}, {}, {{0, 1, 0}}},
  };
  return s;
}

TEST(BvhFromMotion, ExactForZeroOneAndThreeAxesAndDropsOnlyTheMissingAxis) {
  const Skeleton skel = layout_skeleton();
  Motion m;
  m.frame_time = 0.01;
  m.resize(2, skel.num_joints());
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY(),
                        z = Eigen::Vector3d::UnitZ();
  for (int f = 0; f < 2; ++f) {
    for (int j = 0; j < 5; ++j) m.translation(f, j) = skel.joints[j].offset;
    m.translation(f, 0) = Eigen::Vector3d(1, 2 + f, 3);
    m.rotation(f, 0) = about(y, 100 + f) * about(x, -80) * about(z, 170);
    m.rotation(f, 1) = about(x, 10) * about(y, 20) * about(z, 30 - f);
    m.rotation(f, 2) = about(z, 25 + f) * about(x, -35);  // representable: no Y part
    m.rotation(f, 3) = about(y, -120 - f);
  }
  const BvhDocument doc = from_motion(skel, m);
  EXPECT_EQ(doc.num_frames, 2);
  EXPECT_EQ(doc.frame_time, 0.01);
  EXPECT_EQ(doc.value(1, 0), 1.0);
  EXPECT_EQ(doc.value(1, 1), 3.0);
  EXPECT_EQ(doc.value(0, 8), 0.0);  // the repeated Zrotation of three_repeat carries nothing
  EXPECT_NEAR(doc.value(1, 10), 26.0, 1e-9);  // "two": Z then X
  EXPECT_NEAR(doc.value(1, 11), -35.0, 1e-9);
  EXPECT_NEAR(doc.value(1, 12), -121.0, 1e-9);  // "one"
  const Motion back = to_motion(doc);
  for (int f = 0; f < 2; ++f) {
    for (int j = 0; j < 4; ++j) {
      EXPECT_LT(rotation_angle(back.rotation(f, j), m.rotation(f, j)), 1e-12) << f << " " << j;
      EXPECT_EQ(back.translation(f, j), m.translation(f, j));
    }
  }
  // Two axes cannot hold a rotation about the third: that part is dropped, the rest kept.
  m.rotation(0, 2) = about(z, 25) * about(x, -35) * about(y, 15);
  const Motion lossy = to_motion(from_motion(skel, m));
  EXPECT_LT(rotation_angle(lossy.rotation(0, 2), about(z, 25) * about(x, -35)), 1e-12);
}

TEST(BvhFromMotion, AnglesStayContinuousAcrossTheAntimeridian) {
  const Skeleton skel = layout_skeleton();
  Motion m;
  m.frame_time = 0.01;
  const int frames = 50;
  m.resize(frames, skel.num_joints());
  for (int f = 0; f < frames; ++f) {
    const double a = 150.0 + 3.0 * f;  // sweeps through 180° and on to 297°
    m.rotation(f, 0) = about(Eigen::Vector3d::UnitY(), a);
    m.rotation(f, 1) = about(Eigen::Vector3d::UnitZ(), a) * about(Eigen::Vector3d::UnitX(), 20);
    m.rotation(f, 3) = about(Eigen::Vector3d::UnitY(), -a);
  }
  const BvhDocument doc = from_motion(skel, m);
  for (int f = 1; f < frames; ++f) {
    for (int c = 0; c < doc.num_channels(); ++c) {
      EXPECT_LT(std::abs(doc.value(f, c) - doc.value(f - 1, c)), 10.0) << f << " " << c;
    }
  }
  EXPECT_NEAR(doc.value(frames - 1, 3), 297.0, 1e-9);    // root Yrotation
  EXPECT_NEAR(doc.value(frames - 1, 12), -297.0, 1e-9);  // "one"
}

TEST(BvhFromMotion, RejectsAMotionThatDoesNotFit) {
  const Skeleton skel = layout_skeleton();
  Motion m;
  m.resize(3, 4);
  try {
    from_motion(skel, m);
    ADD_FAILURE();
  } catch (const ParameterError& e) {
    EXPECT_EQ(std::string(e.what()),
              "from_motion: the motion (3 frames of 4 joints, 12 rotations, 12 translations) does "
              "not fit the skeleton of 5 joints");
  }
  m.resize(3, 5);
  m.rotations.pop_back();
  EXPECT_THROW(from_motion(skel, m), ParameterError);
  m.resize(3, 5);
  m.frame_time = 0.0;
  try {
    from_motion(skel, m);
    ADD_FAILURE();
  } catch (const ParameterError& e) {
    EXPECT_EQ(std::string(e.what()), "from_motion: frame time 0.000000 is not a finite number > 0");
  }
}

TEST(BvhLoad, LoadBvhIsReadPlusToMotionWithWarnings) {
  const auto path = std::filesystem::temp_directory_path() / "motionmap_bvh_test_load.bvh";
  {
    std::ofstream out(path, std::ios::binary);
    out << kSmall << "1 2 3 4 5 6 7 8 9\n";
  }
  const Clip clip = load_bvh(path.string());
  EXPECT_EQ(clip.path, path.string());
  EXPECT_EQ(clip.skeleton.num_joints(), 2);
  EXPECT_EQ(clip.motion.num_frames, 2);
  EXPECT_EQ(clip.motion.frame_time, 0.0333333);
  EXPECT_EQ(clip.motion.translation(1, 0), Eigen::Vector3d(4, 5, 6));
  ASSERT_EQ(clip.warnings.size(), 1u);
  EXPECT_EQ(clip.warnings[0], path.string() +
                                  ":21: warning: 1 extra motion row after the "
                                  "declared 2 frames ignored");
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace motionmap::io
