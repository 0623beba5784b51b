#pragma once
// The routines the methods (methods.h) share: standardisation, classical MDS, the neighbour graph
// and the joining of its components, the Laplacian eigenmap and LLE of a given graph, and the
// landmark machinery of the points path (distances to landmarks, max-min landmarks, the
// landmark fit).
#include <functional>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "motionmap/core/control.h"
#include "motionmap/embed/graph.h"
#include "motionmap/embed/neighbors.h"
#include "motionmap/embed/points.h"
#include "motionmap/embed/types.h"

namespace motionmap::embed {

class Progress;

/// PCA's per-column scale when standardising: the population standard deviation, 1 for a
/// constant column (StandardScaler's rule); counts those in *constant_columns when given.
Eigen::RowVectorXd standardization_scale(const Eigen::MatrixXd& X, const Eigen::RowVectorXd& mean,
                                         int* constant_columns);
/// The same from the columns' population variances `var` and means over n rows (PCA streamed a
/// block of rows at a time, projection_stream.h).
Eigen::RowVectorXd standardization_scale(const Eigen::RowVectorXd& var,
                                         const Eigen::RowVectorXd& mean, double n,
                                         int* constant_columns);
/// Classical (Torgerson) MDS shared by mds and isomap: B = −½·J·S·J with S_ij = T_ij² (T's lower
/// triangle read; T: #frames by #frames distances), coordinates U·√max(λ, 0) of B's top
/// eigenpairs; fills coordinates, eigenvalues, negative and stress (against T), and warns about
/// axes with λ ≤ 0. Reports the stages "eigen" and "stress" over [begin, end].
void classical_mds(const Eigen::MatrixXd& T, const EmbedOptions& options, Embedding& out,
                   Progress& progress, double begin, double end);

/// The neighbour graph a graph method works on, with the joins already applied.
struct NeighborGraph {
  NeighborLists lists;
  std::vector<Edge> joins;  ///< edges added to connect the components (empty when connected)
  Graph graph;              ///< symmetric k-NN graph + joins, weights = lengths
};

/// How a graph's components are joined (join_components): the edges for the components, the
/// graph rebuilt with them, and the words for the warning ("between their closest frames") and
/// the strict-mode error's hint (" through their closest pairs").
struct Joiner {
  std::string_view how;
  std::string_view strict_hint;
  std::function<std::vector<Edge>(const Components&)> join;
  std::function<Graph(const std::vector<Edge>&)> rebuild;
};

/// Records ng.graph's components in `out` (k_used, graph_components). Several components are
/// refused in strict mode, or joined by `joiner` (ng.joins, ng.graph, connecting_edges and a
/// warning), reporting "joining components" over [begin, end].
/// @throws NumericalError in strict mode when the graph is disconnected; Cancelled.
void join_components(NeighborGraph& ng, const EmbedOptions& options, Embedding& out,
                     Progress& progress, double begin, double end, const Joiner& joiner);

/// k-NN lists, graph, components and joins for `options` (k, strict); records k_used,
/// graph_components, connecting_edges and a warning in `out`. Reports the "neighbours" stage
/// over the overall fractions [begin, end].
/// @throws NumericalError in strict mode when the graph is disconnected (names the number of
///   components and suggests a larger k); Cancelled.
NeighborGraph build_neighbor_graph(const Eigen::MatrixXd& D, const EmbedOptions& options,
                                   Embedding& out, Progress& progress, double begin, double end);

/// The same from points (knn_from_points; no #frames² matrix). A disconnected graph is joined
/// through the closest pairs of a frame and a max-min landmark of another component — the
/// closest pairs of frames would cost #frames² — so joins may be a little longer than the dense
/// path's. Records neighbor_search in `out`.
NeighborGraph build_neighbor_graph(const PointSet& points, const EmbedOptions& options,
                                   Embedding& out, Progress& progress, double begin, double end);

/// Laplacian eigenmap of a neighbour graph (heat-kernel weights, then the sparse eigenproblem),
/// reporting over the overall fractions [begin, end].
void laplacian_eigenmap_on(const NeighborGraph& graph, const EmbedOptions& options, Embedding& out,
                           Progress& progress, double begin, double end = 1.0);
/// LLE of X over a neighbour graph's lists and joins, reporting over [begin, end].
void lle_on(const Eigen::MatrixXd& X, const NeighborGraph& graph, const EmbedOptions& options,
            Embedding& out, Progress& progress, double begin, double end = 1.0);
/// Euclidean distances of frames to fixed landmarks, many at a time (landmark MDS's
/// triangulation, in the fit and when placing): √max(0, ‖p‖² + ‖q‖² − 2·p·q), each sum taken
/// over the values in their order, so a frame's distances are the same bits whichever frames are
/// computed with it. Several frames share each pass over the landmarks (the landmarks stay in
/// cache and the inner loop vectorises over them): 2 flops a value instead of the 3 of Σ(p − q)².
class EuclideanToLandmarks {
 public:
  /// `landmarks`: L rows of points.
  explicit EuclideanToLandmarks(const RowMatrix& landmarks);
  Eigen::Index landmarks() const { return m_by_value.rows(); }
  /// Rows [first, first + count) of `points` (as many values as the landmarks'): their distances
  /// into `out`, L by count, column j for row first + j.
  void compute(const RowMatrix& points, Eigen::Index first, Eigen::Index count,
               Eigen::Ref<Eigen::MatrixXd> out) const;

 private:
  Eigen::MatrixXd m_by_value;  // L by #values: column c holds every landmark's value c
  Eigen::VectorXd m_norms;     // ‖q‖² per landmark
};

/// Max-min landmarks (de Silva & Tenenbaum): the first is frame 0, each next one the frame
/// farthest from those chosen (ties: the smaller index). `distances` receives count by #frames,
/// column f = frame f's distances to the landmarks in the order chosen.
std::vector<int> maxmin_landmarks(const PointSet& points, int count, Eigen::MatrixXd& distances,
                                  const Control& control);
/// The same landmarks without their distances to every frame.
std::vector<int> maxmin_landmarks(const PointSet& points, int count, const Control& control);

/// The landmark map: classical MDS of T (L by L distances between the landmarks, lower triangle
/// read), every frame triangulated from `distances` (L by #frames), then PCA of the result.
/// Fills out.landmarks (but its frames), coordinates, eigenvalues (of the final axes: Σ x² per
/// axis, as classical MDS's eigenvalues), negative, stress (over the landmark pairs) and warnings.
void fit_landmarks(const Eigen::MatrixXd& T, const Eigen::MatrixXd& distances,
                   const EmbedOptions& options, Embedding& out, Progress& progress, double begin,
                   double end);
/// Frames [first, first + count)'s distances to the landmarks, L by count: a view of stored ones,
/// or computed into `scratch`.
using LandmarkDistances = std::function<Eigen::Ref<const Eigen::MatrixXd>(
    int first, int count, Eigen::MatrixXd& scratch)>;
/// The same, reading the #frames frames' distances block by block, twice (the fit, then the map),
/// so that they need never be held all at once.
void fit_landmarks(const Eigen::MatrixXd& T, int frames, const LandmarkDistances& distances,
                   const EmbedOptions& options, Embedding& out, Progress& progress, double begin,
                   double end);

}  // namespace motionmap::embed
