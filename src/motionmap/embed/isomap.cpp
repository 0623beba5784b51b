// Isomap: geodesic distances (shortest paths along the k-NN graph of D) replace D, then
// classical MDS. Unrolls a curved manifold when k is small enough not to short-cut it.
#include "motionmap/embed/detail/methods.h"
#include "motionmap/embed/detail/progress.h"
#include "motionmap/embed/detail/routines.h"
#include "motionmap/embed/graph.h"
#include "motionmap/embed/neighbors.h"

namespace motionmap::embed {

void run_isomap(const Eigen::MatrixXd& D, const EmbedOptions& options, Embedding& out,
                Progress& progress) {
  Eigen::MatrixXd geodesic;
  {
    const NeighborGraph ng = build_neighbor_graph(D, options, out, progress, 0.02, 0.1);
    progress.stage("shortest paths", 0.1, 0.7);
    geodesic = shortest_paths(ng.graph, progress.control());
  }
  classical_mds(geodesic, options, out, progress, 0.7, 1.0);
}

}  // namespace motionmap::embed
