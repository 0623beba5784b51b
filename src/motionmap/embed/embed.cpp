#include "motionmap/embed/embed.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/core/names.h"
#include "motionmap/core/parallel.h"
#include "motionmap/embed/detail/distinct.h"
#include "motionmap/embed/detail/methods.h"
#include "motionmap/embed/detail/progress.h"
#include "motionmap/embed/detail/routines.h"
#include "motionmap/embed/eigen.h"
#include "motionmap/embed/gplvm.h"
#include "motionmap/embed/k_range.h"

namespace motionmap::embed {

namespace {

constexpr EnumName<Method> kMethodNames[] = {
    {Method::Pca, "pca"},
    {Method::Svd, "svd"},
    {Method::Mds, "mds"},
    {Method::Isomap, "isomap"},
    {Method::LaplacianEigenmap, "le"},
    {Method::Lle, "lle"},
    {Method::Umap, "umap"},
    {Method::Gplvm, "gplvm"},
};

struct MethodInfo {
  Method method;
  std::string_view name;
  bool needs_features;
  bool needs_distances;
  bool uses_graph;
};

constexpr MethodInfo kMethods[] = {
    {Method::Pca, enum_name(kMethodNames, Method::Pca), true, false, false},
    {Method::Svd, enum_name(kMethodNames, Method::Svd), true, false, false},
    {Method::Mds, enum_name(kMethodNames, Method::Mds), false, true, false},
    {Method::Isomap, enum_name(kMethodNames, Method::Isomap), false, true, true},
    {Method::LaplacianEigenmap, enum_name(kMethodNames, Method::LaplacianEigenmap), false, true,
     true},
    {Method::Lle, enum_name(kMethodNames, Method::Lle), true, true, true},
    {Method::Umap, enum_name(kMethodNames, Method::Umap), false, true, true},
    {Method::Gplvm, enum_name(kMethodNames, Method::Gplvm), true, false, false},
};

const MethodInfo& info(Method method) {
  for (const MethodInfo& m : kMethods) {
    if (m.method == method) return m;
  }
  throw ParameterError("method: unknown value " + std::to_string(static_cast<int>(method)));
}

std::string cell(const char* name, Eigen::Index r, Eigen::Index c) {
  return std::string(name) + "(" + std::to_string(r) + ", " + std::to_string(c) + ")";
}

void check_features(const Eigen::MatrixXd& X, std::string_view method) {
  if (X.rows() == 0 || X.cols() == 0) {
    throw ParameterError(std::string(method) + ": the feature matrix X is empty (" +
                         std::to_string(X.rows()) + " by " + std::to_string(X.cols()) +
                         "); expected #frames by #features with both ≥ 1");
  }
  if (!X.allFinite()) {
    for (Eigen::Index c = 0; c < X.cols(); ++c) {
      for (Eigen::Index r = 0; r < X.rows(); ++r) {
        if (!std::isfinite(X(r, c))) {
          throw ParameterError(std::string(method) + ": " + cell("X", r, c) + " is " +
                               format_number(X(r, c)) + "; every feature must be finite");
        }
      }
    }
  }
}

// The points of the points path: at least one value per frame, all finite.
void check_points(const RowMatrix& P, std::string_view method) {
  if (P.rows() == 0 || P.cols() == 0) {
    throw ParameterError(std::string(method) + ": the points are empty (" +
                         std::to_string(P.rows()) + " by " + std::to_string(P.cols()) +
                         "); expected #frames by #values with both ≥ 1");
  }
  if (!P.allFinite()) {
    for (Eigen::Index r = 0; r < P.rows(); ++r) {
      for (Eigen::Index c = 0; c < P.cols(); ++c) {
        if (!std::isfinite(P(r, c))) {
          throw ParameterError(std::string(method) + ": " + cell("points", r, c) + " is " +
                               format_number(P(r, c)) + "; every value must be finite");
        }
      }
    }
  }
}

// check_distances' statistics of entry pairs (x, y) = (D_rc, D_cr): whether all are finite (the
// sum of x − x and y − y, 0 exactly when they are), the smallest of x and y, the largest |x|, the
// largest |x − y|; in independent lanes, which change nothing (minima and maxima are exact).
struct Lanes {
#if defined(__SSE2__)
  __m128d poison[2] = {_mm_setzero_pd(), _mm_setzero_pd()},
          smallest[2] = {_mm_setzero_pd(), _mm_setzero_pd()},
          largest[2] = {_mm_setzero_pd(), _mm_setzero_pd()},
          asymmetry[2] = {_mm_setzero_pd(), _mm_setzero_pd()};
  const __m128d sign_off = _mm_castsi128_pd(_mm_set1_epi64x(0x7fffffffffffffff));
  void pair(int l, __m128d x, __m128d y) {
    poison[l] = _mm_add_pd(poison[l], _mm_add_pd(_mm_sub_pd(x, x), _mm_sub_pd(y, y)));
    smallest[l] = _mm_min_pd(smallest[l], _mm_min_pd(x, y));
    largest[l] = _mm_max_pd(largest[l], _mm_and_pd(x, sign_off));
    asymmetry[l] = _mm_max_pd(asymmetry[l], _mm_and_pd(_mm_sub_pd(x, y), sign_off));
  }
  // x: any alignment; y: 16-byte aligned. `magnitude`: whether |x| counts for the largest.
  void visit(const double* x, const double* y, Eigen::Index count, bool magnitude) {
    if (!magnitude) {
      const __m128d keep[2] = {largest[0], largest[1]};
      visit(x, y, count, true);
      largest[0] = keep[0];
      largest[1] = keep[1];
      return;
    }
    Eigen::Index i = 0;
    for (; i + 4 <= count; i += 4) {
      pair(0, _mm_loadu_pd(x + i), _mm_load_pd(y + i));
      pair(1, _mm_loadu_pd(x + i + 2), _mm_load_pd(y + i + 2));
    }
    for (; i < count; ++i) pair(0, _mm_set1_pd(x[i]), _mm_set1_pd(y[i]));
  }
  void finish(bool& finite, double& small, double& large, double& asym) const {
    alignas(16) double v[4][4];
    for (int l = 0; l < 2; ++l) {
      _mm_store_pd(v[0] + 2 * l, poison[l]);
      _mm_store_pd(v[1] + 2 * l, smallest[l]);
      _mm_store_pd(v[2] + 2 * l, largest[l]);
      _mm_store_pd(v[3] + 2 * l, asymmetry[l]);
    }
    finite = true;
    for (int l = 0; l < 4; ++l) {
      finite = finite && v[0][l] == 0.0;
      small = std::min(small, v[1][l]);
      large = std::max(large, v[2][l]);
      asym = std::max(asym, v[3][l]);
    }
  }
#else
  double poison = 0.0, smallest = 0.0, largest = 0.0, asymmetry = 0.0;
  void visit(const double* x, const double* y, Eigen::Index count, bool magnitude) {
    for (Eigen::Index i = 0; i < count; ++i) {
      poison += (x[i] - x[i]) + (y[i] - y[i]);
      smallest = std::min(smallest, std::min(x[i], y[i]));
      if (magnitude) largest = std::max(largest, std::abs(x[i]));
      asymmetry = std::max(asymmetry, std::abs(x[i] - y[i]));
    }
  }
  void finish(bool& finite, double& small, double& large, double& asym) const {
    finite = poison == 0.0;
    small = std::min(small, smallest);
    large = std::max(large, largest);
    asym = std::max(asym, asymmetry);
  }
#endif
};

// D must be a distance matrix: square, finite, ≥ 0, zero diagonal, symmetric (to 1e-10 of its
// largest entry).
void check_distances(const Eigen::MatrixXd& D, std::string_view method, Progress& progress) {
  const std::string who = std::string(method) + ": ";
  if (D.rows() == 0 || D.rows() != D.cols()) {
    throw ParameterError(who + "the distance matrix D is " + std::to_string(D.rows()) + " by " +
                         std::to_string(D.cols()) + "; expected #frames by #frames with ≥ 1 frame");
  }
  const Eigen::Index n = D.rows();
  // One pass over the lower triangle in panels of kPanel columns, a kPanel by kPanel tile at a
  // time, each with its mirror, reduced without branches per tile: finiteness, smallest entry,
  // largest magnitude (of the entries on or below the diagonal 64 by 64 blocks, as it has always
  // been), largest asymmetry, non-zero diagonal.
  constexpr int kPanel = 256, kBlock = 64;
  const int tiles = static_cast<int>((n + kPanel - 1) / kPanel);
  struct TileStats {
    bool finite = true;
    double smallest = 0.0, largest = 0.0, asymmetry = 0.0;
    bool diagonal = false;
  };
  std::vector<TileStats> stats(static_cast<std::size_t>(tiles));
  // The per-entry work is one fused loop over the lower tile and a transposed copy of its mirror
  // (both contiguous), with independent partial results per statistic; x − x is 0 for a finite x
  // and NaN otherwise, so `poison` stays 0 exactly when every entry is finite. (Minima and maxima
  // do not depend on the order they are taken in, so the lanes change no result.) D is too large
  // for the caches above a few thousand frames: tiles of 256 rows read runs of 2 KB, which the
  // hardware prefetchers follow (64-row tiles read runs of 512 bytes, 64 KB apart at 8000 frames,
  // and waited on memory), and the mirror is copied 8 columns of D at a time (contiguous reads,
  // whole cache lines written).
  parallel_chunks(
      tiles,
      [&](int t, int) {
        TileStats& s = stats[t];
        const Eigen::Index c0 = Eigen::Index(t) * kPanel;
        const Eigen::Index w = std::min<Eigen::Index>(kPanel, n - c0);
        std::vector<double> buffer(std::size_t(kPanel) * kPanel);
        double* mirror = buffer.data();  // mirror[c·kPanel + r] = D(c0 + c, r0 + r)
        Lanes lanes;
        for (Eigen::Index r0 = c0; r0 < n; r0 += kPanel) {
          const Eigen::Index h = std::min<Eigen::Index>(kPanel, n - r0);
          for (Eigen::Index r = 0; r < h; r += 8) {
            const Eigen::Index q = std::min<Eigen::Index>(8, h - r);
            for (Eigen::Index c = 0; c < w; ++c) {
              for (Eigen::Index k = 0; k < q; ++k)
                mirror[c * kPanel + r + k] = D(c0 + c, r0 + r + k);
            }
          }
          for (Eigen::Index c = 0; c < w; ++c) {
            // In the diagonal tile, the rows above column c's 64-block count for all but the
            // largest magnitude.
            const Eigen::Index above = r0 == c0 ? (c / kBlock) * kBlock : 0;
            const double* x = D.col(c0 + c).data() + r0;
            if (above > 0) lanes.visit(x, mirror + c * kPanel, above, false);
            lanes.visit(x + above, mirror + c * kPanel + above, h - above, true);
          }
        }
        lanes.finish(s.finite, s.smallest, s.largest, s.asymmetry);
        s.diagonal = D.diagonal().segment(c0, w).cwiseAbs().maxCoeff() != 0.0;
      },
      [&](int done) { progress.update(double(done) / tiles); });
  TileStats all;
  for (const TileStats& s : stats) {
    all.finite = all.finite && s.finite;
    all.smallest = std::min(all.smallest, s.smallest);
    all.largest = std::max(all.largest, s.largest);
    all.asymmetry = std::max(all.asymmetry, s.asymmetry);
    all.diagonal = all.diagonal || s.diagonal;
  }
  if (!all.finite) {
    for (Eigen::Index c = 0; c < n; ++c) {
      for (Eigen::Index r = 0; r < n; ++r) {
        if (!std::isfinite(D(r, c))) {
          throw ParameterError(who + cell("D", r, c) + " is " + format_number(D(r, c)) +
                               "; every distance must be finite");
        }
      }
    }
  }
  const double tolerance = 1e-10 * all.largest;
  if (all.smallest >= 0.0 && all.asymmetry <= tolerance && !all.diagonal) return;
  // Something is wrong: a serial rescan names the first offending entry.
  for (Eigen::Index c = 0; c < n; ++c) {
    for (Eigen::Index r = 0; r < n; ++r) {
      if (D(r, c) < 0.0) {
        throw ParameterError(who + cell("D", r, c) + " = " + format_number(D(r, c)) +
                             " is negative; distances must be ≥ 0");
      }
      if (r == c && D(r, c) != 0.0) {
        throw ParameterError(who + cell("D", r, c) + " = " + format_number(D(r, c)) +
                             "; the diagonal of a distance matrix must be 0");
      }
      if (std::abs(D(r, c) - D(c, r)) > tolerance) {
        throw ParameterError(who + "D is not symmetric: " + cell("D", r, c) + " = " +
                             format_number(D(r, c)) + " but " + cell("D", c, r) + " = " +
                             format_number(D(c, r)));
      }
    }
  }
}

// The method's map of validated inputs, with embed()'s sign convention.
void run_method(const EmbedInput& input, const EmbedOptions& options, int frames, bool on_points,
                Embedding& out, Progress& progress) {
  const PointSet points{input.points, input.metric};
  switch (options.method) {
    case Method::Pca:
      run_pca(*input.features, options, out, progress);
      break;
    case Method::Svd:
      run_svd(*input.features, options, out, progress);
      break;
    case Method::Mds:
      if (on_points) {
        run_landmark_mds(points, options, out, progress);
      } else {
        run_mds(*input.distances, options, out, progress);
      }
      break;
    case Method::Isomap:
      if (on_points) {
        run_landmark_isomap(points, options, out, progress);
      } else {
        run_isomap(*input.distances, options, out, progress);
      }
      break;
    case Method::LaplacianEigenmap:
      if (on_points && frames > kGraphSampleLimit && input.metric == Metric::Euclidean) {
        run_sampled_graph_method(nullptr, points, options, out, progress);
      } else if (on_points) {
        laplacian_eigenmap_on(build_neighbor_graph(points, options, out, progress, 0.02, 0.3),
                              options, out, progress, 0.3);
      } else {
        run_laplacian_eigenmap(*input.distances, options, out, progress);
      }
      break;
    case Method::Lle:
      if (on_points && frames > kGraphSampleLimit && input.metric == Metric::Euclidean) {
        run_sampled_graph_method(input.features, points, options, out, progress);
      } else if (on_points) {
        lle_on(*input.features, build_neighbor_graph(points, options, out, progress, 0.02, 0.2),
               options, out, progress, 0.2);
      } else {
        run_lle(*input.features, *input.distances, options, out, progress);
      }
      break;
    case Method::Umap:
      if (on_points) {
        run_umap(points, options, out, progress);
      } else {
        run_umap(*input.distances, options, out, progress);
      }
      break;
    case Method::Gplvm:
      run_gplvm(*input.features, options, out, progress);
      break;
  }
  const Eigen::MatrixXd unsigned_coordinates = out.landmarks ? out.coordinates : Eigen::MatrixXd();
  const std::vector<bool> flipped = normalize_signs(out.coordinates);
  // The sparse GP-LVM's inducing inputs live in the latent space: flip their axes with the latent
  // points (the kernel sees only distances, so the fit is the same), or its predictive would be
  // built from inducing inputs mirrored away from the frames.
  for (std::size_t a = 0; a < flipped.size(); ++a) {
    if (flipped[a] && out.gplvm_inducing.rows() > 0)
      out.gplvm_inducing.col(Eigen::Index(a)) *= -1.0;
  }
  if (out.landmarks) {
    // The landmark fit maps to the coordinates as they were: flip its axes with them.
    for (Eigen::Index a = 0; a < out.coordinates.cols(); ++a) {
      Eigen::Index at = 0;
      unsigned_coordinates.col(a).cwiseAbs().maxCoeff(&at);
      if (out.coordinates(at, a) != unsigned_coordinates(at, a)) {
        out.landmarks->projection.row(a) *= -1.0;
        out.landmarks->offset[a] *= -1.0;
      }
    }
  }
}

// The graph methods on frames that repeat poses (detail/distinct.h): the map of the distinct
// poses, each repeat given its first occurrence's place. The distinct poses are the same input
// as a clip without the repeats, so they get that clip's map, bit for bit.
void map_distinct(const EmbedInput& input, const EmbedOptions& options,
                  const DistinctPoses& distinct, bool on_points, Embedding& out,
                  Progress& progress) {
  const int frames = static_cast<int>(distinct.pose_of.size());
  const int poses = static_cast<int>(distinct.first.size());
  const Eigen::Map<const Eigen::VectorXi> first(distinct.first.data(), poses);
  Eigen::MatrixXd X, D;
  RowMatrix points;
  EmbedInput reduced = input;
  if (reads_features(options.method)) {  // a caller may pass an X it has emptied (pipeline)
    X = (*input.features)(first, Eigen::all);
    reduced.features = &X;
  }
  if (on_points) {
    points = (*input.points)(first, Eigen::all);
    reduced.points = &points;
  } else {
    D = (*input.distances)(first, first);
    reduced.distances = &D;
  }
  EmbedOptions o = options;
  o.k = std::min(options.k, poses - 1);
  run_method(reduced, o, poses, on_points, out, progress);
  if (o.k != options.k) {
    out.warnings.push_back("k = " + std::to_string(options.k) + " is more than the " +
                           std::to_string(poses) +
                           " distinct poses allow; k = " + std::to_string(o.k) + " used");
  }
  out.notes.push_back(std::to_string(distinct.repeats()) + " of the " + std::to_string(frames) +
                      " frames repeat an earlier frame's pose (within 1e-6 of the data's scale): "
                      "the " +
                      std::to_string(poses) +
                      " distinct poses were mapped, each repeat placed on its first occurrence");
  out.repeated_frames = distinct.repeats();
  // Back to every frame.
  Eigen::MatrixXd all(frames, out.coordinates.cols());
  for (int f = 0; f < frames; ++f) all.row(f) = out.coordinates.row(distinct.pose_of[f]);
  out.coordinates = std::move(all);
  // The model (placement.h) keeps the fitted frames: the distinct poses (or a sample of them).
  if (out.fitted_frames.empty()) {
    out.fitted_frames = distinct.first;
  } else {
    for (int& f : out.fitted_frames) f = distinct.first[f];
  }
  if (out.landmarks) {
    for (int& f : out.landmarks->frames) f = distinct.first[f];
    if (out.landmarks->geodesic.size() > 0) {
      Eigen::MatrixXd geodesic(out.landmarks->geodesic.rows(), frames);
      for (int f = 0; f < frames; ++f) {
        geodesic.col(f) = out.landmarks->geodesic.col(distinct.pose_of[f]);
      }
      out.landmarks->geodesic = std::move(geodesic);
    }
  }
}

}  // namespace

std::string_view search_name(EmbedOptions::Search search) {
  return enum_name(kSearchNames, search);
}

std::optional<EmbedOptions::Search> parse_search(std::string_view name) {
  return parse_enum(kSearchNames, name);
}

std::string_view method_name(Method method) {
  return info(method).name;
}

std::optional<Method> parse_method(std::string_view name) {
  return parse_enum(kMethodNames, name);
}

const std::vector<Method>& all_methods() {
  static const std::vector<Method> methods = enum_values(kMethodNames);
  return methods;
}

bool reads_distances(Method method) {
  return info(method).needs_distances;
}

bool reads_features(Method method) {
  return info(method).needs_features;
}

bool uses_graph(Method method) {
  return info(method).uses_graph;
}

void EmbedOptions::validate(int num_frames) const {
  const MethodInfo& m = info(method);
  const std::string who = std::string(m.name) + ": ";
  if (dimensions != 2 && dimensions != 3) {
    throw ParameterError(who + "dimensions = " + std::to_string(dimensions) +
                         " is out of range; valid values are 2 and 3");
  }
  if (num_frames < dimensions + 2) {
    throw ParameterError(who + "the clip has " + std::to_string(num_frames) + " frame(s); a " +
                         std::to_string(dimensions) + "-D map needs at least " +
                         std::to_string(dimensions + 2));
  }
  if (m.uses_graph && !valid_neighbors(k, num_frames)) {
    throw ParameterError(who + "k = " + std::to_string(k) + " is out of range: with " +
                         std::to_string(num_frames) + " frames it must be in [" +
                         std::to_string(kMinNeighbors) + ", " +
                         std::to_string(max_neighbors(num_frames)) + "]");
  }
  if (method == Method::Umap && k < 2) {
    throw ParameterError(who + "k = " + std::to_string(k) +
                         " is out of range: umap's n_neighbors counts the frame itself, so it "
                         "must be in [2, " +
                         std::to_string(max_neighbors(num_frames)) + "]");
  }
  if (method == Method::Umap && !(min_dist >= 0.0 && min_dist <= 1.0)) {
    throw ParameterError(who + "min_dist = " + format_number(min_dist) +
                         " is out of range; it must be in [0, 1] (the spread; default 0.1)");
  }
  if (method == Method::Umap && (epochs < 0 || epochs > 100000)) {
    throw ParameterError(who + "epochs = " + std::to_string(epochs) +
                         " is out of range; it must be in [1, 100000], or 0 for the default (500 "
                         "up to 10 000 frames, 200 above)");
  }
  if (method == Method::Gplvm && (max_iterations < 1 || max_iterations > 100000)) {
    throw ParameterError(who + "max_iterations = " + std::to_string(max_iterations) +
                         " is out of range; it must be in [1, 100000] (default 300)");
  }
  if (method == Method::Gplvm && (inducing < 0 || inducing > num_frames)) {
    throw ParameterError(who + "inducing = " + std::to_string(inducing) +
                         " is out of range; it must be in [1, " + std::to_string(num_frames) +
                         "] (the number of frames), or 0 for the default (the full model up to " +
                         std::to_string(kGplvmSparseAbove) + " frames, " +
                         std::to_string(kGplvmDefaultInducing) + " inducing points above)");
  }
  if (method == Method::Gplvm && !(lengthscale >= 0.0 && std::isfinite(lengthscale))) {
    throw ParameterError(who + "lengthscale = " + format_number(lengthscale) +
                         " is out of range; it must be a finite ℓ > 0 (held through the fit), or 0 "
                         "to fit it");
  }
  if (method == Method::Umap && seed < 0) {
    throw ParameterError(who + "seed = " + std::to_string(seed) +
                         " is out of range; it must be ≥ 0");
  }
  if (method == Method::LaplacianEigenmap && heat && !std::isfinite(*heat)) {
    throw ParameterError(who + "heat = " + format_number(*heat) +
                         " is not finite; give a number (≤ 0: all weights 1) or leave it unset "
                         "for the automatic width");
  }
  if (landmarks < 0 || (landmarks > 0 && landmarks <= dimensions)) {
    throw ParameterError(who + "landmarks = " + std::to_string(landmarks) +
                         " is out of range; give 0 (the default, " +
                         std::to_string(kDefaultLandmarks) + ") or at least " +
                         std::to_string(dimensions + 1) + " for a " + std::to_string(dimensions) +
                         "-D map");
  }
  if (method == Method::Lle && !(reg > 0.0 && std::isfinite(reg))) {
    throw ParameterError(who + "reg = " + format_number(reg) +
                         " is out of range; it must be a finite number > 0 (default 1e-3)");
  }
}

double estimate_bytes(Method method, int frames, int values, int columns, bool dense,
                      const EmbedOptions& options) {
  const double F = frames, k = options.k;
  const double base = F * (values + columns) * 8.0;  // the points and X
  if (dense) {
    // D, and Isomap's geodesic distances beside it.
    const double squares = !reads_distances(method) ? 0.0 : method == Method::Isomap ? 2.0 : 1.0;
    return base + squares * 8.0 * F * F + F * k * 64.0;
  }
  const double L =
      std::min<double>(F, options.landmarks > 0 ? options.landmarks : kDefaultLandmarks);
  double bytes = base;
  // le and lle above kGraphSampleLimit frames build their graph and eigenproblem on a sample of
  // that many (Euclidean points; a copy of their rows), placing the others after.
  const bool sampled =
      (method == Method::LaplacianEigenmap || method == Method::Lle) && frames > kGraphSampleLimit;
  const double G = sampled ? double(kGraphSampleLimit) : F;
  if (sampled) bytes += G * (values + columns) * 8.0;
  if (uses_graph(method)) {
    // k-NN lists, the flat pair array and the CSR graph; above the exact limit, the float rows
    // of the k-d tree or of HNSW (and its links).
    bytes += G * k * (12.0 + 2 * 16.0 + 2 * 12.0);
    if (G > kExactNeighborLimit) bytes += G * (values * 4.0 + 32 * 4.0 + 64.0);
  }
  if (method == Method::Mds || method == Method::Isomap) bytes += 8.0 * F * L;
  if (method == Method::LaplacianEigenmap) bytes += G * (2 * k + 1) * 12.0 * 6.0;
  if (method == Method::Lle) bytes += G * k * k * 12.0 * 6.0;
  // umap: the directed and symmetric memberships (sparse matrices, triplets) and the layout's
  // edge arrays (two ints and four doubles per directed edge).
  if (method == Method::Umap) bytes += G * k * (3 * 16.0 + 2 * 40.0 + 2 * 12.0);
  // gplvm, full model: K, its factor, K⁻¹, dL/dK and the RBF and distance matrices (N × N
  // each); sparse: K_uf, its RBF part, distances, dL/dK_uf, its product with the RBF part and
  // P⁻¹K_uf Y Yᵀ (M × N each), L-BFGS's 6 pairs of history vectors (2 × (N + M) × q each), Y
  // and its copy (N × values).
  if (method == Method::Gplvm) {
    const double M = gplvm_inducing_points(frames, options.inducing);
    if (M == 0) {
      bytes += 8.0 * F * F * 6.0;
    } else {
      bytes += 8.0 * (F * M * 6.0 + 12.0 * (F + M) * options.dimensions + 2.0 * F * columns +
                      8.0 * M * M);
    }
  }
  return bytes;
}

Embedding embed(const EmbedInput& input, const EmbedOptions& options, const Control& control) {
  const MethodInfo& m = info(options.method);
  Embedding out;
  out.method = options.method;
  Progress progress(control, &out.timings);
  progress.stage("validate", 0.0, 0.02);

  const std::string who = std::string(m.name) + ": ";
  // The points path: a method that reads D, given the points D would be computed from instead.
  const bool on_points = m.needs_distances && input.distances == nullptr && input.points;
  if (m.needs_features && input.features == nullptr) {
    throw ParameterError(who +
                         "this method needs the feature matrix X (#frames by #features); "
                         "none was given");
  }
  if (m.needs_distances && input.distances == nullptr && !on_points) {
    throw ParameterError(who +
                         "this method needs the distance matrix D (#frames by #frames) or the "
                         "points it is computed from; neither was given");
  }
  if (m.needs_features) check_features(*input.features, m.name);
  if (on_points) {
    check_points(*input.points, m.name);
  } else if (m.needs_distances) {
    check_distances(*input.distances, m.name, progress);
  }
  const Eigen::Index distance_rows = !m.needs_distances ? 0
                                     : on_points        ? input.points->rows()
                                                        : input.distances->rows();
  if (m.needs_features && m.needs_distances && input.features->rows() != distance_rows) {
    throw ParameterError(who + "X has " + std::to_string(input.features->rows()) + " rows but " +
                         (on_points ? "the points have " : "D has ") +
                         std::to_string(distance_rows) + "; both need one per frame");
  }
  const int frames = static_cast<int>(m.needs_features ? input.features->rows() : distance_rows);
  options.validate(frames);
  if (!m.needs_distances && input.features->cols() < options.dimensions) {
    throw ParameterError(who + "X has " + std::to_string(input.features->cols()) +
                         " column(s); a " + std::to_string(options.dimensions) +
                         "-D map needs at least " + std::to_string(options.dimensions));
  }
  out.from_points = on_points;
  if (m.uses_graph) {
    const DistinctPoses distinct =
        on_points ? distinct_rows({input.points, input.metric}, progress.control())
                  : distinct_in_distances(*input.distances, progress.control());
    // Too few distinct poses for a map (a static clip): the frames are mapped as they are, as
    // degenerate as they are.
    if (distinct.repeats() > 0 &&
        static_cast<int>(distinct.first.size()) >= options.dimensions + 2) {
      map_distinct(input, options, distinct, on_points, out, progress);
      progress.finish();
      return out;
    }
  }
  run_method(input, options, frames, on_points, out, progress);
  progress.finish();
  return out;
}

}  // namespace motionmap::embed
