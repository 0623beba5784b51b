// pipeline::stream_map (a library read a clip at a time, twice) against map_clips of the same
// clips loaded whole: the same samples, notes and warnings, the map within 1e-10 (Procrustes
// disparity and every coordinate relative to the map's extent) with the same signs, a model that
// places frames as map_model does; progress through both passes, cancel in each, and clear
// errors.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "embed/embed_test_util.h"
#include "motionmap/core/error.h"
#include "motionmap/core/sha256.h"
#include "motionmap/io/load.h"
#include "motionmap/pipeline/clip_map.h"
#include "motionmap/pipeline/stream_map.h"
#include "support/error_message.h"
#include "support/test_data.h"

namespace motionmap::pipeline {
namespace {

using embed::Method;
using ::testing::HasSubstr;

constexpr double kTolerance = 1e-10;

std::vector<std::string> cmu(const std::vector<std::string>& names) {
  std::vector<std::string> out;
  for (const std::string& n : names) out.push_back(test::shared_file("cmu/" + n));
  return out;
}

void expect_same_map(const std::vector<std::string>& paths, const ClipMapOptions& options) {
  SCOPED_TRACE(std::string(embed::method_name(options.embed.method)) + " on " +
               std::to_string(paths.size()) + " clips");
  std::vector<Clip> clips;
  for (const std::string& p : paths) clips.push_back(io::load_clip(p));
  const ClipMap whole = map_clips(clips, options);
  const StreamedMap streamed = stream_map(paths, {}, options);
  const ClipMap& map = streamed.map;

  ASSERT_EQ(streamed.clips.size(), clips.size());
  for (std::size_t c = 0; c < clips.size(); ++c) {
    EXPECT_EQ(streamed.clips[c].path, clips[c].path);
    EXPECT_EQ(streamed.clips[c].motion.num_frames, clips[c].motion.num_frames);
    EXPECT_EQ(streamed.clips[c].motion.frame_time, clips[c].motion.frame_time);
    EXPECT_TRUE(streamed.clips[c].motion.rotations.empty());  // the poses are not kept
  }
  EXPECT_EQ(map.features->clip_of, whole.features->clip_of);
  EXPECT_EQ(map.features->frame_of, whole.features->frame_of);
  EXPECT_EQ(map.features->segment_starts, whole.features->segment_starts);
  EXPECT_EQ(map.features->joints, whole.features->joints);
  EXPECT_EQ(map.features->notes, whole.features->notes);
  EXPECT_EQ(map.features->X.rows(), 0);
  EXPECT_EQ(map.features->X.cols(), whole.features->X.cols());
  EXPECT_EQ(map.features->distance_input.cols(), whole.features->distance_input.cols());
  EXPECT_EQ(map.embedding.warnings, whole.embedding.warnings);
  EXPECT_EQ(map.dense, whole.dense);
  EXPECT_EQ(describe_parameters(map.embedding, options),
            describe_parameters(whole.embedding, options));

  const Eigen::MatrixXd& A = whole.embedding.coordinates;
  const Eigen::MatrixXd& B = map.embedding.coordinates;
  ASSERT_EQ(B.rows(), A.rows());
  EXPECT_LE(test::procrustes_disparity(A, B), kTolerance);
  const double extent = A.cwiseAbs().maxCoeff();
  EXPECT_LE((A - B).cwiseAbs().maxCoeff(), kTolerance * extent);
  for (Eigen::Index a = 0; a < A.cols(); ++a) {
    EXPECT_GT(A.col(a).dot(B.col(a)), 0.0) << "axis " << a << " flipped";
  }

  // The kept model places frames where the in-memory map's model does.
  const embed::MapModel model = map_model(map, options);
  const embed::MapModel reference = map_model(whole, options);
  embed::PlaceInput input;
  input.features = &whole.features->X;
  EXPECT_LE((embed::place(model, input) - embed::place(reference, input)).cwiseAbs().maxCoeff(),
            kTolerance * extent);
}

TEST(StreamMap, MatchesTheInMemoryMapOnRealClips) {
  for (const char* f : {"cmu/64_08.bvh", "cmu/64_09.bvh", "cmu/02_03.bvh"}) {
    MOTIONMAP_REQUIRE_SHARED(f);
  }
  const std::vector<std::string> paths = cmu({"64_08.bvh", "02_03.bvh", "64_09.bvh"});
  for (const Method method : {Method::Pca, Method::Svd}) {
    ClipMapOptions options;
    options.embed.method = method;
    expect_same_map(paths, options);
    options.embed.dimensions = 3;
    options.features.stride = 3;
    expect_same_map(paths, options);
  }
  ClipMapOptions options;
  options.embed.standardize = true;
  options.features.features = features::FeatureKind::Positions;
  expect_same_map(paths, options);
  options.features.features = features::FeatureKind::Quaternions;
  options.features.distance = features::DistanceKind::Geodesic;
  options.features.keep_first = true;
  expect_same_map(paths, options);
}

TEST(StreamMap, MatchesTheInMemoryMapOnALibraryPastTheDenseLimit) {
  MOTIONMAP_REQUIRE_SHARED("cmu/64_08.bvh");
  MOTIONMAP_REQUIRE_SHARED("cmu/02_03.bvh");
  // 16 clips, about 12 000 frames: the points path's side of the dense limit.
  std::vector<std::string> paths;
  for (int i = 0; i < 8; ++i) {
    for (const std::string& p : cmu({"02_03.bvh", "64_08.bvh"})) paths.push_back(p);
  }
  ClipMapOptions options;
  options.embed.method = Method::Pca;
  expect_same_map(paths, options);
}

TEST(StreamMap, TheSamePoseNoteSpansTheClips) {
  // Two files of one still pose each: the same pose across the set gives the note once; a file
  // of another pose takes it away, although each clip alone is still.
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "motionmap-stream-map-test";
  std::filesystem::create_directories(dir);
  auto still = [&](const std::string& name, double angle) {
    const std::string path = (dir / name).string();
    std::ofstream out(path);
    out << "HIERARCHY\nROOT Hips\n{\n OFFSET 0 0 0\n CHANNELS 6 Xposition Yposition Zposition "
           "Zrotation Xrotation Yrotation\n JOINT Knee\n {\n  OFFSET 0 -1 0\n  CHANNELS 3 "
           "Zrotation Xrotation Yrotation\n  End Site\n  {\n   OFFSET 0 -1 0\n  }\n }\n}\n"
           "MOTION\nFrames: 6\nFrame Time: 0.1\n";
    for (int f = 0; f < 6; ++f) out << "0 1 0 0 0 0 " << angle << " 0 0\n";
    return path;
  };
  const std::string a = still("a.bvh", 10.0), b = still("b.bvh", 10.0), c = still("c.bvh", 40.0);
  ClipMapOptions options;
  options.embed.method = Method::Svd;
  const std::vector<std::string> same{a, b}, other{a, c};
  const StreamedMap one_pose = stream_map(same, {}, options);
  EXPECT_THAT(one_pose.map.features->notes,
              ::testing::Contains(features::same_pose_note(options.features.distance)));
  const StreamedMap two_poses = stream_map(other, {}, options);
  EXPECT_THAT(two_poses.map.features->notes,
              ::testing::Not(::testing::Contains(HasSubstr("the same pose"))));
  std::vector<Clip> clips{io::load_clip(a), io::load_clip(c)};
  EXPECT_EQ(two_poses.map.features->notes, map_clips(clips, options).features->notes);
  std::filesystem::remove_all(dir);
}

TEST(StreamMap, ReportsBothPassesAndCancelsInEach) {
  MOTIONMAP_REQUIRE_SHARED("cmu/64_08.bvh");
  MOTIONMAP_REQUIRE_SHARED("cmu/64_09.bvh");
  const std::vector<std::string> paths = cmu({"64_08.bvh", "64_09.bvh", "64_08.bvh"});
  ClipMapOptions options;
  options.embed.method = Method::Pca;
  std::vector<std::string> stages;
  double last = -1.0;
  bool backwards = false;
  const Control watch([&](double fraction, std::string_view stage) {
    // (The end is reported under the caller's stage name, empty here.)
    if (!stage.empty() && (stages.empty() || stages.back() != stage)) stages.emplace_back(stage);
    backwards = backwards || fraction < last;
    last = fraction;
  });
  stream_map(paths, {}, options, watch);
  EXPECT_THAT(stages, ::testing::ElementsAre("pass 1: features and XᵀX", "eigen",
                                             "pass 2: features and projection"));
  EXPECT_FALSE(backwards);
  EXPECT_EQ(last, 1.0);

  for (const std::string stage : {"pass 1: features and XᵀX", "pass 2: features and projection"}) {
    // Cancel at the stage's second poll: between its first and second clip.
    std::string current;
    int polls = 0;
    const Control cancel([&](double, std::string_view s) { current = s; },
                         [&] { return current == stage && ++polls >= 2; });
    EXPECT_THROW(stream_map(paths, {}, options, cancel), Cancelled) << stage;
    EXPECT_GE(polls, 2) << stage;
  }
}

TEST(StreamMap, BadInputIsAClearError) {
  MOTIONMAP_REQUIRE_SHARED("cmu/64_08.bvh");
  ClipMapOptions isomap;
  isomap.embed.method = Method::Isomap;
  const std::vector<std::string> one = cmu({"64_08.bvh"});
  EXPECT_THAT(test::error_message([&] { stream_map(one, {}, isomap); }),
              HasSubstr("only pca and svd"));
  ClipMapOptions common;
  common.embed.method = Method::Pca;
  common.features.joints = features::JointSelection::Common;
  EXPECT_THAT(test::error_message([&] { stream_map(one, {}, common); }),
              HasSubstr("--joints common"));
  ClipMapOptions metrics;
  metrics.embed.method = Method::Pca;
  metrics.metrics = true;
  EXPECT_THAT(why_not_streamed(metrics), HasSubstr("metrics"));

  // A missing file: an error naming it, or skipped with keep_going.
  ClipMapOptions pca;
  pca.embed.method = Method::Pca;
  const std::vector<std::string> with_missing{one.front(), "no/such/clip.bvh", one.front()};
  EXPECT_THAT(test::error_message([&] { stream_map(with_missing, {}, pca); }),
              HasSubstr("no/such/clip.bvh"));
  io::LoadClipsOptions keep_going;
  keep_going.keep_going = true;
  const StreamedMap skipped = stream_map(with_missing, keep_going, pca);
  EXPECT_EQ(skipped.clips.size(), 2u);
  ASSERT_EQ(skipped.failures.size(), 1u);
  EXPECT_THAT(skipped.failures.front(), HasSubstr("no/such/clip.bvh"));
  EXPECT_EQ(skipped.map.features->segment_starts.size(), 2u);

  // Another skeleton: named, as map_clips names it.
  const std::string other = test::shared_file("other/facebookresearch_sinusoidal.bvh");
  if (std::filesystem::exists(other)) {
    const std::vector<std::string> mixed{one.front(), other};
    EXPECT_THAT(test::error_message([&] { stream_map(mixed, {}, pca); }),
                HasSubstr("its joint hierarchy differs from"));
  }
}

TEST(StreamMap, AFileChangedBetweenThePassesIsAnError) {
  // With io::LoadOptions::sha256 (`map --save --stream`) the clips carry the SHA-256 of pass 1,
  // and a file whose bytes differ in pass 2 is refused, though its frames are as many.
  MOTIONMAP_REQUIRE_SHARED("cmu/64_08.bvh");
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("motionmap_stream_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "take.bvh").string();
  std::filesystem::copy_file(test::shared_file("cmu/64_08.bvh"), path,
                             std::filesystem::copy_options::overwrite_existing);
  const std::vector<std::string> paths{path};
  ClipMapOptions pca;
  pca.embed.method = Method::Pca;
  io::LoadClipsOptions hashed;
  hashed.load.sha256 = true;
  const std::string before = sha256_file(path);
  EXPECT_EQ(stream_map(paths, hashed, pca).clips.front().sha256, before);
  // A blank line appended between the passes: the same frames, other bytes.
  const Control touch([&](double, std::string_view stage) {
    if (stage == "eigen") std::ofstream(path, std::ios::app) << "\n";
  });
  EXPECT_THAT(test::error_message([&] { stream_map(paths, hashed, pca, touch); }),
              HasSubstr(path + ": error: the file changed while it was being mapped"));
  EXPECT_NE(sha256_file(path), before);
  std::filesystem::remove_all(dir);
}

TEST(StreamMap, StreamsByDefaultWhenTheFilesWouldNotFit) {
  MOTIONMAP_REQUIRE_SHARED("cmu/64_08.bvh");
  const std::vector<std::string> one = cmu({"64_08.bvh"});
  const std::vector<std::string> two = cmu({"64_08.bvh", "64_08.bvh"});
  const double bytes = double(std::filesystem::file_size(one.front()));
  EXPECT_EQ(estimate_load_bytes(one), kLoadBytesPerFileByte * bytes);
  EXPECT_EQ(estimate_load_bytes(two), 2.0 * kLoadBytesPerFileByte * bytes);
  const std::vector<std::string> missing{"no/such/clip.bvh"};
  EXPECT_EQ(estimate_load_bytes(missing), 0.0);

  // Streamed by default exactly when pca or svd would not fit.
  ClipMapOptions pca;
  pca.embed.method = Method::Pca;
  const auto need = static_cast<std::int64_t>(estimate_load_bytes(two));
  EXPECT_TRUE(streams_by_default(pca, two, need - 1));
  EXPECT_FALSE(streams_by_default(pca, two, need));
  EXPECT_FALSE(streams_by_default(pca, two, std::nullopt));
  ClipMapOptions isomap;
  isomap.embed.method = Method::Isomap;
  EXPECT_FALSE(streams_by_default(isomap, two, need - 1));
  pca.metrics = true;
  EXPECT_FALSE(streams_by_default(pca, two, need - 1));
}

}  // namespace
}  // namespace motionmap::pipeline
