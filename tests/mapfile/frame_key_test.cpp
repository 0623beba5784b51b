// Key poses from frames of clips (mapfile/frame_key.h): what `motionmap inbetween --keys
// FILE:FRAME` and Python's motionmap.inbetween((clip, frame), …) both resolve their keys with.
// Real clips: two Bandai Namco walks (one skeleton) and a CMU swing (another).
#include "motionmap/mapfile/frame_key.h"

#include <cstring>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "motionmap/io/load.h"
#include "motionmap/pipeline/clip_map.h"
#include "support/test_data.h"

namespace motionmap::mapfile {
namespace {

constexpr const char* kAngry = "bandai/dataset-1_walk_angry_001.bvh";
constexpr const char* kProud = "bandai/dataset-1_walk_proud_001.bvh";
constexpr const char* kGolf = "cmu/64_08.bvh";

bool same_frame(const Motion& pose, const Motion& clip, int frame) {
  const auto J = static_cast<std::size_t>(clip.num_joints);
  const auto at = static_cast<std::size_t>(frame) * J;
  return pose.num_frames == 1 &&
         std::memcmp(pose.rotations.data(), &clip.rotations[at], J * sizeof(Eigen::Quaterniond)) ==
             0 &&
         std::memcmp(pose.translations.data(), &clip.translations[at],
                     J * sizeof(Eigen::Vector3d)) == 0;
}

std::string message_of(const KeyMap& on, const Clip& clip, int frame) {
  try {
    frame_key(on, clip, frame);
  } catch (const ParameterError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(FrameKey, SamplesSitOnTheirPointOthersArePlaced) {
  MOTIONMAP_REQUIRE_SHARED(kAngry);
  MOTIONMAP_REQUIRE_SHARED(kProud);
  MOTIONMAP_REQUIRE_SHARED(kGolf);
  // A map of every other frame of the angry walk.
  const std::vector<Clip> clips{io::load_clip(test::shared_file(kAngry))};
  pipeline::ClipMapOptions options;
  options.features.stride = 2;
  options.embed.method = embed::Method::Pca;
  pipeline::ClipMap map = pipeline::map_clips(clips, options);
  const features::FeatureSet samples = *map.features;
  const synth::MapBlender blender(clips, samples, map.embedding.coordinates);
  const MapFile file = make_map_file(clips, map, options);
  int map_file_calls = 0;
  KeyMap on;
  on.blender = &blender;
  on.samples = &samples;
  on.clip_files = {clips[0].path};
  on.reference = &clips[0];
  on.map_file = [&]() -> const MapFile& {
    ++map_file_calls;
    return file;
  };

  // A sample (frame 10: every other frame from 0 is one): synth::sample_key, on its point.
  const int sample = synth::find_sample(samples, 0, 10);
  ASSERT_GE(sample, 0);
  const FrameKey at_sample = frame_key(on, clips[0], 10);
  EXPECT_FALSE(at_sample.placed);
  EXPECT_EQ(at_sample.key.point, Eigen::Vector2d(map.embedding.coordinates(sample, 0),
                                                 map.embedding.coordinates(sample, 1)));
  const synth::Key direct = synth::sample_key(blender, sample, clips[0].motion, 10);
  EXPECT_EQ(at_sample.key.pose.rotations, direct.pose.rotations);
  EXPECT_EQ(at_sample.key.pose.translations, direct.pose.translations);
  EXPECT_EQ(map_file_calls, 0);  // nothing placed: the map file is not asked for

  // A frame the stride left out: placed as `map --onto` places it, its own pose kept.
  const FrameKey left_out = frame_key(on, clips[0], 11);
  EXPECT_TRUE(left_out.placed);
  EXPECT_EQ(map_file_calls, 1);
  PlaceOptions one;
  one.first_frame = 11;
  one.end_frame = 12;
  one.keep_first = true;
  const Placement placed = place_clips(clips, file, one);
  EXPECT_EQ(left_out.key.point,
            Eigen::Vector2d(placed.coordinates(0, 0), placed.coordinates(0, 1)));
  EXPECT_TRUE(same_frame(left_out.key.pose, clips[0].motion, 11));
  // The same frame through another path to the same file is still the map's sample.
  Clip renamed = clips[0];
  renamed.path = test::shared_file("bandai/../bandai/dataset-1_walk_angry_001.bvh");
  EXPECT_FALSE(frame_key(on, renamed, 10).placed);

  // A clip not in the map, of the same skeleton: placed.
  const Clip proud = io::load_clip(test::shared_file(kProud));
  const FrameKey other = frame_key(on, proud, 40);
  EXPECT_TRUE(other.placed);
  EXPECT_TRUE(same_frame(other.key.pose, proud.motion, 40));
  EXPECT_TRUE(other.key.point.allFinite());

  // Errors name the clip and what was expected.
  EXPECT_EQ(message_of(on, clips[0], 143),
            "frame 143 is out of range: " + clips[0].path + " has 143 frames, 0 to 142");
  EXPECT_EQ(message_of(on, clips[0], -1),
            "frame -1 is out of range: " + clips[0].path + " has 143 frames, 0 to 142");
  const Clip golf = io::load_clip(test::shared_file(kGolf));
  const std::string skeleton = message_of(on, golf, 5);
  EXPECT_EQ(skeleton.rfind(golf.path + " is a clip of another skeleton than the map's (", 0), 0u)
      << skeleton;
  EXPECT_NE(skeleton.find("; a key is a frame of a clip of the map's skeleton"), std::string::npos)
      << skeleton;
  KeyMap without_file = on;
  without_file.map_file = nullptr;
  EXPECT_NE(message_of(without_file, clips[0], 11).find("is not a sample of the map"),
            std::string::npos);
  EXPECT_NO_THROW(frame_key(without_file, clips[0], 10));
  KeyMap empty;
  EXPECT_NE(message_of(empty, clips[0], 10).find("blender, samples and reference"),
            std::string::npos);
}

// A key's clip named by the end of its path (no file needs to be there: paths only).
TEST(FrameKey, AClipOfTheMapNamedByTheEndOfItsPath) {
  const std::vector<std::string> map{"/data/takes/walk.bvh", "/data/old/walk.bvh",
                                     "/data/takes/run.bvh", "bow.bvh"};
  EXPECT_EQ(map_clip_named(map, "run.bvh"), "/data/takes/run.bvh");
  EXPECT_EQ(map_clip_named(map, "takes/walk.bvh"), "/data/takes/walk.bvh");
  EXPECT_EQ(map_clip_named(map, "./old//walk.bvh"), "/data/old/walk.bvh");
  EXPECT_EQ(map_clip_named(map, "bow.bvh"), "bow.bvh");
  const auto error = [&](const std::string& name) {
    try {
      map_clip_named(map, name);
    } catch (const ParameterError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(error("walk.bvh"),
            "'walk.bvh' names 2 clips of the map (/data/takes/walk.bvh, /data/old/walk.bvh): give "
            "more of its path");
  EXPECT_EQ(error("jog.bvh"),
            "no such clip file 'jog.bvh', and no clip of the map is named so (its 4 clips: "
            "walk.bvh, walk.bvh, run.bvh, …)");
  // A name that is part of clips' file names: those clips, each by the shortest path end that
  // names it alone.
  EXPECT_EQ(error("alk.bvh"),
            "no such clip file 'alk.bvh', and no clip of the map is named so; did you mean "
            "/data/takes/walk.bvh or /data/old/walk.bvh?");
  EXPECT_EQ(error("RUN"),
            "no such clip file 'RUN', and no clip of the map is named so; did you mean run.bvh?");
  EXPECT_EQ(error("un.bvh"),
            "no such clip file 'un.bvh', and no clip of the map is named so; did you mean "
            "run.bvh?");
  EXPECT_EQ(error(".bvh"),
            "no such clip file '.bvh', and no clip of the map is named so (its 4 clips: "
            "walk.bvh, walk.bvh, run.bvh, …)");
  EXPECT_EQ(map_clip_named({"/a/b.bvh"}, "b.bvh"), "/a/b.bvh");
  try {
    map_clip_named({"/a/b.bvh"}, "c.bvh");
    ADD_FAILURE();
  } catch (const ParameterError& e) {
    EXPECT_STREQ(e.what(),
                 "no such clip file 'c.bvh', and no clip of the map is named so (its clip: b.bvh)");
  }
}

}  // namespace
}  // namespace motionmap::mapfile
