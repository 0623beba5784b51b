// Map files: write → read gives the same map bit for bit (every MapModel field, the options, the
// clips); real maps of every method and path placed back on themselves; and every kind of bad
// file refused with an error naming the file and what was expected. Bad files are made from good
// ones with the HDF5 C API directly (an attribute changed, a dataset removed or replaced).
#include "motionmap/mapfile/map_file.h"

#include <hdf5.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "motionmap/core/sha256.h"
#include "motionmap/features/joint_match.h"
#include "motionmap/io/bvh.h"
#include "motionmap/io/load.h"
#include "motionmap/mapfile/detail/hdf5.h"
#include "motionmap/sample/sample_clip.h"
#include "support/error_message.h"
#include "support/map_edit.h"
#include "support/small_clip.h"

namespace motionmap::mapfile {
namespace {

using embed::Method;
using test::Edit;

// A fresh folder for one test's files, removed afterwards.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    m_path = std::filesystem::temp_directory_path() /
             ("motionmap-mapfile-" + std::to_string(::getpid()) + "-" + info->name());
    std::filesystem::remove_all(m_path);
    std::filesystem::create_directories(m_path);
  }
  ~TempDir() { std::filesystem::remove_all(m_path); }
  std::string file(const std::string& name) const { return (m_path / name).string(); }

 private:
  std::filesystem::path m_path;
};

bool same_bits(const double* a, const double* b, Eigen::Index n) {
  return n == 0 || std::memcmp(a, b, sizeof(double) * std::size_t(n)) == 0;
}

template <class A, class B>
::testing::AssertionResult bit_equal(const A& a, const B& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) {
    return ::testing::AssertionFailure()
           << "shape " << a.rows() << "×" << a.cols() << " vs " << b.rows() << "×" << b.cols();
  }
  // Compare in one storage order.
  const Eigen::MatrixXd x = a, y = b;
  if (!same_bits(x.data(), y.data(), x.size())) {
    return ::testing::AssertionFailure() << "values differ";
  }
  return ::testing::AssertionSuccess();
}

void expect_same_model(const embed::MapModel& a, const embed::MapModel& b) {
  EXPECT_EQ(a.method, b.method);
  EXPECT_EQ(a.dimensions, b.dimensions);
  EXPECT_TRUE(bit_equal(a.coordinates, b.coordinates));
  EXPECT_TRUE(bit_equal(a.mean, b.mean));
  EXPECT_TRUE(bit_equal(a.scale, b.scale));
  EXPECT_TRUE(bit_equal(a.axes, b.axes));
  EXPECT_TRUE(bit_equal(a.points, b.points));
  EXPECT_EQ(a.metric, b.metric);
  EXPECT_EQ(a.points_are_landmarks, b.points_are_landmarks);
  EXPECT_EQ(a.k, b.k);
  ASSERT_EQ(a.landmarks.has_value(), b.landmarks.has_value());
  if (a.landmarks) {
    EXPECT_EQ(a.landmarks->frames, b.landmarks->frames);
    EXPECT_TRUE(bit_equal(a.landmarks->projection, b.landmarks->projection));
    EXPECT_TRUE(bit_equal(a.landmarks->mean_squared, b.landmarks->mean_squared));
    EXPECT_TRUE(bit_equal(a.landmarks->offset, b.landmarks->offset));
    EXPECT_TRUE(bit_equal(a.landmarks->geodesic, b.landmarks->geodesic));
  }
  EXPECT_EQ(a.graph.offsets, b.graph.offsets);
  EXPECT_EQ(a.graph.targets, b.graph.targets);
  EXPECT_EQ(a.graph.weights.size(), b.graph.weights.size());
  EXPECT_TRUE(same_bits(a.graph.weights.data(), b.graph.weights.data(),
                        Eigen::Index(std::min(a.graph.weights.size(), b.graph.weights.size()))));
  EXPECT_TRUE(std::memcmp(&a.heat, &b.heat, sizeof a.heat) == 0);
  EXPECT_TRUE(bit_equal(a.eigenvalues, b.eigenvalues));
  EXPECT_TRUE(bit_equal(a.features, b.features));
  EXPECT_TRUE(std::memcmp(&a.reg, &b.reg, sizeof a.reg) == 0);
}

void expect_same_file(const MapFile& a, const MapFile& b) {
  ASSERT_EQ(a.clips.size(), b.clips.size());
  for (std::size_t c = 0; c < a.clips.size(); ++c) {
    EXPECT_EQ(a.clips[c].path, b.clips[c].path);
    EXPECT_EQ(a.clips[c].sha256, b.clips[c].sha256);
    EXPECT_EQ(a.clips[c].frames, b.clips[c].frames);
    EXPECT_EQ(a.clips[c].frame_time, b.clips[c].frame_time);
    EXPECT_EQ(a.clips[c].first_sample, b.clips[c].first_sample);
    EXPECT_EQ(a.clips[c].samples, b.clips[c].samples);
  }
  EXPECT_EQ(a.clip_of, b.clip_of);
  EXPECT_EQ(a.frame_of, b.frame_of);
  ASSERT_EQ(a.blend.has_value(), b.blend.has_value());
  if (a.blend) {
    EXPECT_EQ(a.blend->motion_root, b.blend->motion_root);
    EXPECT_EQ(a.blend->moving, b.blend->moving);
  }
  EXPECT_EQ(a.parameters, b.parameters);
  const auto &fa = a.options.features, &fb = b.options.features;
  EXPECT_EQ(fa.features, fb.features);
  EXPECT_EQ(fa.distance, fb.distance);
  EXPECT_EQ(fa.up, fb.up);
  EXPECT_EQ(fa.exclude, fb.exclude);
  EXPECT_EQ(fa.first_frame, fb.first_frame);
  EXPECT_EQ(fa.end_frame, fb.end_frame);
  EXPECT_EQ(fa.stride, fb.stride);
  EXPECT_EQ(fa.keep_first, fb.keep_first);
  EXPECT_EQ(fa.joints, fb.joints);
  const auto &ea = a.options.embed, &eb = b.options.embed;
  EXPECT_EQ(ea.method, eb.method);
  EXPECT_EQ(ea.dimensions, eb.dimensions);
  EXPECT_EQ(ea.k, eb.k);
  EXPECT_EQ(ea.heat, eb.heat);
  EXPECT_EQ(ea.reg, eb.reg);
  EXPECT_EQ(ea.standardize, eb.standardize);
  EXPECT_EQ(ea.strict, eb.strict);
  EXPECT_EQ(ea.landmarks, eb.landmarks);
  EXPECT_EQ(ea.search, eb.search);
  EXPECT_EQ(a.options.path, b.options.path);
  EXPECT_EQ(a.options.dense_limit, b.options.dense_limit);
  EXPECT_EQ(a.dense, b.dense);
  EXPECT_EQ(a.k_used, b.k_used);
  EXPECT_EQ(a.heat_used, b.heat_used);
  EXPECT_EQ(a.landmarks_used, b.landmarks_used);
  EXPECT_EQ(a.neighbor_search, b.neighbor_search);
  EXPECT_EQ(a.graph_components, b.graph_components);
  EXPECT_EQ(a.connecting_edges, b.connecting_edges);
  EXPECT_EQ(a.notes, b.notes);
  EXPECT_EQ(a.warnings, b.warnings);
  EXPECT_EQ(a.skeleton.names, b.skeleton.names);
  EXPECT_EQ(a.skeleton.parents, b.skeleton.parents);
  EXPECT_EQ(a.skeleton.end_sites, b.skeleton.end_sites);
  EXPECT_EQ(a.joints, b.joints);
  EXPECT_EQ(a.shared_joints, b.shared_joints);
  EXPECT_EQ(a.x_columns, b.x_columns);
  EXPECT_EQ(a.point_columns, b.point_columns);
  EXPECT_TRUE(bit_equal(a.coordinates, b.coordinates));
  expect_same_model(a.model, b.model);
}

