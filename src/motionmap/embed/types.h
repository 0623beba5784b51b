#pragma once
// The value types of embed(): the methods, their options, the inputs and the map that comes out
// (embed.h). A header of its own so that the routines under embed/ (and detail/) can use the
// types without the front door.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "motionmap/core/metric.h"
#include "motionmap/core/names.h"

namespace motionmap::embed {

enum class Method { Pca, Svd, Mds, Isomap, LaplacianEigenmap, Lle, Umap, Gplvm };

/// "pca", "svd", "mds", "isomap", "le", "lle", "umap", "gplvm".
std::string_view method_name(Method method);

/// The method named by `name` (the names of method_name); nullopt for anything else.
std::optional<Method> parse_method(std::string_view name);

/// Every method, in the order of the enum (for menus and loops).
const std::vector<Method>& all_methods();

/// Whether `method` reads the distance matrix D (mds, isomap, le, lle, umap; not pca and svd).
bool reads_distances(Method method);

/// Whether `method` reads the feature matrix X (pca, svd, lle, gplvm).
bool reads_features(Method method);

/// Whether `method` builds a k-NN graph (isomap, le, lle, umap), so k matters.
bool uses_graph(Method method);

/// What an embedding needs from its caller. Defaults are the documented ones (docs/methods/).
struct EmbedOptions {
  Method method = Method::Pca;
  int dimensions = 2;  ///< 2 or 3
  /// Neighbours per frame (isomap, le, lle); must satisfy 1 ≤ k ≤ #frames − 1. umap: its
  /// n_neighbors, which counts the frame itself (k − 1 others; 2 ≤ k ≤ #frames − 1; umap-learn's
  /// and the CLI's default for umap is 15).
  int k = 20;
  /// Laplacian eigenmap heat-kernel width t in exp(−d²/t): nullopt = the median squared k-NN
  /// distance (reported in Embedding::heat_used); ≤ 0 = every edge weight 1.
  std::optional<double> heat;
  /// LLE regularisation: C += reg·trace(C)·I before solving for the weights; must be > 0.
  double reg = 1e-3;
  /// PCA only: divide every column by its standard deviation first (correlation PCA).
  bool standardize = false;
  /// Disconnected neighbour graph: false joins the components through their closest pairs and
  /// warns; true throws NumericalError instead.
  bool strict = false;
  /// umap: the smallest distance between points of the map (the curve 1/(1 + a·d^(2b)) is fitted
  /// to 1 below it, spread 1); in [0, 1].
  double min_dist = 0.1;
  /// umap: layout epochs; 0 = 500 up to 10 000 frames, 200 above (umap_default_epochs).
  int epochs = 0;
  /// umap: seed of the layout's random numbers (negative samples, the start's jitter); ≥ 0.
  int seed = 0;
  /// gplvm: L-BFGS iterations at most (gplvm.h); in [1, 100000].
  int max_iterations = 300;
  /// gplvm: inducing points of the sparse model (gplvm.h); 0 = the full model up to
  /// kGplvmSparseAbove (1 000) frames and kGplvmDefaultInducing (100) above, capped at #frames.
  /// Given (1 ≤ inducing ≤ #frames), the sparse model with that many at any size.
  int inducing = 0;
  /// gplvm: > 0 holds the RBF kernel's lengthscale ℓ at this value through the fit, in latent
  /// units (the latent points' prior is N(0, I)), so that it converges; 0 (the default) fits it
  /// with the latent points, a fit without an optimum whose short ℓ keeps the GP's variance — the
  /// map's validity rule — close to the data (docs/methods/gplvm.md). Finite, ≥ 0.
  double lengthscale = 0.0;
  /// Points path, mds and isomap: number of landmarks (0 = min(#frames, kDefaultLandmarks)).
  int landmarks = 0;
  /// Points path, graph methods: how the k nearest neighbours are found (points.h).
  enum class Search { Auto, Exact, Approximate } search = Search::Auto;

