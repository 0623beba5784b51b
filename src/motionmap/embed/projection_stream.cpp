#include "motionmap/embed/projection_stream.h"

#include <cmath>
#include <string>
#include <vector>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/embed/detail/routines.h"
#include "motionmap/embed/eigen.h"

namespace motionmap::embed {

namespace {

std::string who(const EmbedOptions& options) {
  return std::string(method_name(options.method)) + ": ";
}

}  // namespace

ProjectionStream::ProjectionStream(const EmbedOptions& options) : m_options(options) {
  if (options.method != Method::Pca && options.method != Method::Svd) {
    throw ParameterError(who(options) +
                         "only pca and svd can be computed a block of rows at a time (they read "
                         "X only)");
  }
  if (options.dimensions != 2 && options.dimensions != 3) {
    throw ParameterError(who(options) + "dimensions = " + std::to_string(options.dimensions) +
                         " is out of range; valid values are 2 and 3");
  }
}

void ProjectionStream::accumulate(const Eigen::Ref<const Eigen::MatrixXd>& rows) {
  merge(summarize(rows));
}

ProjectionStream::Block ProjectionStream::summarize(const Eigen::Ref<const Eigen::MatrixXd>& rows) {
  Block block;
  block.rows = rows.rows();
  block.cols = rows.cols();
  if (!rows.allFinite()) {
    for (Eigen::Index c = 0; c < rows.cols() && block.bad_row < 0; ++c) {
      for (Eigen::Index r = 0; r < rows.rows(); ++r) {
        if (!std::isfinite(rows(r, c))) {
          block.bad_row = r;
          block.bad_col = c;
          block.bad_value = rows(r, c);
          break;
        }
      }
    }
    return block;
  }
  block.mean = rows.rows() > 0 ? Eigen::RowVectorXd(rows.colwise().mean())
                               : Eigen::RowVectorXd::Zero(rows.cols());
  const Eigen::MatrixXd centred = rows.rowwise() - block.mean;
  block.scatter = Eigen::MatrixXd::Zero(rows.cols(), rows.cols());
  block.scatter.selfadjointView<Eigen::Lower>().rankUpdate(centred.transpose());
  return block;
}

void ProjectionStream::merge(const Block& block) {
  if (m_fitted) throw ParameterError(who(m_options) + "accumulate() after fit()");
  if (m_mean.size() == 0) {
    if (block.cols == 0) {
      throw ParameterError(who(m_options) +
                           "the feature matrix X has no columns; expected #frames by #features "
                           "with both ≥ 1");
    }
    m_mean = Eigen::RowVectorXd::Zero(block.cols);
    m_scatter = Eigen::MatrixXd::Zero(block.cols, block.cols);
  } else if (block.cols != m_mean.size()) {
    throw ParameterError(who(m_options) + "a block of X has " + std::to_string(block.cols) +
                         " columns; the rows before it have " + std::to_string(m_mean.size()));
  }
  if (block.bad_row >= 0) {
    throw ParameterError(who(m_options) + "X(" + std::to_string(m_rows + block.bad_row) + ", " +
                         std::to_string(block.bad_col) + ") is " + format_number(block.bad_value) +
                         "; every feature must be finite");
  }
  if (block.rows == 0) return;
  // The block's mean and centred scatter, merged with the rows before it (Chan, Golub and
  // LeVeque's pairwise update): no sum of squares minus a squared sum, so a column's spread
  // keeps its digits however far its values are from 0.
  const double before = double(m_rows), added = double(block.rows);
  const double total = before + added;
  m_scatter.triangularView<Eigen::Lower>() += block.scatter;
  const Eigen::RowVectorXd delta = block.mean - m_mean;
  if (before > 0.0) {
    m_scatter.selfadjointView<Eigen::Lower>().rankUpdate(delta.transpose(), before * added / total);
  }
  m_mean += delta * (added / total);
  m_rows += block.rows;
}

void ProjectionStream::fit() {
  const std::string w = who(m_options);
  if (m_rows == 0) {
    throw ParameterError(w + "the feature matrix X is empty (0 by " +
                         std::to_string(m_mean.size()) +
                         "); expected #frames by #features with both ≥ 1");
  }
  m_options.validate(static_cast<int>(m_rows));
  const int dims = m_options.dimensions;
  if (m_mean.size() < dims) {
    throw ParameterError(w + "X has " + std::to_string(m_mean.size()) + " column(s); a " +
                         std::to_string(dims) + "-D map needs at least " + std::to_string(dims));
  }
  const double n = double(m_rows);
  Eigen::MatrixXd gram = m_scatter.selfadjointView<Eigen::Lower>();
  m_warnings.clear();
  if (m_options.method == Method::Pca) {
    m_shift = m_mean;
    if (m_options.standardize) {
      int constant = 0;
      m_scale = standardization_scale(Eigen::RowVectorXd(gram.diagonal().transpose() / n), m_mean,
                                      n, &constant);
      if (constant > 0) {
        m_warnings.push_back(std::to_string(constant) +
                             " constant feature column(s) were left unscaled (they are 0 after "
                             "centring)");
      }
      const Eigen::VectorXd inverse = m_scale.transpose().cwiseInverse();
      gram = inverse.asDiagonal() * gram * inverse.asDiagonal();
    }
  } else {
    // XᵀX = the scatter about the mean + n·meanᵀ·mean.
    gram.noalias() += n * m_mean.transpose() * m_mean;
  }
  const EigenPairs top = gram_eigenpairs(gram, dims, method_name(m_options.method));
  m_axes = top.vectors;
  m_squared = top.values;
  for (int a = 0; a < dims; ++a) {
    if (!(m_squared[a] > 0.0)) m_axes.col(a).setZero();
  }
  const Eigen::VectorXd eigenvalues =
      m_options.method == Method::Pca ? Eigen::VectorXd(m_squared / (n - 1.0)) : m_squared;
  for (int a = 0; a < dims; ++a) {
    if (eigenvalues[a] > 1e-12 * eigenvalues[0]) continue;
    m_warnings.push_back(m_options.method == Method::Pca
                             ? "axis " + std::to_string(a + 1) +
                                   " has no variance: the frames span fewer than " +
                                   std::to_string(dims) + " dimensions"
                             : "axis " + std::to_string(a + 1) + " is flat: X has rank below " +
                                   std::to_string(dims));
  }
  m_fitted = true;
}

Eigen::MatrixXd ProjectionStream::project(const Eigen::Ref<const Eigen::MatrixXd>& rows) const {
  if (!m_fitted) throw ParameterError(who(m_options) + "project() before fit()");
  if (rows.cols() != m_axes.rows()) {
    throw ParameterError(who(m_options) + "a block of X has " + std::to_string(rows.cols()) +
                         " columns; the map's have " + std::to_string(m_axes.rows()));
  }
  Eigen::MatrixXd Z = rows;
  if (m_shift.size() > 0) Z.rowwise() -= m_shift;
  if (m_scale.size() > 0) Z.array().rowwise() /= m_scale.array();
  // (An axis without variance has zero columns: its coordinates are 0, as embed() gives them.)
  return Z * m_axes;
}

Embedding ProjectionStream::finish(Eigen::MatrixXd coordinates, MapModel* model) const {
  if (!m_fitted) throw ParameterError(who(m_options) + "finish() before fit()");
  if (coordinates.rows() != m_rows || coordinates.cols() != m_axes.cols()) {
    throw ParameterError(
        who(m_options) + "finish() was given " + std::to_string(coordinates.rows()) + " by " +
        std::to_string(coordinates.cols()) + " coordinates; pass 1 had " + std::to_string(m_rows) +
        " rows and the map " + std::to_string(m_axes.cols()) + " axes");
  }
  Embedding out;
  out.method = m_options.method;
  out.eigenvalues = m_options.method == Method::Pca
                        ? Eigen::VectorXd(m_squared / (double(m_rows) - 1.0))
                        : m_squared;
  out.warnings = m_warnings;
  // The axes flip with the coordinates, so that the model places frames on this map.
  Eigen::MatrixXd axes = m_axes;
  const std::vector<bool> flipped = normalize_signs(coordinates);
  for (Eigen::Index a = 0; a < axes.cols(); ++a) {
    if (flipped[std::size_t(a)]) axes.col(a) = (-axes.col(a)).array() + 0.0;
  }
  out.coordinates = std::move(coordinates);
  if (model) {
    *model = MapModel();
    model->method = m_options.method;
    model->dimensions = static_cast<int>(out.coordinates.cols());
    model->coordinates = out.coordinates;
    model->mean = m_shift;
    model->scale = m_scale;
    model->axes = std::move(axes);
  }
  return out;
}

}  // namespace motionmap::embed