// A map file with every field filled with seeded random values, consistent as the reader
// checks: an isomap map (points, landmarks with geodesics, a graph) that also carries every other
// method's fields, so that one round trip covers them all.
MapFile synthetic_file(int n = 40, int dims = 3) {
  std::mt19937_64 random(7);
  std::normal_distribution<double> normal;
  auto matrix = [&](Eigen::Index r, Eigen::Index c) {
    Eigen::MatrixXd m(r, c);
    for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] = normal(random) * 1e3;
    return m;
  };
  MapFile f;
  f.clips = {{"takes/a.bvh", std::string(64, 'a'), n, 1.0 / 120, 0, n / 2},
             {"/abs/b ü.bvh", sha256_hex("b"), n + 5, 1.0 / 30, n / 2, n - n / 2}};
  for (int i = 0; i < n; ++i) {
    f.clip_of.push_back(i < n / 2 ? 0 : 1);
    f.frame_of.push_back(i < n / 2 ? i : i - n / 2 + 3);
  }
  f.parameters = "method=isomap dims=3 k=7 features=quat distance=pointcloud up=y";
  f.options.features.features = features::FeatureKind::Positions;
  f.options.features.distance = features::DistanceKind::Geodesic;
  f.options.features.up = Axis::Z;
  f.options.features.exclude = ".*(Thumb|Finger).*";
  f.options.features.first_frame = 1;
  f.options.features.end_frame = 200;
  f.options.features.stride = 2;
  f.options.features.keep_first = true;
  f.options.features.joints = features::JointSelection::Common;
  f.options.embed.method = Method::Isomap;
  f.options.embed.dimensions = dims;
  f.options.embed.k = 7;
  f.options.embed.heat = 0.125;
  f.options.embed.reg = 3e-4;
  f.options.embed.standardize = true;
  f.options.embed.strict = true;
  f.options.embed.landmarks = 12;
  f.options.embed.search = embed::EmbedOptions::Search::Exact;
  f.options.path = pipeline::MapPath::Landmarks;
  f.options.dense_limit = 5000;
  f.dense = false;
  f.k_used = 7;
  f.heat_used = 0.125;
  f.landmarks_used = 12;
  f.neighbor_search = "exact";
  f.graph_components = 2;
  f.connecting_edges = 1;
  f.notes = {"a.bvh: frame 0 looks like a bind pose (…): left out", "ünïcode"};
  f.warnings = {"the graph had 2 components"};
  f.skeleton = {{"Hips", "Spine", "Head"}, {-1, 0, 1}, {0, 0, 1}};
  f.blend = BlendRecord{0, {1, 2}};
  f.joints = {"Spine", "Head"};
  f.shared_joints = {"Hips", "Spine", "Head"};
  f.x_columns = 8;
  f.point_columns = 9;
  f.coordinates = matrix(n, dims);

  embed::MapModel& m = f.model;
  m.method = Method::Isomap;
  m.dimensions = dims;
  m.coordinates = f.coordinates;
  m.mean = matrix(1, 8);
  m.scale = matrix(1, 8).cwiseAbs();
  m.axes = matrix(8, dims);
  m.points = matrix(n, 9);
  m.metric = Metric::QuaternionAngles;
  m.k = 7;
  embed::LandmarkFit fit;
  for (int l = 0; l < 12; ++l) fit.frames.push_back((l * 7) % n);
  fit.projection = matrix(dims, 12);
  fit.mean_squared = matrix(12, 1);
  fit.offset = matrix(dims, 1);
  fit.geodesic = matrix(12, n).cwiseAbs();
  m.landmarks = fit;
  // A ring: i – i±1.
  for (int i = 0; i < n; ++i) {
    m.graph.offsets.push_back(int(m.graph.targets.size()));
    for (const int j : {(i + n - 1) % n, (i + 1) % n}) {
      m.graph.targets.push_back(j);
      m.graph.weights.push_back(std::abs(normal(random)));
    }
  }
  m.graph.offsets.push_back(int(m.graph.targets.size()));
  m.heat = 0.125;
  m.eigenvalues = matrix(dims, 1).cwiseAbs() / 1e4;
  m.features = matrix(n, 8);
  m.reg = 3e-4;
  return f;
}

TEST(MapFile, WriteThenReadIsBitExact) {
  const TempDir dir;
  const std::string path = dir.file("all.mmap.h5");
  const MapFile written = synthetic_file();
  write_map_file(path, written);
  const MapFile read = read_map_file(path);
  EXPECT_EQ(read.path, path);
  expect_same_file(written, read);

  // Large ones too (the integer datasets chunked and compressed).
  const MapFile big = synthetic_file(9000, 2);
  write_map_file(path, big);
  expect_same_file(big, read_map_file(path));
}

TEST(MapFile, ModelCoordinatesThatDifferFromTheMapAreKeptApart) {
  const TempDir dir;
  MapFile f = synthetic_file();
  f.model.coordinates(3, 1) += 1.0;
  write_map_file(dir.file("m.mmap.h5"), f);
  expect_same_model(f.model, read_map_file(dir.file("m.mmap.h5")).model);
}

TEST(MapFile, UnusedFieldsAreLeftOutAndReadBackEmpty) {
  const TempDir dir;
  MapFile f = synthetic_file();
  f.options.embed.method = f.model.method = Method::Svd;
  f.options.embed.heat.reset();
  f.options.features.joints = features::JointSelection::All;
  f.shared_joints.clear();
  f.model.mean.resize(0);
  f.model.scale.resize(0);
  f.model.points.resize(0, 0);
  f.model.landmarks.reset();
  f.model.graph = {};
  f.model.eigenvalues.resize(0);
  f.model.features.resize(0, 0);
  f.notes.clear();
  f.warnings.clear();
  write_map_file(dir.file("svd.mmap.h5"), f);
  const MapFile read = read_map_file(dir.file("svd.mmap.h5"));
  expect_same_file(f, read);
  EXPECT_FALSE(read.options.embed.heat.has_value());
}

// ---- Real maps ---------------------------------------------------------------------------------

