// Truncated SVD: the frames, not centred, times X's top right-singular vectors (like
// sklearn.decomposition.TruncatedSVD). The first axis mostly shows the mean pose's magnitude.
#include <string>

#include "motionmap/embed/detail/methods.h"
#include "motionmap/embed/detail/progress.h"
#include "motionmap/embed/eigen.h"

namespace motionmap::embed {

void run_svd(const Eigen::MatrixXd& X, const EmbedOptions& options, Embedding& out,
             Progress& progress) {
  progress.stage("eigen", 0.02, 1.0);
  out.coordinates = top_singular_scores(X, {}, {}, options.dimensions, "svd", out.eigenvalues);
  for (int a = 0; a < options.dimensions; ++a) {
    if (!(out.eigenvalues[a] > 1e-12 * out.eigenvalues[0])) {
      out.warnings.push_back("axis " + std::to_string(a + 1) + " is flat: X has rank below " +
                             std::to_string(options.dimensions));
    }
  }
}

}  // namespace motionmap::embed
