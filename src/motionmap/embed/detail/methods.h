#pragma once
// The methods behind embed(). Each checks what only it needs, composes the shared routines
// (routines.h: neighbors, graph, eigen) and fills `out` (coordinates before the sign convention,
// eigenvalues, diagnostics). embed() has already validated the options and the inputs it reads.
#include <Eigen/Core>

#include "motionmap/embed/points.h"
#include "motionmap/embed/types.h"

namespace motionmap::embed {

class Progress;

/// PCA of X (#frames by #features): scores on the top principal axes.
void run_pca(const Eigen::MatrixXd& X, const EmbedOptions& options, Embedding& out,
             Progress& progress);
/// Truncated SVD of X, not centred: X times its top right-singular vectors.
void run_svd(const Eigen::MatrixXd& X, const EmbedOptions& options, Embedding& out,
             Progress& progress);
/// Classical MDS of D (#frames by #frames).
void run_mds(const Eigen::MatrixXd& D, const EmbedOptions& options, Embedding& out,
             Progress& progress);
/// Isomap: classical MDS of the geodesic distances along D's k-NN graph.
void run_isomap(const Eigen::MatrixXd& D, const EmbedOptions& options, Embedding& out,
                Progress& progress);
/// Laplacian eigenmap of D's heat-kernel k-NN graph.
void run_laplacian_eigenmap(const Eigen::MatrixXd& D, const EmbedOptions& options, Embedding& out,
                            Progress& progress);
/// LLE: reconstruction weights from X over neighbours from D.
void run_lle(const Eigen::MatrixXd& X, const Eigen::MatrixXd& D, const EmbedOptions& options,
             Embedding& out, Progress& progress);

/// UMAP of D's k-NN graph (umap.h): options.k is n_neighbors, the frame itself counted.
void run_umap(const Eigen::MatrixXd& D, const EmbedOptions& options, Embedding& out,
              Progress& progress);
/// UMAP of the points' k-NN graph.
void run_umap(const PointSet& points, const EmbedOptions& options, Embedding& out,
              Progress& progress);

/// GP-LVM of X (gplvm.h): latent points and kernel fitted from the PCA scores.
void run_gplvm(const Eigen::MatrixXd& X, const EmbedOptions& options, Embedding& out,
               Progress& progress);

// The points path (embed.h, "Two paths"): the same maps without an #frames² matrix.
/// Landmark MDS of the points.
void run_landmark_mds(const PointSet& points, const EmbedOptions& options, Embedding& out,
                      Progress& progress);
/// Landmark Isomap of the points' k-NN graph.
void run_landmark_isomap(const PointSet& points, const EmbedOptions& options, Embedding& out,
                         Progress& progress);

/// The points path's le and lle above kGraphSampleLimit frames (Euclidean points): the method on
/// a strided sample of at most kGraphSampleLimit frames, every other frame placed by the
/// method's out-of-sample rule (placement.h) over its k nearest samples. X: lle only.
void run_sampled_graph_method(const Eigen::MatrixXd* X, const PointSet& points,
                              const EmbedOptions& options, Embedding& out, Progress& progress,
                              int sample_limit = kGraphSampleLimit);

}  // namespace motionmap::embed