// The sample swing written as BVH (map files hash the clip files) and loaded back.
Clip swing_clip(const TempDir& dir, double seconds = 1.5) {
  sample::SampleOptions options;
  options.fps = 60;
  options.seconds = seconds;
  const Clip sample = sample::make_sample_clip(sample::SampleKind::Swing, options);
  const std::string path = dir.file("swing.bvh");
  io::write_bvh(io::from_motion(sample.skeleton, sample.motion), path);
  return io::load_clip(path);
}

struct Case {
  Method method;
  bool landmarks;    // the points path
  double tolerance;  // for placing the map's own frames, relative to the largest coordinate
                     // (0: bit for bit)
};

TEST(MapFile, RealMapsRoundTripAndTheirFramesPlaceBackOnThemselves) {
  const TempDir dir;
  const Clip clip = swing_clip(dir);
  const std::vector<Clip> clips{clip};
  // A frame equal to a sample lands on it (mds, isomap, le, lle; a landmark mds map by the
  // same triangulation the map used): exactly. pca and svd recompute the projection from the
  // saved axes: equal to rounding (measured ≤ 5e-14 here).
  const Case cases[] = {{Method::Pca, false, 1e-10},
                        {Method::Svd, false, 1e-10},
                        {Method::Mds, false, 0},
                        {Method::Mds, true, 0},
                        {Method::Isomap, false, 0},
                        {Method::Isomap, true, 0},
                        {Method::LaplacianEigenmap, false, 0},
                        {Method::LaplacianEigenmap, true, 0},
                        {Method::Lle, false, 0},
                        {Method::Lle, true, 0}};
  for (const Case& c : cases) {
    SCOPED_TRACE(std::string(embed::method_name(c.method)) +
                 (c.landmarks ? " landmarks" : " dense"));
    pipeline::ClipMapOptions options;
    options.embed.method = c.method;
    options.embed.k = 8;
    if (c.landmarks) {
      options.path = pipeline::MapPath::Landmarks;
      options.embed.landmarks = 0;
    }
    const pipeline::ClipMap map = pipeline::map_clips(clips, options);
    const MapFile made = make_map_file(clips, map, options);
    EXPECT_EQ(made.clips.front().sha256, sha256_file(clip.path));
    EXPECT_EQ(made.parameters, pipeline::describe_parameters(map.embedding, options));
    const std::string path = dir.file("m.mmap.h5");
    write_map_file(path, made);
    const MapFile read = read_map_file(path);
    expect_same_file(made, read);
    // What the CSV writer is given describes the map as it was.
    EXPECT_EQ(
        pipeline::describe_parameters(embedding_for_csv(read, read.coordinates), read.options),
        made.parameters);

    const Placement placed = place_clips(clips, read);
    EXPECT_EQ(placed.features.frame_of, map.features->frame_of);
    const Eigen::MatrixXd& want = map.embedding.coordinates;
    ASSERT_EQ(placed.coordinates.rows(), want.rows());
    if (c.tolerance == 0) {
      EXPECT_TRUE(bit_equal(placed.coordinates, want))
          << "largest difference " << (placed.coordinates - want).cwiseAbs().maxCoeff();
    } else {
      EXPECT_LE((placed.coordinates - want).cwiseAbs().maxCoeff(),
                c.tolerance * want.cwiseAbs().maxCoeff());
    }
  }
}

TEST(MapFile, PlacingFramesDoesNotDependOnTheOtherFramesPlaced) {
  const TempDir dir;
  const std::vector<Clip> clips{swing_clip(dir)};
  pipeline::ClipMapOptions options;
  options.embed.method = Method::Isomap;
  const MapFile file = make_map_file(clips, pipeline::map_clips(clips, options), options);
  const Placement all = place_clips(clips, file);
  PlaceOptions some;
  some.first_frame = 20;
  some.end_frame = 40;
  some.stride = 3;
  const Placement part = place_clips(clips, file, some);
  ASSERT_GT(part.coordinates.rows(), 0);
  for (int i = 0; i < part.coordinates.rows(); ++i) {
    const int row = int(std::find(all.features.frame_of.begin(), all.features.frame_of.end(),
                                  part.features.frame_of[i]) -
                        all.features.frame_of.begin());
    EXPECT_TRUE(bit_equal(part.coordinates.row(i), all.coordinates.row(row))) << "frame " << i;
  }
}

TEST(MapFile, AClipOfAnotherSkeletonIsRefusedNamingWhatDiffers) {
  const TempDir dir;
  const std::vector<Clip> clips{swing_clip(dir)};
  pipeline::ClipMapOptions options;
  options.embed.method = Method::Pca;
  MapFile file = make_map_file(clips, pipeline::map_clips(clips, options), options);
  file.path = "lib.mmap.h5";
  const std::vector<Clip> other{test::smooth_clip(30, "small.bvh")};
  EXPECT_EQ(test::error_message<ParameterError>([&] { place_clips(other, file); }),
            "small.bvh: cannot be placed on lib.mmap.h5: its joint hierarchy differs from the "
            "map's (it has 4 joints, swing.bvh 31; the first that differs is joint 1: 'Spine' "
            "(parent 'Hips') where swing.bvh has 'LHipJoint' (parent 'Hips')); a clip placed on "
            "a map must have the skeleton of the map's clips (joint names, parents and End Sites)");
}

TEST(MapFile, AClipWithOtherEndSitesIsRefused) {
  // The same joint names and parents, but a joint without its End Site: the point clouds would
  // not line up.
  const TempDir dir;
  const std::vector<Clip> clips{swing_clip(dir)};
  pipeline::ClipMapOptions options;
  options.embed.method = Method::Isomap;
  const MapFile file = make_map_file(clips, pipeline::map_clips(clips, options), options);
  Clip other = clips.front();
  other.path = "other.bvh";
  const int head = other.skeleton.find("Head");
  ASSERT_GE(head, 0);
  ASSERT_FALSE(other.skeleton.joints[std::size_t(head)].end_sites.empty());
  other.skeleton.joints[std::size_t(head)].end_sites.clear();
  const std::vector<Clip> bad{other};
  const std::string message = test::error_message<ParameterError>([&] { place_clips(bad, file); });
  EXPECT_EQ(message.rfind("other.bvh: cannot be placed on the map: its joint hierarchy differs", 0),
            0u)
      << message;
  EXPECT_NE(message.find("End Site"), std::string::npos) << message;
}

