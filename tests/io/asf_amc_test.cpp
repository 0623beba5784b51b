#include "motionmap/io/amc.h"
#include "motionmap/io/asf.h"

#include <cmath>
#include <initializer_list>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "motionmap/io/load.h"
#include "motionmap/skeleton/forward_kinematics.h"
#include "support/test_data.h"

namespace motionmap::io {
namespace {

// A two-bone skeleton: `a` points up (length 2) with its axis turned 90° about Z and one dof rx;
// `b` hangs from a's end, points along +X (length 3), dofs rx ry rz. Line numbers in comments.
std::vector<std::string> tiny_asf_lines() {
  return {
      ":version 1.10",              // 1
      ":name tiny",                 // 2
      ":units",                     // 3
      "  mass 1.0",                 // 4
      "  length 1.0",               // 5
      "  angle deg",                // 6
      ":root",                      // 7
      "  order TX TY TZ RX RY RZ",  // 8
      "  axis XYZ",                 // 9
      "  position 0 0 0",           // 10
      "  orientation 0 0 0",        // 11
      ":bonedata",                  // 12
      "  begin",                    // 13
      "    id 1",                   // 14
      "    name a",                 // 15
      "    direction 0 1 0",        // 16
      "    length 2",               // 17
      "    axis 0 0 90 XYZ",        // 18
      "    dof rx",                 // 19
      "    limits (-inf inf)",      // 20
      "  end",                      // 21
      "  begin",                    // 22
      "    id 2",                   // 23
      "    name b",                 // 24
      "    direction 1 0 0",        // 25
      "    length 3",               // 26
      "    axis 0 0 0 XYZ",         // 27
      "    dof rx ry rz",           // 28
      "    limits (-10 10)",        // 29
      "           (-20 20)",        // 30
      "           (-30 30)",        // 31
      "  end",                      // 32
      ":hierarchy",                 // 33
      "  begin",                    // 34
      "    root a",                 // 35
      "    a b",                    // 36
      "  end",                      // 37
  };
}

std::string join(const std::vector<std::string>& lines, const char* eol = "\n") {
  std::string out;
  for (const auto& l : lines) out += l + eol;
  return out;
}

std::string tiny_asf() {
  return join(tiny_asf_lines());
}

// tiny_asf_lines() with line `line` (1-based) replaced by `text` (or removed when text is null).
std::string tiny_asf_with(std::size_t line, const char* text) {
  auto lines = tiny_asf_lines();
  if (text) {
    lines.at(line - 1) = text;
  } else {
    lines.erase(lines.begin() + static_cast<long>(line - 1));
  }
  return join(lines);
}

const char* kTinyAmc =
    ":FULLY-SPECIFIED\n"  // 1
    ":DEGREES\n"          // 2
    "1\n"                 // 3
    "root 1 2 3 0 0 0\n"  // 4
    "a 90\n"              // 5
    "b 0 0 0\n"           // 6
    "2\n"                 // 7
    "root 1 2 3 0 0 0\n"  // 8
    "a 0\n"               // 9
    "b 90 90 0\n";        // 10

template <typename F>
ParseError parse_error_of(F f) {
  try {
    f();
  } catch (const ParseError& e) {
    return e;
  }
  ADD_FAILURE() << "no ParseError thrown";
  return ParseError("", 0, 0, "");
}

// Asserts that parsing `asf` fails at line:column with exactly `message`.
void expect_asf_error(const std::string& asf, std::size_t line, std::size_t column,
                      const std::string& message) {
  const ParseError e = parse_error_of([&] { parse_asf(asf, "s.asf"); });
  EXPECT_EQ(e.path(), "s.asf");
  EXPECT_EQ(e.line(), line) << e.what();
  EXPECT_EQ(e.column(), column) << e.what();
  EXPECT_EQ(e.message(), message);
  EXPECT_EQ(std::string(e.what()),
            "s.asf:" + std::to_string(line) + ":" + std::to_string(column) + ": error: " + message);
}

void expect_amc_error(const std::string& amc, std::size_t line, std::size_t column,
                      const std::string& message) {
  const AsfSkeleton asf = parse_asf(tiny_asf());
  const ParseError e = parse_error_of([&] { parse_amc(amc, asf, 120.0, "m.amc"); });
  EXPECT_EQ(e.line(), line) << e.what();
  EXPECT_EQ(e.column(), column) << e.what();
  EXPECT_EQ(e.message(), message);
}

void expect_near(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double tol = 1e-12) {
  EXPECT_LT((a - b).norm(), tol) << "got " << a.transpose() << ", expected " << b.transpose();
}

// World position of joint `name`'s end site in `frame`.
Eigen::Vector3d end_site(const Skeleton& s, const Motion& m, int frame, const std::string& name) {
  const WorldPose w = forward_kinematics(s, m, frame);
  std::size_t e = 0;
  for (int j = 0; j < s.num_joints(); ++j) {
    if (s.joints[j].name == name) return w.end_sites.at(e);
    e += s.joints[j].end_sites.size();
  }
  ADD_FAILURE() << "no end site for " << name;
  return Eigen::Vector3d::Zero();
}

Eigen::Quaterniond rot(Axis a, double degrees) {
  return axis_rotation(a, deg_to_rad(degrees));
}

// ---------------------------------------------------------------------------------------------
// Parsing and conversion: known answers.

TEST(AsfParse, TinySkeletonFields) {
  const AsfSkeleton asf = parse_asf(tiny_asf());
  EXPECT_EQ(asf.name, "tiny");
  EXPECT_TRUE(asf.angles_in_degrees);
  ASSERT_EQ(asf.root_order.size(), 6u);
  EXPECT_EQ(asf.root_order[0], Dof::TX);
  EXPECT_EQ(asf.root_order[5], Dof::RZ);
  ASSERT_EQ(asf.bones.size(), 2u);
  const AsfBone& a = asf.bones[0];
  EXPECT_EQ(a.name, "a");
  EXPECT_EQ(a.id, 1);
  EXPECT_EQ(a.parent, -1);
  expect_near(a.axis_angles, {0, 0, 90});
  ASSERT_EQ(a.limits.size(), 1u);
  EXPECT_EQ(a.limits[0].first, -std::numeric_limits<double>::infinity());
  EXPECT_EQ(a.limits[0].second, std::numeric_limits<double>::infinity());
  const AsfBone& b = asf.bones[1];
  EXPECT_EQ(b.parent, 0);
  EXPECT_EQ(b.dofs, (std::vector<Dof>{Dof::RX, Dof::RY, Dof::RZ}));
  ASSERT_EQ(b.limits.size(), 3u);
  EXPECT_EQ(b.limits[2], (std::pair<double, double>(-30, 30)));
  EXPECT_TRUE(asf.warnings.empty());
}

TEST(AsfParse, Cmu02Skeleton) {
  MOTIONMAP_REQUIRE_SHARED("asfamc/02.asf");
  const AsfSkeleton asf = read_asf(test::shared_file("asfamc/02.asf"));
  EXPECT_EQ(asf.name, "VICON");
  EXPECT_DOUBLE_EQ(asf.length_unit, 0.45);
  EXPECT_DOUBLE_EQ(asf.mass_unit, 1.0);
  EXPECT_TRUE(asf.angles_in_degrees);
  EXPECT_EQ(asf.root_order,
            (std::vector<Dof>{Dof::TX, Dof::TY, Dof::TZ, Dof::RX, Dof::RY, Dof::RZ}));
  ASSERT_EQ(asf.bones.size(), 30u);
  // CMU lists bones depth-first already: the order is the file's (ids 1..30).
  for (std::size_t i = 0; i < asf.bones.size(); ++i) {
    EXPECT_EQ(asf.bones[i].id, static_cast<int>(i) + 1);
    EXPECT_LT(asf.bones[i].parent, static_cast<int>(i));
    EXPECT_NEAR(asf.bones[i].direction.norm(), 1.0, 1e-12);
  }
  const AsfBone& lfemur = asf.bones[1];
  EXPECT_EQ(lfemur.name, "lfemur");
  EXPECT_EQ(asf.bones[lfemur.parent].name, "lhipjoint");
  EXPECT_DOUBLE_EQ(lfemur.length, 7.59371);
  expect_near(lfemur.axis_angles, {0, 0, 20});
  EXPECT_EQ(lfemur.limits[0], (std::pair<double, double>(-160, 20)));
  EXPECT_EQ(lfemur.limits[2], (std::pair<double, double>(-60, 70)));
  const AsfBone& lfoot = asf.bones[3];
  EXPECT_EQ(lfoot.dofs, (std::vector<Dof>{Dof::RX, Dof::RZ}));
  EXPECT_DOUBLE_EQ(lfoot.axis_angles[1], 7.62852e-016);
  EXPECT_EQ(asf.bones[16].name, "lclavicle");
  EXPECT_EQ(asf.bones[asf.bones[16].parent].name, "thorax");
}

TEST(AsfToSkeleton, Cmu02JointsOffsetsChannelsEndSites) {
  MOTIONMAP_REQUIRE_SHARED("asfamc/02.asf");
  const AsfSkeleton asf = read_asf(test::shared_file("asfamc/02.asf"));
  const Skeleton s = asf_to_skeleton(asf);
  ASSERT_EQ(s.num_joints(), 31);
  EXPECT_NO_THROW(s.validate());
  using C = ChannelType;
  EXPECT_EQ(s.joints[0].name, "root");
  EXPECT_EQ(s.joints[0].channels, (std::vector<C>{C::Xposition, C::Yposition, C::Zposition,
                                                  C::Zrotation, C::Yrotation, C::Xrotation}));
  const int lhip = s.find("lhipjoint"), lfemur = s.find("lfemur"), ltibia = s.find("ltibia");
  EXPECT_TRUE(s.joints[lhip].channels.empty());  // no dofs
  EXPECT_EQ(s.joints[ltibia].channels, (std::vector<C>{C::Zrotation, C::Yrotation, C::Xrotation}));
  // Root's children start at the root; others at their parent bone's end.
  expect_near(s.joints[lhip].offset, Eigen::Vector3d::Zero());
  expect_near(s.joints[lfemur].offset, asf.bones[0].direction * 2.52691);
  expect_near(s.joints[ltibia].offset,
              Eigen::Vector3d(0.34202, -0.939693, 0).normalized() * 7.59371, 1e-12);
  // Leaves: ltoes rtoes head lfingers lthumb rfingers rthumb.
  EXPECT_EQ(s.num_end_sites(), 7);
  const auto& head = s.joints[s.find("head")];
  ASSERT_EQ(head.end_sites.size(), 1u);
  EXPECT_NEAR(head.end_sites[0].norm(), 1.6265, 1e-12);
}

TEST(AmcParse, TinyKnownPoses) {
  const AsfSkeleton asf = parse_asf(tiny_asf());
  const Motion m = parse_amc(kTinyAmc, asf, 60.0);
  const Skeleton s = asf_to_skeleton(asf);
  ASSERT_EQ(m.num_frames, 2);
  ASSERT_EQ(m.num_joints, 3);
  EXPECT_DOUBLE_EQ(m.fps(), 60.0);
  // Frame 1: a's rx = 90° about its axis frame C = Rz(90): a rotation of 90° about world Y.
  EXPECT_LT(rotation_angle(m.rotation(0, 1), rot(Axis::Y, 90)), 1e-12);
  expect_near(m.translation(0, 0), {1, 2, 3});
  // b's end: root (1,2,3) + a's length along Y + Ry(90)·(3,0,0) = (0,0,-3).
  expect_near(end_site(s, m, 0, "b"), {1, 4, 0});
  // Frame 2: b's dofs rx ry rz = (90, 90, 0) compose as Rz·Ry·Rx: Ry(90)·Rx(90)·(3,0,0) = (0,0,-3).
  EXPECT_LT(rotation_angle(m.rotation(1, 2), rot(Axis::Y, 90) * rot(Axis::X, 90)), 1e-12);
  expect_near(end_site(s, m, 1, "b"), {1, 4, 0});
}

TEST(AmcParse, AxisTripleComposesXFirst) {
  // axis 90 90 0 XYZ means C = Rz(0)·Ry(90)·Rx(90); a dof rz then turns about C·z.
  auto lines = tiny_asf_lines();
  lines[17] = "    axis 90 90 0 XYZ";
  lines[18] = "    dof rz";
  const AsfSkeleton asf = parse_asf(join(lines));
  const Motion m = parse_amc("1\na 30\n", asf);
  const Eigen::Quaterniond c = rot(Axis::Y, 90) * rot(Axis::X, 90);
  EXPECT_LT(rotation_angle(m.rotation(0, 1), c * rot(Axis::Z, 30) * c.conjugate()), 1e-12);
  // C·z = Ry(90)·Rx(90)·z = Ry(90)·(−y) = −y: a turn of 30° about −Y.
  EXPECT_LT(rotation_angle(m.rotation(0, 1), rot(Axis::Y, -30)), 1e-12);
}

TEST(AmcParse, DofOrderAsListedRootOrderAndRadians) {
  // Bone a: `dof rz rx` gives R = Rx·Rz (first listed, first applied). Root order puts rotation
  // first and animates only Y of the translation (X, Z keep `position`). Angles in radians.
  auto lines = tiny_asf_lines();
  lines[5] = "  angle rad";
  lines[7] = "  order RY TY";
  lines[9] = "  position 5 6 7";
  lines[17] = "    axis 0 0 0 XYZ";
  lines[18] = "    dof rz rx";
  lines[19] = "    limits (-1 1) (-2 2)";
  const AsfSkeleton asf = parse_asf(join(lines));
  EXPECT_FALSE(asf.angles_in_degrees);
  const Motion m = parse_amc("1\nroot 0.5 -1\na 0.25 1.5\n", asf);
  expect_near(m.translation(0, 0), {5, -1, 7});
  EXPECT_LT(rotation_angle(m.rotation(0, 0), axis_rotation(Axis::Y, 0.5)), 1e-12);
  EXPECT_LT(
      rotation_angle(m.rotation(0, 1), axis_rotation(Axis::X, 1.5) * axis_rotation(Axis::Z, 0.25)),
      1e-12);
  // An AMC :DEGREES overrides the ASF's radians.
  const Motion d = parse_amc(":DEGREES\n1\nroot 90 0\n", asf);
  EXPECT_LT(rotation_angle(d.rotation(0, 0), rot(Axis::Y, 90)), 1e-12);
}

TEST(AmcParse, AbsentBonesKeepRestPose) {
  const AsfSkeleton asf = parse_asf(tiny_asf());
  const Motion m = parse_amc("# only b moves\n7\nb 0 0 90\n8\n", asf);
  ASSERT_EQ(m.num_frames, 2);
  for (int f = 0; f < 2; ++f) {
    EXPECT_LT(rotation_angle(m.rotation(f, 0), Eigen::Quaterniond::Identity()), 1e-15);
    EXPECT_LT(rotation_angle(m.rotation(f, 1), Eigen::Quaterniond::Identity()), 1e-15);
    expect_near(m.translation(f, 0), Eigen::Vector3d::Zero());
    expect_near(m.translation(f, 2), {0, 2, 0});  // rest offset: a's direction × length
  }
  EXPECT_LT(rotation_angle(m.rotation(0, 2), rot(Axis::Z, 90)), 1e-12);
  EXPECT_LT(rotation_angle(m.rotation(1, 2), Eigen::Quaterniond::Identity()), 1e-15);
}

TEST(AmcParse, TranslationAndLengthDofs) {
  // a: `dof tx l` with C = Rz(90): tx moves a's joint along C·x = +Y; l stretches a, moving b.
  auto lines = tiny_asf_lines();
  lines[18] = "    dof tx l";
  lines[19] = "    limits (-1 1) (0 5)";
  const AsfSkeleton asf = parse_asf(join(lines));
  const Skeleton s = asf_to_skeleton(asf);
  using C = ChannelType;
  EXPECT_EQ(s.joints[1].channels, (std::vector<C>{C::Xposition, C::Yposition, C::Zposition}));
  EXPECT_EQ(s.joints[2].channels, (std::vector<C>{C::Xposition, C::Yposition, C::Zposition,
                                                  C::Zrotation, C::Yrotation, C::Xrotation}));
  const Motion m = parse_amc("1\nb 0 0 0\na 0.5 1\n", asf);
  expect_near(m.translation(0, 1), {0, 0.5, 0}, 1e-12);
  expect_near(m.translation(0, 2), {0, 3, 0}, 1e-12);  // (2 + 1) along a's direction
  expect_near(end_site(s, m, 0, "b"), {3, 3.5, 0}, 1e-12);
}

TEST(AsfParse, LenientFormsRealFilesUse) {
  // CRLF, comments, upper-case keywords and dofs, :skin (warned), bodymass/cofmass, limits
  // with loose parentheses across lines, a bone declared before its parent, tabs.
  const std::string text =
      "# header\r\n"
      ":VERSION 1.10\r\n"
      ":NAME two words\r\n"
      ":DOCUMENTATION\r\n"
      "  free text, even begin / end / limits (\r\n"
      ":ROOT\r\n"
      "\tORDER tx ty tz rz ry rx\r\n"
      "\tAXIS xyz\r\n"
      ":BONEDATA\r\n"
      "  BEGIN\r\n"
      "    NAME child  # a trailing comment\r\n"
      "    DIRECTION 0 0 2\r\n"
      "    LENGTH 1\r\n"
      "    AXIS 0 0 0 zyx\r\n"
      "    DOF RX Rz\r\n"
      "    LIMITS ( -inf\r\n"
      "     +inf ) (\r\n"
      "  -1e1 1E1\r\n"
      " )\r\n"
      "    BODYMASS 2.5\r\n"
      "    COFMASS 0.5\r\n"
      "  END\r\n"
      "#\r\n"
      "  begin\r\n"
      "    name parent\r\n"
      "    direction 0 1 0\r\n"
      "    length 1\r\n"
      "    axis 0 0 0 XYZ\r\n"
      "  end\r\n"
      ":hierarchy\r\n"
      "  begin\r\n"
      "    ROOT parent\r\n"
      "    parent child\r\n"
      "  end\r\n"
      ":skin\r\n"
      "  body.skin\r\n";
  const AsfSkeleton asf = parse_asf(text, "x.asf");
  EXPECT_EQ(asf.name, "two words");
  ASSERT_EQ(asf.bones.size(), 2u);
  EXPECT_EQ(asf.bones[0].name, "parent");  // reordered: parents first
  EXPECT_EQ(asf.bones[1].name, "child");
  EXPECT_EQ(asf.bones[1].parent, 0);
  expect_near(asf.bones[1].direction, {0, 0, 1});  // normalised
  EXPECT_EQ(asf.bones[1].axis_order, (std::array<Axis, 3>{Axis::Z, Axis::Y, Axis::X}));
  EXPECT_EQ(asf.bones[1].dofs, (std::vector<Dof>{Dof::RX, Dof::RZ}));
  EXPECT_EQ(asf.bones[1].limits[1], (std::pair<double, double>(-10, 10)));
  EXPECT_TRUE(std::isinf(asf.bones[1].limits[0].second));
  EXPECT_EQ(asf.root_order[3], Dof::RZ);
  ASSERT_EQ(asf.warnings.size(), 1u);
  EXPECT_EQ(asf.warnings[0],
            "x.asf:35: warning: ':skin' section ignored (skin files are not used)");
  // Lone-CR line ends too.
  std::string cr = tiny_asf();
  for (char& ch : cr) {
    if (ch == '\n') ch = '\r';
  }
  EXPECT_EQ(parse_asf(cr).bones.size(), 2u);
}

TEST(AmcParse, Cmu02_03RootOfFirstFrame) {
  MOTIONMAP_REQUIRE_SHARED("asfamc/02_03.amc");
  const Clip clip =
      load_asf_amc(test::shared_file("asfamc/02.asf"), test::shared_file("asfamc/02_03.amc"));
  EXPECT_EQ(clip.motion.num_frames, 173);
  EXPECT_EQ(clip.motion.num_joints, 31);
  EXPECT_DOUBLE_EQ(clip.motion.fps(), 120.0);
  EXPECT_EQ(clip.path, test::shared_file("asfamc/02_03.amc"));
  EXPECT_TRUE(clip.warnings.empty());
  // "root 9.28722 16.95 -34.2762 8.20944 3.39386 1.16184": R = Rz·Ry·Rx.
  expect_near(clip.motion.translation(0, 0), {9.28722, 16.95, -34.2762});
  const Eigen::Quaterniond r =
      rot(Axis::Z, 1.16184) * rot(Axis::Y, 3.39386) * rot(Axis::X, 8.20944);
  EXPECT_LT(rotation_angle(clip.motion.rotation(0, 0), r), 1e-12);
  // "lowerback 6.78285 -4.34327 -2.18541" with axis 0 0 0.
  const int lowerback = clip.skeleton.find("lowerback");
  const Eigen::Quaterniond lb =
      rot(Axis::Z, -2.18541) * rot(Axis::Y, -4.34327) * rot(Axis::X, 6.78285);
  EXPECT_LT(rotation_angle(clip.motion.rotation(0, lowerback), lb), 1e-12);
  // "ltibia 24.253" with axis 0 0 20: a knee bend about the tilted axis Rz(20)·x.
  const int ltibia = clip.skeleton.find("ltibia");
  const Eigen::Quaterniond c = rot(Axis::Z, 20);
  EXPECT_LT(
      rotation_angle(clip.motion.rotation(0, ltibia), c * rot(Axis::X, 24.253) * c.conjugate()),
      1e-12);
  for (const auto& q : clip.motion.rotations) ASSERT_NEAR(q.norm(), 1.0, 1e-12);
  EXPECT_EQ(load_asf_amc(test::shared_file("asfamc/02.asf"), test::shared_file("asfamc/02_02.amc"))
                .motion.num_frames,
            298);
}

TEST(AmcParse, LoadClipFindsTheSubjectsAsf) {
  MOTIONMAP_REQUIRE_SHARED("asfamc/02_03.amc");
  const Clip clip = load_clip(test::shared_file("asfamc/02_03.amc"), {.asf_path = "", .fps = 30});
  EXPECT_EQ(clip.motion.num_frames, 173);
  EXPECT_DOUBLE_EQ(clip.motion.fps(), 30.0);
  EXPECT_EQ(clip.skeleton.num_joints(), 31);
}

TEST(AmcParse, RejectsBadFrameRateAndInconsistentSkeleton) {
  const AsfSkeleton asf = parse_asf(tiny_asf());
  EXPECT_THROW(parse_amc(kTinyAmc, asf, 0.0), ParameterError);
  EXPECT_THROW(parse_amc(kTinyAmc, asf, std::nan("")), ParameterError);
  AsfSkeleton bad = asf;
  bad.bones[0].parent = 1;
  EXPECT_THROW(asf_to_skeleton(bad), ParameterError);
  EXPECT_THROW(load_asf_amc("/nonexistent/x.asf", "/nonexistent/x.amc"), Error);
}

// ---------------------------------------------------------------------------------------------
// ASF errors: every one names its line, column and what was expected.

constexpr const char* kSectionList =
    "a section (':version', ':name', ':units', ':documentation', ':root', ':bonedata', "
    "':hierarchy')";

TEST(AsfErrors, EmptyGarbageAndUnknownSection) {
  expect_asf_error("", 1, 1, std::string("expected ") + kSectionList + ", found end of file");
  expect_asf_error("# only a comment\n\n", 3, 1,
                   std::string("expected ") + kSectionList + ", found end of file");
  expect_asf_error(std::string("\x7f"
                               "ELF\x01\x00\x02",
                               7),
                   1, 1,
                   std::string("expected ") + kSectionList + ", found '\\x7FELF\\x01\\x00\\x02'");
  expect_asf_error(tiny_asf_with(2, ":nome tiny"), 2, 1,
                   std::string("expected ") + kSectionList + ", found ':nome'");
  expect_asf_error(tiny_asf_with(2, ":units"), 3, 1,
                   "expected each section once, found ':units' again");
  expect_asf_error(tiny_asf_with(1, "version 1.10"), 1, 1,
                   std::string("expected ") + kSectionList + ", found 'version'");
}

TEST(AsfErrors, Units) {
  expect_asf_error(tiny_asf_with(5, "  time 1.0"), 5, 3,
                   "expected a unit ('mass', 'length' or 'angle') or a section, found 'time'");
  expect_asf_error(tiny_asf_with(5, "  length 0"), 5, 10,
                   "expected a positive length unit, found '0'");
  expect_asf_error(tiny_asf_with(4, "  mass"), 4, 7, "expected mass unit, found end of line");
  expect_asf_error(tiny_asf_with(6, "  angle grad"), 6, 9,
                   "expected an angle unit ('deg' or 'rad'), found 'grad'");
  expect_asf_error(tiny_asf_with(5, "  length 1.0 cm"), 5, 14, "expected end of line, found 'cm'");
}

TEST(AsfErrors, Root) {
  expect_asf_error(tiny_asf_with(9, "  axes XYZ"), 9, 3,
                   "expected a root keyword ('order', 'axis', 'position', 'orientation') or a "
                   "section, found 'axes'");
  expect_asf_error(tiny_asf_with(8, "  order TX TY L"), 8, 15,
                   "expected a root dof (TX, TY, TZ, RX, RY or RZ), found 'L'");
  expect_asf_error(tiny_asf_with(8, "  order TX TX"), 8, 12,
                   "expected each dof once, found 'TX' again");
  expect_asf_error(tiny_asf_with(8, "  axis XYZ"), 9, 3,
                   "expected each root keyword once, found 'axis' again");
  expect_asf_error(tiny_asf_with(8, nullptr), 11, 1,
                   "expected 'order' in the :root section, found ':bonedata'");
  expect_asf_error(tiny_asf_with(9, "  axis XYY"), 9, 8,
                   "expected an axis order (a permutation of XYZ), found 'XYY'");
  expect_asf_error(tiny_asf_with(10, "  position 0 nan 0"), 10, 14,
                   "expected root position (a finite number), found 'nan'");
  expect_asf_error(tiny_asf_with(11, "  orientation 0 0"), 11, 18,
                   "expected root orientation, found end of line");
}

TEST(AsfErrors, MissingSections) {
  auto lines = tiny_asf_lines();
  lines.resize(32);  // no :hierarchy
  expect_asf_error(join(lines), 33, 1, "expected section ':hierarchy', found end of file");
  lines.resize(11);  // no :bonedata either
  expect_asf_error(join(lines), 12, 1, "expected section ':bonedata', found end of file");
  lines.resize(6);
  expect_asf_error(join(lines), 7, 1, "expected section ':root', found end of file");
}

TEST(AsfErrors, BoneBlocks) {
  expect_asf_error(tiny_asf_with(13, "  begn"), 13, 3,
                   "expected 'begin' or a section, found 'begn'");
  expect_asf_error(tiny_asf_with(14, "    idx 1"), 14, 5,
                   "expected a bone keyword ('id', 'name', 'direction', 'length', 'axis', 'dof', "
                   "'limits', 'bodymass', 'cofmass') or 'end', found 'idx'");
  expect_asf_error(tiny_asf_with(14, "    length 2"), 17, 5,
                   "expected each keyword once in a bone block, found 'length' again");
  expect_asf_error(tiny_asf_with(17, "    bodymass 3"), 21, 3,
                   "expected 'length' in the bone block of bone 'a', found 'end'");
  expect_asf_error(tiny_asf_with(15, "    id2 3"), 15, 5,
                   "expected a bone keyword ('id', 'name', 'direction', 'length', 'axis', 'dof', "
                   "'limits', 'bodymass', 'cofmass') or 'end', found 'id2'");
  expect_asf_error(tiny_asf_with(15, nullptr), 20, 3,
                   "expected 'name' in the bone block, found 'end'");
  expect_asf_error(tiny_asf_with(18, nullptr), 20, 3,
                   "expected 'axis' in the bone block of bone 'a', found 'end'");
  expect_asf_error(tiny_asf_with(24, "    name a"), 24, 10,
                   "expected a bone name used once, found 'a' again");
  expect_asf_error(tiny_asf_with(24, "    name root"), 24, 10,
                   "expected a bone name other than 'root', found 'root'");
  expect_asf_error(
      tiny_asf_with(24, "    name 42"), 24, 10,
      "expected a bone name (not all digits, not starting with ':' or '#'), found '42'");
  expect_asf_error(tiny_asf_with(14, "    id one"), 14, 8,
                   "expected a bone id (an integer), found 'one'");
  auto lines = tiny_asf_lines();
  lines.resize(18);  // file ends inside a bone block
  expect_asf_error(join(lines), 19, 1,
                   "expected a bone keyword ('id', 'name', 'direction', 'length', 'axis', 'dof', "
                   "'limits', 'bodymass', 'cofmass') or 'end', found end of file");
}

TEST(AsfErrors, BoneValues) {
  expect_asf_error(tiny_asf_with(16, "    direction 0 0 0"), 16, 15,
                   "expected a non-zero direction vector, found '0'");
  expect_asf_error(tiny_asf_with(16, "    direction 0 1e999 0"), 16, 17,
                   "expected bone direction (a finite number), found '1e999'");
  expect_asf_error(tiny_asf_with(16, "    direction 0 y 0"), 16, 17,
                   "expected bone direction, found 'y'");
  expect_asf_error(tiny_asf_with(17, "    length -2"), 17, 12,
                   "expected a non-negative bone length, found '-2'");
  expect_asf_error(tiny_asf_with(17, "    length inf"), 17, 12,
                   "expected bone length (a finite number), found 'inf'");
  expect_asf_error(tiny_asf_with(17, "    length 2 3"), 17, 14, "expected end of line, found '3'");
  expect_asf_error(tiny_asf_with(18, "    axis 0 0 90"), 18, 16,
                   "expected an axis order (a permutation of XYZ), found end of line");
  expect_asf_error(tiny_asf_with(18, "    axis 0 0 90 XYW"), 18, 17,
                   "expected an axis order (a permutation of XYZ), found 'XYW'");
}

TEST(AsfErrors, DofsAndLimits) {
  expect_asf_error(tiny_asf_with(28, "    dof rx rw rz"), 28, 12,
                   "expected a dof name (rx, ry, rz, tx, ty, tz or l), found 'rw'");
  expect_asf_error(tiny_asf_with(28, "    dof"), 28, 8,
                   "expected a dof name (rx, ry, rz, tx, ty, tz or l), found end of line");
  expect_asf_error(tiny_asf_with(28, "    dof rx ry rx"), 28, 15,
                   "expected each dof once, found 'rx' again");
  // Fewer limits than dofs, more, before `dof`, malformed pairs.
  expect_asf_error(tiny_asf_with(28, "    dof rx ry rz l"), 32, 3,
                   "expected '(' opening limit 4 of 4 (dof l), found 'end'");
  expect_asf_error(tiny_asf_with(28, "    dof rx ry"), 31, 12,
                   "expected 2 limits (one per dof), found '(-30'");
  expect_asf_error(tiny_asf_with(20, "    dof rx"), 20, 5,
                   "expected each keyword once in a bone block, found 'dof' again");
  expect_asf_error(tiny_asf_with(19, "    bodymass 5"), 20, 5,
                   "expected 'dof' before 'limits', found 'limits'");
  expect_asf_error(tiny_asf_with(29, "    limits (-10 ten)"), 29, 17,
                   "expected the upper limit 1 of 3 (dof rx) (a number or inf), found 'ten)'");
  expect_asf_error(tiny_asf_with(29, "    limits (nan 10)"), 29, 13,
                   "expected the lower limit 1 of 3 (dof rx) (a number or inf), found 'nan'");
  expect_asf_error(tiny_asf_with(29, "    limits -10 10"), 29, 12,
                   "expected '(' opening limit 1 of 3 (dof rx), found '-10'");
  expect_asf_error(tiny_asf_with(29, "    limits (-10 10 20)"), 29, 20,
                   "expected ')' closing limit 1 of 3 (dof rx), found '20)'");
  expect_asf_error(tiny_asf_with(20, "    limits (-inf inf"), 21, 3,
                   "expected ')' closing limit 1 of 1 (dof rx), found 'end'");
}

TEST(AsfErrors, Hierarchy) {
  expect_asf_error(tiny_asf_with(34, "  begn"), 34, 3, "expected 'begin', found 'begn'");
  expect_asf_error(tiny_asf_with(36, "    x b"), 36, 5,
                   "expected 'root' or a bone declared in :bonedata, found 'x'");
  expect_asf_error(tiny_asf_with(36, "    a b c"), 36, 9,
                   "expected a bone declared in :bonedata, found 'c'");
  expect_asf_error(tiny_asf_with(35, "    root a b"), 36, 7,
                   "expected a bone not attached yet, found 'b' (already a child of 'root' on line "
                   "35)");
  expect_asf_error(tiny_asf_with(36, "    a"), 36, 6,
                   "expected a child bone name after 'a', found end of line");
  expect_asf_error(tiny_asf_with(36, nullptr), 36, 3,
                   "expected a hierarchy line attaching bone 'b', found 'end'");
  expect_asf_error(tiny_asf_with(35, "    b a"), 35, 7,
                   "expected a bone connected to 'root', found 'a' (in a cycle, each a child of "
                   "the next: a -> b -> a)");
  expect_asf_error(tiny_asf_with(36, "    b b"), 36, 7,
                   "expected a bone connected to 'root', found 'b' (in a cycle, each a child of "
                   "the next: b -> b)");
  auto lines = tiny_asf_lines();
  lines.resize(36);  // no `end`
  expect_asf_error(join(lines), 37, 1, "expected a hierarchy line or 'end', found end of file");
  lines[35] = ":bonedata";
  expect_asf_error(join(lines), 36, 1, "expected a hierarchy line or 'end', found ':bonedata'");
}

// ---------------------------------------------------------------------------------------------
// AMC errors.

TEST(AmcErrors, EmptyHeaderOnlyAndGarbage) {
  expect_amc_error("", 1, 1, "expected a frame number, found end of file");
  expect_amc_error(":FULLY-SPECIFIED\n:DEGREES\n", 3, 1,
                   "expected a frame number, found end of file");
  expect_amc_error(std::string("\x89PNG\r\n\x1a\n", 8), 1, 1,
                   "expected a frame number, found '\\x89PNG'");
  expect_amc_error(":FULLY-SPECIFIED\nroot 1 2 3 0 0 0\n", 2, 1,
                   "expected a frame number, found 'root'");
  expect_amc_error(":DEGREES\n:SECONDS\n1\n", 2, 1,
                   "expected ':FULLY-SPECIFIED', ':DEGREES' or ':RADIANS', found ':SECONDS'");
  expect_amc_error(":DEGREES\n:RADIANS\n1\n", 2, 1, "expected one angle unit, found ':RADIANS'");
  expect_amc_error("1\n:DEGREES\n", 2, 1,
                   "expected a frame number or a bone line, found ':DEGREES'");
}

TEST(AmcErrors, FramesAndBones) {
  expect_amc_error("1\n2\n4\n", 3, 1, "expected frame number 3, found '4'");
  expect_amc_error("5\n5\n", 2, 1, "expected frame number 6, found '5'");
  expect_amc_error("1 2\n", 1, 3, "expected end of line after the frame number, found '2'");
  expect_amc_error("1\n99999999999\n", 2, 1, "expected a frame number, found '99999999999'");
  expect_amc_error("1\nlfemur 1 2 3\n", 2, 1,
                   "expected a bone of the skeleton or a frame number, found 'lfemur'");
  expect_amc_error("1\nb 1 2 3\na 1\nb 1 2 3\n", 4, 1,
                   "expected each bone once per frame, found 'b' again in frame 1");
}

TEST(AmcErrors, ValueCounts) {
  expect_amc_error("1\nroot 1 2 3 0 0\n", 2, 15,
                   "expected value 6 of 6 for 'root' (rz), found end of line");
  expect_amc_error("1\nb 1 2\n", 2, 6, "expected value 3 of 3 for 'b' (rz), found end of line");
  expect_amc_error("1\nb 1 2 3 4\n", 2, 9,
                   "expected end of line after the 3 values of 'b', found '4'");
  expect_amc_error("1\na\n", 2, 2, "expected value 1 of 1 for 'a' (rx), found end of line");
  expect_amc_error("1\na 1\n2\na x\n", 4, 3, "expected value 1 of 1 for 'a' (rx), found 'x'");
  expect_amc_error("1\na 1e400\n", 2, 3,
                   "expected value 1 of 1 for 'a' (rx) (a finite number), found '1e400'");
  expect_amc_error("1\na -nan\n", 2, 3,
                   "expected value 1 of 1 for 'a' (rx) (a finite number), found '-nan'");
}

}  // namespace
}  // namespace motionmap::io
