#pragma once
// Maps every frame of a clip to a point on a 2-D (or 3-D) map: PCA, SVD, classical MDS, Isomap,
// Laplacian eigenmap and LLE over a feature matrix X and/or a pose-distance matrix D.
//
//   motionmap::embed::EmbedOptions options;
//   options.method = motionmap::embed::Method::Isomap;
//   options.k = 15;
//   motionmap::embed::Embedding map = motionmap::embed::embed({.distances = &D}, options);
//   // map.coordinates: #frames by 2; map.warnings: anything the caller should show
//
// Rows are frames everywhere. Which input each method reads:
//   pca, svd  X only;   mds, isomap, le  D only;   lle  X (weights) and D (neighbours).
//
// Two paths, one interface. Given D, every method is exact (dense: D is #frames², so this path
// ends near 20 000 frames). Given the points D would be computed from instead (EmbedInput::points,
// see points.h), mds, isomap, le and lle never form an #frames² matrix:
//   mds     landmark MDS (de Silva & Tenenbaum 2004): max-min landmarks, classical MDS of the
//           landmarks, every frame triangulated from its distances to them;
//   isomap  landmark Isomap: geodesic distances from the landmarks only (Dijkstra on the sparse
//           k-NN graph), then the same triangulation;
//   le, lle the same sparse eigenproblems as the dense path, on the k-NN graph of the points
//           (exact k-d tree search, approximate HNSW above kExactNeighborLimit frames).
// With every frame a landmark, landmark MDS and Isomap give the dense maps (to rounding).
// Every output axis is flipped so that its entry of largest magnitude is positive, so the same
// input always gives the same picture (and byte-identical numbers on one machine).
#include <Eigen/Core>

#include "motionmap/core/control.h"
#include "motionmap/embed/types.h"

namespace motionmap::embed {

/// The triangulation of LandmarkFit, frame by frame: column f of `distances` (L by #frames)
/// holds frame f's distances to the landmarks; returns #frames by dims. Row f depends on column f
/// only, summed in a fixed order, so a frame lands on the same bits however many are placed.
Eigen::MatrixXd triangulate(const LandmarkFit& fit, const Eigen::MatrixXd& distances);

/// Estimated peak memory in bytes of mapping `frames` frames with `method` on the dense path
/// (dense = true: D given) or the points path, the inputs included: `values` is the width of the
/// points, `columns` of X (0 when X's rows are not held). Within a factor of about 1.5, for
/// refusing requests that cannot fit before they start.
double estimate_bytes(Method method, int frames, int values, int columns, bool dense,
                      const EmbedOptions& options);

/// Computes the map of options.method. X and/or D (or the points instead of D) per the method
/// (see the top of this file); when both are given they must have the same number of rows.
/// @throws ParameterError for a missing or malformed input (empty, non-finite, D not square,
///   not symmetric, negative or with a non-zero diagonal, row counts that differ) or a bad option;
///   NumericalError for a disconnected graph in strict mode, heat-kernel weights that underflow,
///   or an eigen solver that does not converge; Cancelled when `control` is cancelled. `control`
///   hears each stage ("validate", "neighbours", "shortest paths", "eigen", "stress", …) and its
///   progress, and is polled within every long loop.
Embedding embed(const EmbedInput& input, const EmbedOptions& options, const Control& control = {});

}  // namespace motionmap::embed