TEST(MapFile, AJointsCommonMapPlacesClipsThatHaveItsSharedJoints) {
  const TempDir dir;
  const Clip swing = swing_clip(dir);
  // The swing's skeleton without its hands: mapped together, the two share the rest.
  Clip small = test::smooth_clip(40, dir.file("small.bvh"));
  const std::vector<Clip> clips{swing, small};
  pipeline::ClipMapOptions options;
  options.embed.method = Method::Mds;
  options.features.joints = features::JointSelection::Common;
  // small.bvh is not on disk: hash a copy.
  io::write_bvh(io::from_motion(small.skeleton, small.motion), small.path);
  const pipeline::ClipMap map = pipeline::map_clips(clips, options);
  const MapFile file = make_map_file(clips, map, options);
  EXPECT_EQ(file.shared_joints, features::common_joint_names(clips));
  // The swing alone, placed by the shared joints only, lands where the map put it.
  const std::vector<Clip> again{swing};
  const Placement placed = place_clips(again, file);
  const int n = file.clips.front().samples;
  EXPECT_LE((placed.coordinates - map.embedding.coordinates.topRows(n)).norm(),
            1e-6 * map.embedding.coordinates.norm());
  // A clip without one of them cannot be placed.
  Clip lacking = swing;
  lacking.path = "lacking.bvh";
  lacking.skeleton.joints[lacking.skeleton.find("Spine")].name = "Spine0";
  const std::vector<Clip> bad{lacking};
  EXPECT_EQ(test::error_message<ParameterError>([&] { place_clips(bad, file); }),
            "lacking.bvh: cannot be placed on the map: it lacks 1 of the " +
                std::to_string(file.shared_joints.size()) +
                " joints the map compares by (--joints common): Spine");
}

// ---- Bad files ---------------------------------------------------------------------------------

// Matrices are read a slab of rows at a time and checked in parallel blocks: still bit for bit,
// from compressed datasets too, and the first non-finite value in row-major order is the one named.
TEST(MapFile, LargeMatricesReadBackWholeAndTheirFirstNonFiniteValueIsNamed) {
  const TempDir dir;
  const std::string path = dir.file("big.mmap.h5");
  const MapFile big = synthetic_file(20000, 2);
  write_map_file(path, big);
  {
    Edit e(path);
    e.compress("/model/points");
    e.compress("/model/landmarks/geodesic");
  }
  expect_same_file(big, read_map_file(path));

  write_map_file(path, big);
  {
    Edit e(path);
    e.set("/model/points", 19000, 1, INFINITY);
    e.set("/model/points", 15000, 3, NAN);
  }
  EXPECT_EQ(test::error_message([&] { read_map_file(path); }),
            path + ": error: /model/points holds a non-finite value (nan) at row 15000, column 3");
  write_map_file(path, big);
  {
    Edit e(path);
    e.set("/model/landmarks/geodesic", 7, 100, NAN);
    e.set("/model/landmarks/geodesic", 5, 19999, -INFINITY);
  }
  EXPECT_EQ(test::error_message([&] { read_map_file(path); }),
            path +
                ": error: /model/landmarks/geodesic holds a non-finite value (-inf) at row 5, "
                "column 19999");
}

TEST(MapFile, BadFilesAreRefusedWithWhatWasExpected) {
  const TempDir dir;
  const MapFile good = synthetic_file(40, 2);
  int count = 0;
  // Each case: a fresh good file, one edit, the error expected (after "path: error: ").
  auto refused = [&](const std::function<void(Edit&)>& edit) {
    const std::string path = dir.file("bad" + std::to_string(count++) + ".mmap.h5");
    write_map_file(path, good);
    {
      Edit e(path);
      edit(e);
    }
    const std::string message = test::error_message([&] { read_map_file(path); });
    const std::string prefix = path + ": error: ";
    EXPECT_EQ(message.rfind(prefix, 0), 0u) << message;
    return message.substr(std::min(message.size(), prefix.size()));
  };

  EXPECT_EQ(refused([](Edit& e) { e.text_attribute("/", "format", "other-format"); }),
            "not a MotionMap map file: its format is 'other-format', expected 'motionmap-map'");
  EXPECT_EQ(refused([](Edit& e) { e.int_attribute("/", "format_version", 4); }),
            "map file layout version 4 is newer than this MotionMap reads (3); read it with a "
            "newer MotionMap");
  EXPECT_EQ(refused([](Edit& e) { e.int_attribute("/", "format_version", 0); }),
            "unknown map file layout version 0 (this MotionMap reads versions 1 to 3)");
  EXPECT_EQ(refused([](Edit& e) { e.text_attribute("/", "format_version", "1"); }),
            "attribute format_version of / is not an integer");
  EXPECT_EQ(refused([](Edit& e) { e.int_attribute("/blend", "motion_root", 3); }),
            "attribute motion_root of /blend is 3, expected the joint carrying the root motion in "
            "[0, 2]");
  EXPECT_EQ(refused([](Edit& e) { e.replace("/blend/moving_joints", 2, 0, H5T_STD_I32LE, 1); }),
            "/blend/moving_joints is not increasing or names the motion root 0");
  EXPECT_EQ(refused([](Edit& e) { e.remove("/coordinates"); }),
            "missing dataset /coordinates (#samples by dims, float64)");
  EXPECT_EQ(refused([](Edit& e) { e.replace("/coordinates", 40, 3, H5T_IEEE_F64LE, 0.5); }),
            "/coordinates has shape 40×3, expected 40×2 (#samples by dims)");
  EXPECT_EQ(refused([](Edit& e) { e.replace("/coordinates", 40, 2, H5T_STD_I32LE, 1); }),
            "/coordinates holds int32 values, expected float64 (#samples by dims)");
  EXPECT_EQ(refused([](Edit& e) { e.replace("/coordinates", 40, 2, H5T_IEEE_F32LE, 1); }),
            "/coordinates holds float32 values, expected float64 (#samples by dims)");
  EXPECT_EQ(refused([](Edit& e) { e.replace("/coordinates", 40, 2, H5T_IEEE_F64LE, NAN); }),
            "/coordinates holds a non-finite value (nan) at row 0, column 0");
  // Finite but beyond any map's values: squared distances of it overflow (found by
  // fuzz_mapfile_edits: placing on a model point of -1e300 read out of range).
  EXPECT_EQ(refused([](Edit& e) { e.set("/model/points", 3, 1, -1e300); }),
            "/model/points holds -1e+300 at row 3, column 1: no value of a map is that large (at "
            "most 1e100 in magnitude)");
  EXPECT_EQ(refused([](Edit& e) { e.replace("/samples/clip", 40, 0, H5T_STD_I32LE, 5); }),
            "/samples/clip holds 5 at index 0, expected a clip index in [0, 2)");
  EXPECT_EQ(refused([](Edit& e) { e.replace("/samples/frame", 39, 0, H5T_STD_I32LE, 0); }),
            "/samples/frame has shape 39, expected 40 (a frame index)");
  EXPECT_EQ(refused([](Edit& e) { e.remove("/model/landmarks"); }),
            "missing dataset /model/landmarks (the isomap map places new frames with it)");
  EXPECT_EQ(refused([](Edit& e) { e.remove("/model/points"); }),
            "missing dataset /model/points (the isomap map places new frames with it)");
  EXPECT_EQ(refused([](Edit& e) { e.replace("/model/points", 40, 8, H5T_IEEE_F64LE, 0); }),
            "/model/points has shape 40×8, expected 40×9 (#model samples by #point values)");
  EXPECT_EQ(
      refused([](Edit& e) { e.replace("/model/landmarks/frames", 12, 0, H5T_STD_I32LE, 40); }),
      "/model/landmarks/frames holds 40 at index 0, expected a model sample index in [0, 40)");
  EXPECT_EQ(refused([](Edit& e) { e.replace("/model/graph/offsets", 41, 0, H5T_STD_I32LE, 0); }),
            "/model/graph/offsets is not a CSR offset list (from 0, never decreasing, to the 80 "
            "targets)");
  EXPECT_EQ(refused([](Edit& e) { e.text_attribute("/parameters", "method", "tsne"); }),
            "attribute method of /parameters is 'tsne', expected a method (pca, svd, mds, "
            "isomap, le, lle, umap, gplvm)");
  EXPECT_EQ(refused([](Edit& e) { e.int_attribute("/model", "k", 0); }),
            "attribute k of /model is 0, expected 1 to 40 for the isomap map");
  EXPECT_EQ(refused([](Edit& e) { e.remove("/parameters"); }),
            "missing group /parameters (the effective parameters)");
}