  /// Checks every field for a clip of `num_frames` frames. @throws ParameterError naming the
  /// parameter, its value and the valid range.
  void validate(int num_frames) const;
};

/// The searches' names, as map files write them.
inline constexpr EnumName<EmbedOptions::Search> kSearchNames[] = {
    {EmbedOptions::Search::Auto, "auto"},
    {EmbedOptions::Search::Exact, "exact"},
    {EmbedOptions::Search::Approximate, "approximate"}};
/// "auto", "exact", "approximate".
std::string_view search_name(EmbedOptions::Search search);
/// The search named `name` (search_name's names); nullopt for anything else.
std::optional<EmbedOptions::Search> parse_search(std::string_view name);

/// Landmarks of the points path of mds and isomap unless EmbedOptions::landmarks says otherwise.
constexpr int kDefaultLandmarks = 256;

/// Above this many frames the points path's le and lle (Euclidean points) solve their
/// eigenproblem on a strided sample of at most this many frames and place every other frame by
/// the method's out-of-sample rule over its k nearest samples (placement.h: the Nyström
/// extension, barycentric weights), with a warning. The sparse factorization of the whole graph
/// grows much faster than the frames (le on 72 000 library frames: 6.4·10⁶ entries; on 10⁶:
/// 9.4·10⁸, 11 GB), and the smallest eigenvalues of a library's graph (1e-16 … 1e-13:
/// near-separate clusters of repeated poses) leave no iterative solver to fall back on.
constexpr int kGraphSampleLimit = 100000;

/// The inputs. Pointers, so a caller passes only what its method needs (nullptr = absent).
struct EmbedInput {
  const Eigen::MatrixXd* features = nullptr;  ///< X: #frames by #features
  const Eigen::MatrixXd* distances =
      nullptr;  ///< D: #frames by #frames, symmetric, ≥ 0, 0 diagonal
  /// Instead of D (mds, isomap, le, lle): the rows D would be computed from, and their metric.
  /// Used only when `distances` is null.
  const RowMatrix* points = nullptr;
  Metric metric = Metric::Euclidean;
};

/// What a landmark map (mds and isomap on the points path) keeps to place frames: a frame with
/// distances δ to the landmarks (δ_l = distance to landmark l; Isomap: geodesic) lands at
///   x = −½·P·(δ² − μ) + c
/// de Silva & Tenenbaum's distance-based triangulation into the landmarks' top classical-MDS
/// axes (up to 20), followed by the PCA of all frames so triangulated (P and c include it).
struct LandmarkFit {
  std::vector<int> frames;       ///< the landmarks, as frame indices, in the order chosen
  Eigen::MatrixXd projection;    ///< P: dims by L
  Eigen::VectorXd mean_squared;  ///< μ: L, mean over the landmarks of the squared distances
  Eigen::VectorXd offset;        ///< c: dims
  /// Isomap: L by #frames, column f = frame f's geodesic distances to the landmarks (what a new
  /// frame reaches the landmarks through). Empty for mds.
  Eigen::MatrixXd geodesic;
};

/// What classical MDS (and Isomap's MDS step) learns about the spectrum of B = −½·J·D²·J that the
/// map leaves out. Negative eigenvalues mean the distances are not Euclidean; they are reported
/// here, never folded into the coordinates.
struct NegativeSpectrum {
  /// Most negative eigenvalue of B (0 when B has none). Exact for #frames ≤ kDenseEigenLimit
  /// (eigen.h); above, a free by-product of the Lanczos solve (its smallest Ritz value), which
  /// is never more negative than the truth and usually close to it, but only an estimate.
  double most_negative = 0.0;
  /// |most_negative| ÷ the largest eigenvalue: ≈0 for Euclidean distances; large values mean
  /// the map distorts D strongly.
  double relative = 0.0;
  /// Number of eigenvalues < −1e-9·largest. Known only when the whole spectrum was computed
  /// (#frames ≤ kDenseEigenLimit, see eigen.h); nullopt otherwise.
  std::optional<int> count;
};

/// Wall time of one stage.
struct StageTime {
  std::string stage;
  double seconds = 0.0;
};

/// A map of the frames, with what was used to make it and anything worth telling the user.
struct Embedding {
  Method method = Method::Pca;
  /// #frames by dimensions: row f = the map position of frame f.
  Eigen::MatrixXd coordinates;
  /// dimensions eigenvalues, one per axis, of the matrix the method decomposes: PCA the
  /// covariance (1/(F−1)), SVD XᵀX, MDS/Isomap B, LE the generalised L·y = λ·Deg·y, LLE M.
  Eigen::VectorXd eigenvalues;
  NegativeSpectrum negative;  ///< MDS and Isomap only
  /// MDS and Isomap: normalised stress against D, resp. the geodesic distances (metrics.h).
  std::optional<double> stress;
  int k_used = 0;            ///< graph methods: neighbours per frame (0 otherwise)
  double heat_used = 0.0;    ///< LE: the heat-kernel width used (0 = all weights 1)
  int graph_components = 0;  ///< graph methods: components of the k-NN graph before joining
  int connecting_edges = 0;  ///< edges added to join them (0 when connected)
  std::vector<std::string> warnings;
  /// Facts worth telling that are not problems (e.g. how many frames repeat a pose).
  std::vector<std::string> notes;
  /// Graph methods: frames that repeat an earlier frame's pose exactly (distance 0); each
  /// distinct pose was mapped once and its repeats placed on it (detail/distinct.h).
  int repeated_frames = 0;
  std::vector<StageTime> timings;  ///< in execution order
  /// Points path: how the neighbours were found ("exact", or "approximate (HNSW), recall …");
  /// empty on the dense path and for methods without a graph.
  std::string neighbor_search;
  /// Whether the points path made the map (EmbedInput::points instead of D).
  bool from_points = false;
  /// The frames the method was fitted on, ascending, when not all: le and lle on the points path
  /// above kGraphSampleLimit frames (every s-th; every other frame was placed on their map,
  /// placement.h), and graph methods on frames that repeat poses (the first frame of each
  /// distinct pose; every repeat has its first's place). make_model() keeps these frames.
  /// Empty when every frame was fitted.
  std::vector<int> fitted_frames;
  /// mds and isomap: what placing frames needs (placement.h). On the points path the landmarks
  /// (the stress is then measured over the landmark pairs); on the dense path every frame is a
  /// landmark.
  std::optional<LandmarkFit> landmarks;
  /// gplvm: the kernel's parameters (log σ_f², log ℓ, log σ_b², log σ_n²) the fit ended at, and
  /// the sparse model's inducing inputs (M by dims; empty for the full model): with the
  /// coordinates and X, what placing frames needs (placement.h).
  std::vector<double> gplvm_kernel;
  Eigen::MatrixXd gplvm_inducing;
};

}  // namespace motionmap::embed
