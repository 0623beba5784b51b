// The gp blend mode and the GP's rule of where a GP-LVM map is valid (synth/blender.h,
// embed::GplvmMap), on CMU 64_08 every 4th frame mapped by the GP-LVM.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "motionmap/core/rotation.h"
#include "motionmap/embed/gplvm.h"
#include "motionmap/io/load.h"
#include "motionmap/pipeline/clip_map.h"
#include "motionmap/synth/blender.h"
#include "motionmap/synth/route.h"
#include "support/error_message.h"
#include "support/test_data.h"

namespace motionmap::synth {
namespace {

using ::testing::HasSubstr;

struct GpMap {
  std::vector<Clip> clips;
  pipeline::ClipMap map;
  std::shared_ptr<const embed::GplvmMap> gp;
};

// 64_08 every 4th frame, the full model (or with `inducing` the sparse one), 60 iterations.
GpMap gp_map(int inducing = 0) {
  GpMap m;
  m.clips.push_back(io::load_clip(test::shared_file("cmu/64_08.bvh")));
  pipeline::ClipMapOptions options;
  options.embed.method = embed::Method::Gplvm;
  options.embed.max_iterations = 60;
  options.embed.inducing = inducing;
  options.features.stride = 4;
  m.map = pipeline::map_clips(m.clips, options);
  m.gp = std::dynamic_pointer_cast<const embed::GplvmMap>(pipeline::map_gplvm(m.map));
  return m;
}

MapBlender blender_of(const GpMap& m, BlendMode mode) {
  BlendOptions o;
  o.mode = mode;
  o.gplvm = m.gp;
  return MapBlender(m.clips, *m.map.features, m.map.embedding.coordinates, o);
}

double angle_of(const Eigen::Vector4d& wxyz, const Eigen::Quaterniond& q) {
  return rotation_angle(Eigen::Quaterniond(wxyz[0], wxyz[1], wxyz[2], wxyz[3]).normalized(), q);
}

#define SKIP_WITHOUT_64_08()                                        \
  if (!std::filesystem::exists(test::shared_file("cmu/64_08.bvh"))) \
  GTEST_SKIP() << "shared data file absent: " << test::shared_file("cmu/64_08.bvh")

// The gp blend's joint rotations are the GP's predictive mean of the quaternion features,
// normalised per joint (dropping the smallest weights, kGpWeightTolerance, moves them by < 1e-3
// rad), and at a frame's own latent point the blend is near that frame's pose: no farther than the
// GP's own fit of the frame (its predictive mean there) plus that, as the GP smooths.
TEST(SynthBlenderGp, BlendsTheGpsPredictiveMeanAndNearlyEachFrameAtItsPoint) {
  SKIP_WITHOUT_64_08();
  for (const int inducing : {0, 30}) {
    SCOPED_TRACE("inducing " + std::to_string(inducing));
    const GpMap m = gp_map(inducing);
    ASSERT_TRUE(m.gp);
    const MapBlender blender = blender_of(m, BlendMode::Gp);
    const features::FeatureSet& f = *m.map.features;
    const Eigen::MatrixXd& coords = m.map.embedding.coordinates;
    const Clip& clip = m.clips.front();
    double worst_mean = 0.0, worst_frame = 0.0, worst_fit = 0.0, worst_excess = 0.0;
    std::size_t most_samples = 0;
    int mixed = 0;  // (frame, joint) pairs whose blended samples straddle hemispheres
    for (int i = 0; i < f.num_samples(); ++i) {
      const Eigen::Vector2d x = coords.row(i).transpose();
      const MapWeights w = blender.locate(x);
      EXPECT_FALSE(w.validity.clamped) << "frame " << i;
      most_samples = std::max(most_samples, w.samples.size());
      const Motion pose = blender.pose(w);
      const Eigen::VectorXd weights = m.gp->frame_weights(x);
      const Eigen::RowVectorXd mu = weights.transpose() * f.X;
      Eigen::Index heaviest = 0;
      weights.cwiseAbs().maxCoeff(&heaviest);
      for (std::size_t b = 0; b < f.joints.size(); ++b) {
        const int j = f.joints[b];
        const auto c = Eigen::Index(4 * b);
        const Eigen::Vector4d q = mu.segment<4>(c).transpose();
        const Eigen::Quaterniond own = clip.motion.rotation(f.frame_of[std::size_t(i)], j);
        const double fit = angle_of(q, own), frame = rotation_angle(pose.rotation(0, j), own);
        worst_frame = std::max(worst_frame, frame);
        worst_fit = std::max(worst_fit, fit);
        // The features' signs follow each clip frame to frame; the blend aligns every sample to
        // the heaviest one's hemisphere. They agree unless a blended sample's quaternion lies
        // in the other hemisphere from the heaviest's (CMU's flipping thumbs).
        bool same_side = true;
        for (const int k : w.samples)
          same_side =
              same_side && f.X.row(k).segment<4>(c).dot(f.X.row(heaviest).segment<4>(c)) >= 0.0;
        if (!same_side) {
          ++mixed;
          continue;
        }
        worst_mean = std::max(worst_mean, angle_of(q, pose.rotation(0, j)));
        worst_excess = std::max(worst_excess, frame - fit);
      }
    }
    std::printf(
        "gp blend, %s: blend vs normalised predictive mean %.2e rad; at a frame's own point, "
        "blend vs frame up to %.4f rad (the GP's own fit up to %.4f rad, the blend beyond it by "
        "%.2e); at most %zu of %d samples blended; %d (frame, joint) pairs across hemispheres\n",
        inducing ? "sparse" : "full", worst_mean, worst_frame, worst_fit, worst_excess,
        most_samples, f.num_samples(), mixed);
    EXPECT_LE(worst_mean, 1e-3);
    // Only the thumbs of a few frames straddle hemispheres.
    EXPECT_LE(mixed, f.num_samples() * 2);
    EXPECT_LE(worst_excess, 1e-3);
  }
}

// A point far off the map is moved to the edge of the GP's region, on the segment towards its
// nearest sample: inside there, outside just beyond, reported with the GP's variance, in the gp
// mode and in the local mode alike (one rule); a point at a frame is not moved.
TEST(SynthBlenderGp, ClampsToTheEdgeOfTheGpsRegionInEveryMode) {
  SKIP_WITHOUT_64_08();
  const GpMap m = gp_map();
  const Eigen::MatrixXd& coords = m.map.embedding.coordinates;
  const Eigen::Vector2d far = coords.colwise().maxCoeff().transpose() * 3.0;
  for (const BlendMode mode : {BlendMode::Gp, BlendMode::Local, BlendMode::Idw}) {
    SCOPED_TRACE(std::string(blend_mode_name(mode)));
    const MapBlender blender = blender_of(m, mode);
    const PointValidity v = blender.locate(far).validity;
    EXPECT_TRUE(v.clamped);
    EXPECT_FALSE(blender.inside(far));
    EXPECT_TRUE(blender.inside(v.point));
    EXPECT_LE(v.variance, m.gp->threshold());
    EXPECT_DOUBLE_EQ(v.variance, m.gp->variance(v.point));
    const Eigen::Vector2d q = blender.sample_point(v.nearest_sample);
    // On the segment from the nearest sample to the query, at its GP edge.
    const Eigen::Vector2d along = (far - q).normalized();
    EXPECT_NEAR(std::abs((v.point - q).x() * along.y() - (v.point - q).y() * along.x()), 0.0,
                1e-9 * (far - q).norm());
    EXPECT_GT(m.gp->variance(v.point + 1e-6 * (far - q)), m.gp->threshold());
    const PointValidity at = blender.locate(Eigen::Vector2d(coords.row(7).transpose())).validity;
    EXPECT_FALSE(at.clamped);
    EXPECT_EQ(at.point, Eigen::Vector2d(coords.row(7).transpose()));
    EXPECT_DOUBLE_EQ(at.variance, m.gp->variance(at.point));
  }
}

// The grid route on a GP-LVM map keeps to the GP's rule, the blender's: the field's validity is
// the blender's at random points, its cost finite exactly there, a far point pulled in is valid,
// and a route within one stretch of the swing (frames 2 to 20, the backswing: no jump between)
// runs where the blender does not clamp.
TEST(SynthBlenderGp, TheGridRouteKeepsToTheGpsRule) {
  SKIP_WITHOUT_64_08();
  const GpMap m = gp_map();
  const MapBlender blender = blender_of(m, BlendMode::Gp);
  const MapField field(blender);
  const Eigen::MatrixXd& coords = m.map.embedding.coordinates;
  const Eigen::Vector2d lo = coords.colwise().minCoeff(), hi = coords.colwise().maxCoeff();
  std::mt19937 random(9);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int valid = 0;
  for (int t = 0; t < 400; ++t) {
    const Eigen::Vector2d p = lo + (hi - lo).cwiseProduct(Eigen::Vector2d(u(random), u(random)));
    const bool inside = blender.inside(p);
    EXPECT_EQ(field.valid(p), inside);
    EXPECT_EQ(std::isfinite(field.cost(p)), inside);
    valid += inside;
  }
  EXPECT_GT(valid, 40);
  EXPECT_LT(valid, 360);
  const Eigen::Vector2d far = hi * 3.0;
  EXPECT_FALSE(field.valid(far));
  EXPECT_TRUE(field.valid(field.pulled_in(far)));
  EXPECT_FALSE(blender.locate(field.pulled_in(far)).validity.clamped);
  const Eigen::Vector2d a = coords.row(2).transpose(), b = coords.row(20).transpose();
  const std::vector<Eigen::Vector2d> route = find_route(field, make_grid(field), a, b);
  ASSERT_GE(route.size(), 2u);
  for (std::size_t i = 1; i < route.size(); ++i) {
    EXPECT_TRUE(field.segment_valid(route[i - 1], route[i])) << i;
    EXPECT_FALSE(blender.locate(0.5 * (route[i - 1] + route[i])).validity.clamped) << i;
  }
}

// The gp mode needs a GP, of as many frames as the map has samples.
TEST(SynthBlenderGp, TheGpModeNeedsTheMapsGp) {
  SKIP_WITHOUT_64_08();
  const GpMap m = gp_map();
  BlendOptions o;
  o.mode = BlendMode::Gp;
  EXPECT_THAT(test::error_message<ParameterError>([&] {
                (void)MapBlender(m.clips, *m.map.features, m.map.embedding.coordinates, o);
              }),
              HasSubstr("not a GP-LVM map"));
  features::FeatureSet fewer = *m.map.features;
  o.gplvm = m.gp;
  fewer.clip_of.pop_back();
  fewer.frame_of.pop_back();
  EXPECT_THAT(test::error_message<ParameterError>([&] {
                (void)MapBlender(m.clips, fewer,
                                 m.map.embedding.coordinates.topRows(fewer.num_samples()), o);
              }),
              HasSubstr("GP has 91 frames but the map 90 samples"));
  EXPECT_EQ(parse_blend_mode("gp"), BlendMode::Gp);
  EXPECT_EQ(blend_mode_name(BlendMode::Gp), "gp");
}

}  // namespace
}  // namespace motionmap::synth