// `map --save` records the SHA-256 of the bytes it mapped (io::LoadOptions::sha256), not of the
// file as it is by the time the record is made; a clip loaded without a hash gets the file's.
TEST(MapFile, TheHashRecordedIsOfTheBytesMapped) {
  const TempDir dir;
  const std::string path = swing_clip(dir).path;
  const std::string mapped_hash = sha256_file(path);
  io::LoadOptions load;
  load.sha256 = true;
  const std::vector<Clip> hashed{io::load_clip(path, load)}, plain{io::load_clip(path)};
  EXPECT_EQ(hashed[0].sha256, mapped_hash);
  pipeline::ClipMapOptions options;
  options.embed.method = Method::Pca;
  const pipeline::ClipMap map = pipeline::map_clips(hashed, options);
  swing_clip(dir, 2.0);  // the file is another swing now
  const std::string now_hash = sha256_file(path);
  ASSERT_NE(now_hash, mapped_hash);
  EXPECT_EQ(make_map_file(hashed, map, options).clips[0].sha256, mapped_hash);
  EXPECT_EQ(placed_clips(hashed, place_clips(hashed, make_map_file(hashed, map, options)))[0]
                .record.sha256,
            mapped_hash);
  EXPECT_EQ(recorded_sha256(plain[0]), now_hash);
}

// A map of clips placed on a saved map (`map --onto fitted --save`, Dask's map_library): the
// placed frames are its rows, bit for bit, and placing on it is placing on the fitted map.
TEST(MapFile, AMapOfPlacedClipsKeepsTheFittedModel) {
  const TempDir dir;
  const std::vector<Clip> clips{swing_clip(dir)};
  const int frames = clips.front().motion.num_frames;
  const Case cases[] = {{Method::Pca, false, 0},
                        {Method::Mds, true, 0},
                        {Method::Isomap, false, 0},
                        {Method::Isomap, true, 0},
                        {Method::LaplacianEigenmap, false, 0},
                        {Method::Lle, true, 0}};
  for (const Case& c : cases) {
    SCOPED_TRACE(std::string(embed::method_name(c.method)) +
                 (c.landmarks ? " landmarks" : " dense"));
    // Fitted on the first half of the swing; the whole swing placed on it.
    pipeline::ClipMapOptions options;
    options.embed.method = c.method;
    options.embed.k = 8;
    options.features.end_frame = frames / 2;
    if (c.landmarks) options.path = pipeline::MapPath::Landmarks;
    const MapFile fitted = make_map_file(clips, pipeline::map_clips(clips, options), options);
    const Placement placed = place_clips(clips, fitted);
    ASSERT_GT(placed.coordinates.rows(), fitted.num_samples());
    const std::vector<PlacedClip> records = placed_clips(clips, placed);
    ASSERT_EQ(records.size(), 1u);
    EXPECT_EQ(records[0].record.sha256, sha256_file(clips[0].path));
    EXPECT_EQ(records[0].frames, placed.features.frame_of);

    const std::string path = dir.file("placed.mmap.h5");
    write_map_file(path, placed_map_file(fitted, records, "fitted.mmap.h5"));
    const MapFile read = read_map_file(path);
    EXPECT_TRUE(bit_equal(read.coordinates, placed.coordinates));
    EXPECT_EQ(read.frame_of, placed.features.frame_of);
    EXPECT_EQ(read.clips[0].samples, placed.coordinates.rows());
    EXPECT_EQ(read.parameters, fitted.parameters);
    EXPECT_TRUE(bit_equal(read.model.coordinates, fitted.model.coordinates));
    EXPECT_NE(read.notes.back().find("placed on the " + std::string(embed::method_name(c.method)) +
                                     " map fitted.mmap.h5 without refitting it (fitted on " +
                                     std::to_string(fitted.num_samples()) + " frames"),
              std::string::npos)
        << read.notes.back();
    // Placing on it is placing on the fitted map.
    EXPECT_TRUE(bit_equal(place_clips(clips, read).coordinates, placed.coordinates));
  }
  // Layout 2: a reader of layout 1 refuses it as newer instead of misreading the model.
  pipeline::ClipMapOptions options;
  options.features.end_frame = frames / 2;
  const MapFile fitted = make_map_file(clips, pipeline::map_clips(clips, options), options);
  const std::string path = dir.file("v2.mmap.h5");
  write_map_file(path,
                 placed_map_file(fitted, placed_clips(clips, place_clips(clips, fitted)), "f"));
  EXPECT_EQ(read_map_file(path).model.coordinates.rows(), fitted.num_samples());
  {
    Edit e(path);
    e.int_attribute("/", "format_version", 1);
  }
  EXPECT_NE(test::error_message([&] { read_map_file(path); }).find("/model/coordinates has shape"),
            std::string::npos);
  // A map of the fitted map's own shape stays layout 1.
  const std::string v1 = dir.file("v1.mmap.h5");
  write_map_file(v1, fitted);
  EXPECT_EQ(read_map_file(v1).num_samples(), fitted.num_samples());

  EXPECT_THROW(placed_map_file(fitted, {}, "f"), ParameterError);
  PlacedClip wrong = placed_clips(clips, place_clips(clips, fitted)).front();
  wrong.frames.pop_back();
  EXPECT_THROW(placed_map_file(fitted, {&wrong, 1}, "f"), ParameterError);
  MapFile without_model = fitted;
  without_model.model = {};
  EXPECT_THROW(placed_map_file(without_model, placed_clips(clips, place_clips(clips, fitted)), "f"),
               ParameterError);
}

