#pragma once
// Placing new frames on a map that was already made, without refitting it (scikit-learn's
// `transform`): everything a map keeps for that (MapModel), and place().
//
//   MapModel model = make_model(input, options, map);          // after embed(input, options)
//   Eigen::MatrixXd xy = place(model, {&new_X, &new_points});   // #new frames by dims
//
// Per method:
//   pca, svd  projection on the map's axes: x = ((f − mean) ÷ scale)·axes;
//   mds       the landmark triangulation (embed.h, LandmarkFit) from the distances to the
//             landmarks; a dense map keeps every frame as a landmark (Nyström);
//   isomap    the same, from geodesic distances: a new frame joins the k-NN graph through its k
//             nearest samples, g(new, l) = min over them of d(new, s) + g(s, l) (a landmark map
//             keeps g(s, l); a dense map runs Dijkstra from the new frame over the kept graph);
//   le        the Nyström extension (Bengio et al. 2004): x = Σ_s w_s·y_s ÷ ((1 − λ_a)·Σ_s w_s)
//             over the k nearest samples s, w_s the heat kernel, λ_a axis a's eigenvalue;
//   lle       barycentric weights of the k nearest samples (LLE's own weights, regularised the
//             same way): x = Σ_s w_s·y_s;
//   umap      the fuzzy-weighted average of the k (n_neighbors) nearest samples' map points,
//             umap-learn's start for transform (its layout steps after it are not run):
//             w_s = exp(−d_s/sigma), sigma by the fit's bisection to Σ w_s = log2(k);
//   gplvm     the latent point x that best explains the frame's features y under the fitted GP:
//             the minimum of −log p(y | x) − log p(x) = D/2 log σ²(x) + |y − μ(x)|²/(2σ²(x))
//             + |x|²/2 (+ constants), μ and σ² the GP's predictive mean and variance (full or
//             sparse model, gplvm.h), by L-BFGS from the latent points of the frame's
//             kGplvmPlaceStarts nearest training frames (in X), the lowest kept. A map's own
//             frames land near, not on, their latent points (the fit also weighs their
//             neighbours and the kernel).
// A frame whose point equals a sample's (distance 0) lands on that sample's coordinates, so
// placing the map's own frames gives their coordinates back: exactly for pca/svd (to rounding),
// landmark maps and every sample of le and lle; for dense mds and isomap to the eigen solver's
// tolerance. Each frame is placed on its own: place(X)[i] == place(X[i:i+1]) bit for bit.
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "motionmap/core/control.h"
#include "motionmap/core/metric.h"
#include "motionmap/embed/gplvm.h"
#include "motionmap/embed/neighbors.h"
#include "motionmap/embed/points.h"
#include "motionmap/embed/types.h"

namespace motionmap::embed {

/// What placing frames on a map needs. Fields a method does not use are empty.
struct MapModel {
  Method method = Method::Pca;
  int dimensions = 2;
  /// The samples' map positions (#samples by dims).
  Eigen::MatrixXd coordinates;

  // pca, svd: x = ((f − mean) ÷ scale)·axes; mean empty for svd, scale empty unless
  // standardised.
  Eigen::RowVectorXd mean;
  Eigen::RowVectorXd scale;
  Eigen::MatrixXd axes;  ///< #features by dims

  // mds, isomap, le, lle, umap: the samples as points (the rows D is computed from) and their
  // metric. For a landmark mds map only the landmarks' rows are kept (in LandmarkFit::frames
  // order).
  RowMatrix points;
  Metric metric = Metric::Euclidean;
  /// mds on the points path: `points` holds the landmarks' rows only.
  bool points_are_landmarks = false;
  int k = 0;  ///< isomap, le, lle, umap: neighbours a new frame joins through
  /// mds, isomap: the triangulation (a dense map: every frame a landmark, in frame order).
  std::optional<LandmarkFit> landmarks;
  /// isomap on the dense path: the k-NN graph (with its joins) the geodesics run on.
  Graph graph;
  double heat = 0.0;            ///< le: heat-kernel width (0: every weight 1)
  Eigen::VectorXd eigenvalues;  ///< le: λ per axis (of L_sym)
  /// lle: the samples' features (X, rows), which the barycentric weights are solved in, and reg.
  RowMatrix features;
  double reg = 1e-3;

  /// gplvm: the GP's predictive (gplvm.h); `features` holds the training frames' X (the
  /// searches start at their nearest's latent points) and `mean` X's column means.
  GplvmPredictive gplvm;
};

/// A gplvm map's GP read as a map over its coordinates `coords` (#samples by 2, the map's rows in
/// the model's sample order): the predictive mean as blend weights and the predictive variance as
/// the rule of where the map is valid (GplvmMap). Null when `model` is not a 2-D gplvm model or
/// its samples are not as many as `coords`' rows (a map of frames placed on a model fitted on
/// other frames).
/// @throws ParameterError as GplvmMap: a model whose predictive does not belong to its latent
///         points and features (a damaged or edited map file).
std::shared_ptr<const GplvmMap> gplvm_map(const MapModel& model, const Eigen::MatrixXd& coords);

/// gplvm: the nearest training frames whose latent points start the search of a new frame's.
inline constexpr int kGplvmPlaceStarts = 3;

/// What place() reads of the new frames: their features (pca, svd, lle: X's columns) and/or their
/// points (mds, isomap, le, lle: the rows D would be computed from, in the model's metric).
struct PlaceInput {
  const Eigen::MatrixXd* features = nullptr;
  const RowMatrix* points = nullptr;
};

/// The model of `map`, which embed(input, options) returned. Reads input as embed() did (a dense
/// mds map reads D once more for the landmark means; a dense isomap map rebuilds its k-NN graph).
/// Takes the map's coordinates and landmark fit (a landmark Isomap map's L × #frames geodesic
/// distances: 2 GB at 10⁶ frames) from `map`: pass std::move(map) when done with it.
/// @throws ParameterError if `input` is not what the map was made from (row counts).
MapModel make_model(const EmbedInput& input, const EmbedOptions& options, Embedding map);

/// The map positions of new frames (#frames by dims). In parallel; `control` hears the fraction
/// placed and may cancel. isomap, le, lle and a dense mds map look up each frame's nearest
/// samples: in `search` when given — a SampleSearch over model.points, kept by a caller that
/// places frames on the same model many times (make_search) — otherwise in one built for this
/// call (building its k-d tree is O(#samples log #samples)). The result is the same either way.
/// @throws ParameterError when the input the method needs is missing, has a different number of
///   columns than the map's, or holds non-finite values (naming the frame), or `search` is not
///   over model.points; Cancelled.
Eigen::MatrixXd place(const MapModel& model, const PlaceInput& input, const Control& control = {},
                      const SampleSearch* search = nullptr);

/// The search place() uses for `model`'s nearest samples, to keep with the model (which must
/// outlive it and not change), or null for a model whose placement does not search (pca, svd, a
/// landmark mds map).
std::unique_ptr<SampleSearch> make_search(const MapModel& model, const Control& control = {});

}  // namespace motionmap::embed
