#pragma once
// PCA and SVD of a feature matrix X that is never held whole: its rows are given a block at a
// time, twice, in the same order — the first pass accumulates what the axes need (the row count,
// the column means and the centred scatter matrix, #features by #features), the second places
// each block's rows on the axes. Memory: O(#features² + one block + the #frames by dims
// coordinates). The map is embed()'s PCA/SVD of the stacked rows to rounding (the scatter matrix
// is summed in another order), with embed()'s signs (each axis's largest-magnitude coordinate
// positive), eigenvalues and warnings. pipeline/stream_map.h streams a library's clips so.
//
//   motionmap::embed::ProjectionStream stream(options);    // options.method: Pca or Svd
//   for (auto& block : blocks) stream.accumulate(block);    // pass 1
//   stream.fit();                                           // the axes
//   Eigen::MatrixXd Y(stream.rows(), options.dimensions);
//   for (…) Y.middleRows(at, block.rows()) = stream.project(block);   // pass 2
//   MapModel model;
//   Embedding map = stream.finish(std::move(Y), &model);
#include <Eigen/Core>

#include "motionmap/embed/placement.h"
#include "motionmap/embed/types.h"

namespace motionmap::embed {

class ProjectionStream {
 public:
  /// @throws ParameterError unless options.method is Pca or Svd, or for bad dimensions.
  explicit ProjectionStream(const EmbedOptions& options);

  /// Pass 1: the next rows of X (any number, each block #rows by #features, the same #features
  /// every time): merge(summarize(rows)). @throws as merge().
  void accumulate(const Eigen::Ref<const Eigen::MatrixXd>& rows);

  /// What pass 1 keeps of a block of rows: its row count, column means and centred scatter
  /// matrix, and its first non-finite value if any.
  struct Block {
    Eigen::Index rows = 0, cols = 0;
    Eigen::RowVectorXd mean;
    Eigen::MatrixXd scatter;  ///< lower triangle
    Eigen::Index bad_row = -1, bad_col = -1;
    double bad_value = 0.0;
  };
  /// A block's summary, on its own: several blocks can be summarised at once (on several
  /// threads) and merged in order; the result does not depend on how they were computed.
  static Block summarize(const Eigen::Ref<const Eigen::MatrixXd>& rows);
  /// Adds the next block (in row order). @throws ParameterError for a non-finite value (naming its
  /// row among all rows given so far and its column) or a block of another width.
  void merge(const Block& block);

  /// Between the passes: the axes, from what pass 1 accumulated.
  /// @throws ParameterError for too few rows or columns for the map (as embed()); NumericalError
  ///   as embed().
  void fit();

  /// Pass 2: the map coordinates of `rows` (#rows by dims), before the signs of the whole map are
  /// settled in finish(). @throws ParameterError before fit() or for a block of another width.
  Eigen::MatrixXd project(const Eigen::Ref<const Eigen::MatrixXd>& rows) const;

  /// After pass 2: the map of every row, `coordinates` being project()'s blocks stacked in pass 1's
  /// order, each axis flipped as embed() flips it; with `model`, also what placing new frames
  /// needs (embed::make_model's mean, scale and axes, the axes flipped alike).
  /// @throws ParameterError when `coordinates` does not have pass 1's rows.
  Embedding finish(Eigen::MatrixXd coordinates, MapModel* model = nullptr) const;

  /// Rows accumulated in pass 1.
  Eigen::Index rows() const { return m_rows; }

 private:
  EmbedOptions m_options;
  Eigen::Index m_rows = 0;
  Eigen::RowVectorXd m_mean;  // running column means
  Eigen::MatrixXd m_scatter;  // Σ (x − mean)ᵀ(x − mean), lower triangle
  bool m_fitted = false;
  Eigen::RowVectorXd m_shift;  // pca: the mean; svd: empty
  Eigen::RowVectorXd m_scale;  // pca --standardize: the columns' deviations; else empty
  Eigen::MatrixXd m_axes;      // #features by dims, V
  Eigen::VectorXd m_squared;   // σ², descending
  std::vector<std::string> m_warnings;
};

}  // namespace motionmap::embed