TEST(MapFile, StringsAreReadInEveryEncodingHdf5Writes) {
  // Variable-length UTF-8 (what MotionMap wrote before layout 3, and h5py writes), variable-length
  // ASCII and fixed-length ASCII (MATLAB's h5create/h5writeatt) all read back from a file of
  // layout 1.
  const TempDir dir;
  const MapFile good = synthetic_file();
  const std::string path = dir.file("strings.mmap.h5");
  write_map_file(path, good);
  {
    Edit e(path);
    e.int_attribute("/", "format_version", 1);
    e.variable_text_attribute("/parameters", "description", "ascii line");
    e.fixed_strings("/clips/path", {"a.bvh", "folder/b.bvh"});
  }
  const MapFile read = read_map_file(path);
  EXPECT_EQ(read.parameters, "ascii line");
  ASSERT_EQ(read.clips.size(), 2u);
  EXPECT_EQ(read.clips[0].path, "a.bvh");
  EXPECT_EQ(read.clips[1].path, "folder/b.bvh");
  EXPECT_EQ(read.notes, good.notes);  // UTF-8
}

TEST(MapFile, FilesThatAreNotMapFilesAreRefused) {
  const TempDir dir;
  EXPECT_EQ(test::error_message([&] { read_map_file(dir.file("none.mmap.h5")); }),
            dir.file("none.mmap.h5") + ": error: cannot open: No such file or directory");
  const std::string text = dir.file("text.mmap.h5");
  std::ofstream(text) << "frame,x,y\n1,2,3\n";
  EXPECT_EQ(test::error_message([&] { read_map_file(text); }),
            text +
                ": error: not an HDF5 file (expected a MotionMap map file, as `motionmap map "
                "--save` writes)");
  // An HDF5 file of something else.
  const std::string other = dir.file("other.h5");
  const hid_t f = H5Fcreate(other.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  H5Fclose(f);
  EXPECT_EQ(test::error_message([&] { read_map_file(other); }),
            other +
                ": error: not a MotionMap map file: the root has no 'format' attribute "
                "(expected format = motionmap-map, as `motionmap map --save` writes)");
}

TEST(MapFile, AFailedWriteLeavesNoFile) {
  const TempDir dir;
  const std::string path = dir.file("no/such/folder/m.mmap.h5");
  const std::string message = test::error_message([&] { write_map_file(path, synthetic_file()); });
  EXPECT_EQ(message.rfind(path + ": error: cannot create the file", 0), 0u) << message;
  MapFile empty;
  EXPECT_EQ(test::error_message([&] { write_map_file(dir.file("e.mmap.h5"), empty); }),
            dir.file("e.mmap.h5") +
                ": error: cannot write an empty or inconsistent map (0 clips, 0 samples, 0 "
                "coordinates)");
  EXPECT_FALSE(std::filesystem::exists(dir.file("e.mmap.h5")));
}

// ---- Trusting a file: checksums, strings, indices (issue 22) ---------------------------------

// Whether `s` is valid UTF-8 (what every message must be).
bool valid_utf8(const std::string& s) {
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    const int extra = c < 0x80 ? 0 : c >= 0xf0 ? 3 : c >= 0xe0 ? 2 : c >= 0xc2 ? 1 : -1;
    if (extra < 0 || i + std::size_t(extra) >= s.size() + (extra == 0 ? 1 : 0)) return false;
    for (int k = 1; k <= extra; ++k) {
      if ((static_cast<unsigned char>(s[i + std::size_t(k)]) & 0xc0) != 0x80) return false;
    }
    i += std::size_t(extra) + 1;
  }
  return true;
}

// The error reading `path` gives, after "path: error: ", checked to be valid UTF-8.
std::string read_error(const std::string& path) {
  const std::string message = test::error_message([&] { read_map_file(path); });
  EXPECT_TRUE(valid_utf8(message)) << message;
  const std::string prefix = path + ": error: ";
  EXPECT_EQ(message.rfind(prefix, 0), 0u) << message;
  return message.substr(std::min(message.size(), prefix.size()));
}

TEST(MapFileTrust, LayoutThreeWritesNoVariableLengthStringsAndAChecksumOnEveryDataset) {
  const TempDir dir;
  const std::string path = dir.file("v3.mmap.h5");
  write_map_file(path, synthetic_file());
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  struct Seen {
    int datasets = 0, variable = 0, without_checksum = 0;
  } seen;
  H5Ovisit2(
      file, H5_INDEX_NAME, H5_ITER_NATIVE,
      [](hid_t f, const char* name, const H5O_info_t* info, void* out) -> herr_t {
        auto& s = *static_cast<Seen*>(out);
        if (info->type != H5O_TYPE_DATASET) return 0;
        ++s.datasets;
        const hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
        const hid_t type = H5Dget_type(d);
        if (H5Tis_variable_str(type) > 0) ++s.variable;
        if (H5Aexists(d, detail::kChecksumAttribute) <= 0) ++s.without_checksum;
        H5Tclose(type);
        H5Dclose(d);
        return 0;
      },
      &seen, H5O_INFO_BASIC);
  const hid_t format = H5Aopen(file, "format", H5P_DEFAULT);
  const hid_t type = H5Aget_type(format);
  EXPECT_EQ(H5Tis_variable_str(type), 0);
  H5Tclose(type);
  H5Aclose(format);
  EXPECT_GT(H5Aexists(file, detail::kAttributesChecksumAttribute), 0);
  H5Fclose(file);
  EXPECT_GT(seen.datasets, 20);
  EXPECT_EQ(seen.variable, 0);
  EXPECT_EQ(seen.without_checksum, 0);
  const MapFile read = read_map_file(path);
  EXPECT_TRUE(read.read_notes.empty());
}

// The checksum of a dataset does not depend on how its values are fed (a matrix is hashed a slab
// of rows at a time, its blocks in parallel), and one changed bit changes it.
TEST(MapFileTrust, AChecksumIsTheSameWhicheverPiecesItIsFedIn) {
  std::vector<double> values(std::size_t(3.5 * detail::kChecksumBlock / sizeof(double)));
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = std::sin(double(i));
  detail::Hasher whole;
  whole.doubles(values.data(), values.size());
  std::mt19937 random(3);
  for (int trial = 0; trial < 3; ++trial) {
    detail::Hasher pieces;
    for (std::size_t at = 0; at < values.size();) {
      const std::size_t n = std::min<std::size_t>(values.size() - at, random() % 300000 + 1);
      pieces.doubles(values.data() + at, n);
      at += n;
    }
    EXPECT_EQ(pieces.digest(), whole.digest());
  }
  values[values.size() / 2 + 7] = std::nextafter(values[values.size() / 2 + 7], 2.0);
  detail::Hasher changed;
  changed.doubles(values.data(), values.size());
  EXPECT_NE(changed.digest(), whole.digest());
  EXPECT_NE(detail::Hasher().digest(), whole.digest());
}

