// PCA: scores of the centred frames on the covariance matrix's top eigenvectors (like
// sklearn.decomposition.PCA); with standardize, of the standardised frames (correlation PCA).
#include <cmath>
#include <limits>
#include <string>

#include "motionmap/embed/detail/methods.h"
#include "motionmap/embed/detail/progress.h"
#include "motionmap/embed/detail/routines.h"
#include "motionmap/embed/eigen.h"

namespace motionmap::embed {

Eigen::RowVectorXd standardization_scale(const Eigen::MatrixXd& X, const Eigen::RowVectorXd& mean,
                                         int* constant_columns) {
  // Population standard deviation, as sklearn's StandardScaler; a column counts as constant
  // (scale 1, so it stays 0 after centring) by StandardScaler's rule: var ≤ n·ε·var +
  // (n·mean·ε)².
  const double n = double(X.rows());
  const Eigen::RowVectorXd var = (X.rowwise() - mean).array().square().colwise().sum() / n;
  return standardization_scale(var, mean, n, constant_columns);
}

Eigen::RowVectorXd standardization_scale(const Eigen::RowVectorXd& var,
                                         const Eigen::RowVectorXd& mean, double n,
                                         int* constant_columns) {
  const double eps = std::numeric_limits<double>::epsilon();
  Eigen::RowVectorXd scale = var.cwiseSqrt();
  int constant = 0;
  for (Eigen::Index c = 0; c < var.size(); ++c) {
    const double bound = n * eps * var[c] + (n * mean[c] * eps) * (n * mean[c] * eps);
    if (var[c] <= bound) {
      scale[c] = 1.0;
      ++constant;
    }
  }
  if (constant_columns) *constant_columns = constant;
  return scale;
}

void run_pca(const Eigen::MatrixXd& X, const EmbedOptions& options, Embedding& out,
             Progress& progress) {
  progress.stage("eigen", 0.02, 1.0);
  const double n = double(X.rows());
  const Eigen::RowVectorXd mean = X.colwise().mean();
  Eigen::RowVectorXd scale;
  if (options.standardize) {
    int constant = 0;
    scale = standardization_scale(X, mean, &constant);
    if (constant > 0) {
      out.warnings.push_back(std::to_string(constant) +
                             " constant feature column(s) were left unscaled (they are 0 after "
                             "centring)");
    }
  }
  Eigen::VectorXd squared;
  out.coordinates = top_singular_scores(X, mean, scale, options.dimensions, "pca", squared);
  out.eigenvalues = squared / (n - 1.0);
  for (int a = 0; a < options.dimensions; ++a) {
    if (!(out.eigenvalues[a] > 1e-12 * out.eigenvalues[0])) {
      out.warnings.push_back("axis " + std::to_string(a + 1) +
                             " has no variance: the frames span fewer than " +
                             std::to_string(options.dimensions) + " dimensions");
    }
  }
}

}  // namespace motionmap::embed