TEST(MapFileTrust, DamagedValuesAreAnErrorNamingTheDataset) {
  const TempDir dir;
  const std::string path = dir.file("damaged.mmap.h5");
  const MapFile good = synthetic_file(40, 2);
  // A finite value changed: only the checksum can tell.
  write_map_file(path, good);
  Edit(path, Edit::Damage::Unsealed).set("/model/points", 3, 1, 0.125);
  std::string message = read_error(path);
  EXPECT_EQ(message.rfind("/model/points is damaged: the checksum of its values is ", 0), 0u)
      << message;
  write_map_file(path, good);
  Edit(path, Edit::Damage::Unsealed).set("/coordinates", 39, 0, good.coordinates(39, 0) * 2);
  message = read_error(path);
  EXPECT_EQ(message.rfind("/coordinates is damaged", 0), 0u) << message;
  // An attribute changed: its object's attributes are damaged.
  write_map_file(path, good);
  Edit(path, Edit::Damage::Unsealed).int_attribute("/model", "k", 5);
  message = read_error(path);
  EXPECT_EQ(message.rfind("the attributes of /model are damaged: their checksum is ", 0), 0u)
      << message;
  // A checksum removed from a file of layout 3.
  write_map_file(path, good);
  Edit(path, Edit::Damage::Unsealed).remove_attribute("/samples/frame", "xxh3");
  EXPECT_EQ(read_error(path),
            "missing attribute xxh3 of /samples/frame (the checksum of its values, which layout 3 "
            "requires)");
}

// Bytes of the file changed outside the datasets' values (HDF5's own structure), or the file cut:
// refused before HDF5 parses it.
TEST(MapFileTrust, DamageToTheFilesStructureIsFoundBeforeHdf5ReadsIt) {
  const TempDir dir;
  const std::string path = dir.file("structure.mmap.h5");
  write_map_file(path, synthetic_file(40, 2));
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  ASSERT_GT(bytes.size(), 5000u);
  EXPECT_EQ(bytes.rfind("MotionMap map file", 0), 0u);
  EXPECT_EQ(bytes.compare(4096, 4, "\x89HDF"), 0);
  auto write = [&](const std::string& b) { std::ofstream(path, std::ios::binary) << b; };
  // The superblock's byte after its signature.
  std::string damaged = bytes;
  damaged[4096 + 9] = char(damaged[4096 + 9] ^ 0x40);
  write(damaged);
  std::string message = read_error(path);
  EXPECT_EQ(message.rfind("its HDF5 structure (everything but the datasets' values) is damaged: "
                          "its checksum is ",
                          0),
            0u)
      << message;
  write(bytes.substr(0, bytes.size() - 100));
  EXPECT_EQ(read_error(path),
            "its HDF5 structure (everything but the datasets' values) is damaged: the file has " +
                std::to_string(bytes.size() - 100) + " bytes where it had " +
                std::to_string(bytes.size()) + " (cut or extended)");
  damaged = bytes;
  damaged[60] = 'x';  // inside the checksum line
  write(damaged);
  message = read_error(path);
  EXPECT_NE(message.find("its structure checksum is damaged"), std::string::npos) << message;
  damaged = bytes;
  damaged[0] = 'm';
  write(damaged);
  EXPECT_EQ(read_error(path),
            "its HDF5 structure (everything but the datasets' values) cannot be checked: its "
            "first 4096 bytes, which hold its structure checksum, are damaged");
  write(bytes);
  EXPECT_EQ(read_map_file(path).num_samples(), 40);
}

TEST(MapFileTrust, OldFilesWithoutChecksumsStillReadWithANote) {
  const TempDir dir;
  const std::string path = dir.file("old.mmap.h5");
  const MapFile good = synthetic_file(40, 2);
  write_map_file(path, good);
  {
    Edit e(path, Edit::Damage::Unsealed);
    e.remove_checksums();
    e.int_attribute("/", "format_version", 1);
    // Variable-length strings, as layouts 1 and 2 wrote them.
    e.variable_text_attribute("/parameters", "description", good.parameters.c_str());
  }
  const MapFile read = read_map_file(path);
  expect_same_file(good, read);
  ASSERT_EQ(read.read_notes.size(), 1u);
  EXPECT_EQ(read.read_notes[0],
            path +
                " was written by an older MotionMap (layout 1) without checksums: damage to its "
                "data cannot be detected; save it again to add them");
  // The same file as layout 3 is refused: its checksums are required.
  Edit(path, Edit::Damage::Unsealed).int_attribute("/", "format_version", 3);
  EXPECT_EQ(read_error(path),
            "missing attribute attributes_xxh3 of / (the checksum of its attributes, which layout "
            "3 requires)");
}

TEST(MapFileTrust, TextThatIsNotPrintableUtf8IsRefusedAndEscaped) {
  const TempDir dir;
  const MapFile good = synthetic_file(40, 2);
  int count = 0;
  auto refused = [&](const std::function<void(Edit&)>& edit) {
    const std::string path = dir.file("text" + std::to_string(count++) + ".mmap.h5");
    write_map_file(path, good);
    {
      Edit e(path);
      edit(e);
    }
    return read_error(path);
  };
  EXPECT_EQ(refused([](Edit& e) {
              e.fixed_strings("/skeleton/names", {"Hips\xff", "Spine", "Head"});
            }),
            "/skeleton/names[0] is not printable UTF-8 text: 'Hips\\xFF'");
  EXPECT_EQ(refused([](Edit& e) {
              e.fixed_strings("/clips/path", {"a.bvh", "b\x1b[31m.bvh"});
            }),
            "/clips/path[1] is not printable UTF-8 text: 'b\\x1B[31m.bvh'");
  EXPECT_EQ(refused([](Edit& e) { e.text_attribute("/parameters", "method", "\xc3\x28"); }),
            "attribute method of /parameters is not printable UTF-8 text: '\\xC3('");
  EXPECT_EQ(refused([](Edit& e) { e.text_attribute("/", "format", "motion\xe2\x82map"); }),
            "not a MotionMap map file: its format is 'motion\\xE2\\x82map', expected "
            "'motionmap-map'");
  // A variable-length string in a file of layout 3 (which writes none) is not read at all.
  EXPECT_EQ(refused([](Edit& e) { e.variable_text_attribute("/parameters", "exclude", "x"); }),
            "attribute exclude of /parameters is a variable-length string, which layout 3 does "
            "not write");
  // Valid UTF-8 reads as it is.
  const std::string path = dir.file("utf8.mmap.h5");
  MapFile names = good;
  names.skeleton.names = {"Hüfte", "Rücken", "Kopf"};
  write_map_file(path, names);
  EXPECT_EQ(read_map_file(path).skeleton.names, names.skeleton.names);
}

TEST(MapFileTrust, EveryIndexAndSizeIsCheckedBeforeUse) {
  const TempDir dir;
  const MapFile good = synthetic_file(40, 2);
  int count = 0;
  auto refused = [&](const std::function<void(Edit&)>& edit) {
    const std::string path = dir.file("index" + std::to_string(count++) + ".mmap.h5");
    write_map_file(path, good);
    {
      Edit e(path);
      edit(e);
    }
    return read_error(path);
  };
  // Frames of a clip, neighbours (graph edges), landmarks, samples.
  EXPECT_EQ(refused([](Edit& e) { e.replace("/samples/frame", 40, 0, H5T_STD_I32LE, 45); }),
            "/samples/frame holds 45 at row 0, but clip 0 has 40 frames");
  EXPECT_EQ(refused([](Edit& e) { e.replace("/model/graph/targets", 80, 0, H5T_STD_I32LE, 40); }),
            "/model/graph/targets holds 40 at index 0, expected a model sample index in [0, 40)");
  EXPECT_EQ(refused([](Edit& e) { e.replace("/model/graph/targets", 80, 0, H5T_STD_I32LE, -1); }),
            "/model/graph/targets holds -1 at index 0, expected a model sample index in [0, 40)");
  EXPECT_EQ(
      refused([](Edit& e) { e.replace("/model/landmarks/frames", 12, 0, H5T_STD_I32LE, -3); }),
      "/model/landmarks/frames holds -3 at index 0, expected a model sample index in [0, 40)");
  EXPECT_EQ(refused([](Edit& e) { e.replace("/clips/first_sample", 2, 0, H5T_STD_I32LE, 0); }),
            "/clips/first_sample[1] is 0, expected 20 (clips' rows follow each other)");
  EXPECT_EQ(refused([](Edit& e) { e.replace("/skeleton/end_sites", 3, 0, H5T_STD_I32LE, 1e9); }),
            "/skeleton/end_sites holds 1000000000 at index 0, expected End Sites per joint in [0, "
            "65536)");
  // Shapes against each other, and a size no storage holds (never allocated).
  EXPECT_EQ(
      refused([](Edit& e) { e.replace("/model/landmarks/projection", 2, 11, H5T_IEEE_F64LE, 1); }),
      "/model/landmarks/projection has shape 2×11, expected 2×12 (dims by #landmarks)");
  {
    // Unsealed: no checksum can be computed of values that are not there.
    const std::string path = dir.file("unwritten.mmap.h5");
    write_map_file(path, good);
    Edit(path, Edit::Damage::Unsealed).unwritten("/model/points", 1000000000, 9);
    EXPECT_EQ(read_error(path),
              "/model/points has shape 1000000000×9, more values than its 0 stored bytes hold");
  }
  // Non-finite values, and numbers the method cannot use.
  EXPECT_EQ(refused([](Edit& e) {
              e.replace("/model/landmarks/mean_squared", 12, 0, H5T_IEEE_F64LE, INFINITY);
            }),
            "/model/landmarks/mean_squared holds a non-finite value (inf) at index 0");
}

// ---- Labels (issue 24) ---------------------------------------------------------------------

// synthetic_file() with two labels: "action" over its 40 samples, and "note" with "" and a UTF-8
// value.
MapFile labelled_file() {
  MapFile f = synthetic_file(40, 2);
  pipeline::LabelColumn action{"action", {"run", "walk"}, {}};
  pipeline::LabelColumn note{"note", {"", "über, \"quoted\""}, {}};
  for (int i = 0; i < f.num_samples(); ++i) {
    action.codes.push_back(i % 3 == 0 ? 0 : 1);
    note.codes.push_back(i < 5 ? 1 : 0);
  }
  f.labels.columns = {action, note};
  return f;
}

TEST(MapFileLabels, LabelsRoundTripAndFilesWithoutThemReadWithNone) {
  const TempDir dir;
  const std::string path = dir.file("labels.mmap.h5");
  const MapFile f = labelled_file();
  write_map_file(path, f);
  const MapFile back = read_map_file(path);
  ASSERT_EQ(back.labels.columns.size(), 2u);
  for (std::size_t l = 0; l < 2; ++l) {
    EXPECT_EQ(back.labels.columns[l].name, f.labels.columns[l].name);
    EXPECT_EQ(back.labels.columns[l].categories, f.labels.columns[l].categories);
    EXPECT_EQ(back.labels.columns[l].codes, f.labels.columns[l].codes);
  }
  // Also without the model (Studio, info).
  ReadOptions no_model;
  no_model.model = false;
  EXPECT_EQ(read_map_file(path, no_model).labels.columns[1].codes, f.labels.columns[1].codes);
  const std::string plain = dir.file("plain.mmap.h5");
  write_map_file(plain, synthetic_file(40, 2));
  EXPECT_TRUE(read_map_file(plain).labels.empty());
  // Labels of another sample count are not written.
  MapFile wrong = f;
  wrong.labels.columns[0].codes.pop_back();
  EXPECT_THROW(write_map_file(dir.file("wrong.mmap.h5"), wrong), ParameterError);
}

TEST(MapFileLabels, DamagedLabelsAreAnErrorNamingTheDataset) {
  const TempDir dir;
  const MapFile good = labelled_file();
  int count = 0;
  auto refused = [&](Edit::Damage damage, const std::function<void(Edit&)>& edit) {
    const std::string path = dir.file("damaged" + std::to_string(count++) + ".mmap.h5");
    write_map_file(path, good);
    {
      Edit e(path, damage);
      edit(e);
    }
    return read_error(path);
  };
  // A code changed on disk: the checksum tells.
  std::string message =
      refused(Edit::Damage::Unsealed, [](Edit& e) { e.set_flat("/labels/0/codes", 3, 1); });
  EXPECT_EQ(message.rfind("/labels/0/codes is damaged: the checksum of its values is ", 0), 0u)
      << message;
  // Written that way on purpose (checksums recomputed): the range check tells.
  EXPECT_EQ(refused(Edit::Damage::Sealed,
                    [](Edit& e) { e.replace("/labels/1/codes", 40, 0, H5T_STD_I32LE, 2); }),
            "/labels/1/codes holds 2 at index 0, expected each sample's value (an index into "
            "/labels/1/values) in [0, 2)");
  EXPECT_EQ(refused(Edit::Damage::Sealed,
                    [](Edit& e) { e.replace("/labels/0/codes", 39, 0, H5T_STD_I32LE, 0); }),
            "/labels/0/codes has shape 39, expected 40 (each sample's value (an index into "
            "/labels/0/values))");
  EXPECT_EQ(refused(Edit::Damage::Sealed,
                    [](Edit& e) {
                      e.fixed_strings("/labels/0/values", {"run",
                                                           "w\xff"
                                                           "alk"});
                    }),
            "/labels/0/values[1] is not printable UTF-8 text: 'w\\xFFalk'");
  EXPECT_EQ(refused(Edit::Damage::Sealed,
                    [](Edit& e) {
                      e.fixed_strings("/labels/names", {"action", "action"});
                    }),
            "/labels: labels: the label 'action' is given twice");
  message = refused(Edit::Damage::Sealed, [](Edit& e) { e.remove("/labels/1/values"); });
  EXPECT_NE(message.find("/labels/1/values"), std::string::npos) << message;
  message = refused(Edit::Damage::Sealed, [](Edit& e) { e.remove("/labels/1"); });
  EXPECT_EQ(message, "missing group /labels/1 (the values of label 'note')");
  // The whole group lost: not taken for a file without labels (the root lists its datasets).
  EXPECT_EQ(refused(Edit::Damage::Sealed, [](Edit& e) { e.remove("/labels"); }),
            "missing dataset /labels/names (the root attribute datasets lists it)");
}

}  // namespace
}  // namespace motionmap::mapfile
