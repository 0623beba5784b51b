#pragma once
// Helpers for the embed tests: the reference fixtures (tests/reference/fixtures, written by
// tests/reference/make_fixtures.py), Procrustes disparity, and small synthetic inputs.
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Core>
#include <Eigen/SVD>

namespace motionmap::test {

inline std::string fixture_dir() {
  return std::string(MOTIONMAP_SOURCE_DIR) + "/tests/reference/fixtures";
}

/// A fixture file: "# key value…" header lines, then "# rows cols" and the matrix rows.
struct Fixture {
  std::map<std::string, std::string> header;
  Eigen::MatrixXd matrix;

  bool has(const std::string& key) const { return header.count(key) > 0; }
  double number(const std::string& key) const { return std::stod(header.at(key)); }
  Eigen::VectorXd numbers(const std::string& key) const {
    std::istringstream in(header.at(key));
    std::vector<double> v;
    for (std::string tok; in >> tok;) v.push_back(std::strtod(tok.c_str(), nullptr));
    return Eigen::Map<Eigen::VectorXd>(v.data(), Eigen::Index(v.size()));
  }
};

inline Fixture read_fixture(const std::string& path) {
  std::ifstream in(path);
  if (!in) ADD_FAILURE() << "cannot open fixture " << path;
  Fixture f;
  std::vector<std::string> comments;
  std::string line;
  Eigen::Index rows = -1, cols = -1, r = 0;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (line[0] == '#') {
      std::istringstream h(line.substr(1));
      std::string key;
      h >> key;
      std::string rest;
      std::getline(h, rest);
      const auto start = rest.find_first_not_of(' ');
      rest = start == std::string::npos ? "" : rest.substr(start);
      if (!key.empty() && std::isdigit(static_cast<unsigned char>(key[0]))) {
        rows = std::stol(key);
        cols = std::stol(rest);
        f.matrix.resize(rows, cols);
      } else {
        f.header[key] = rest;
      }
      continue;
    }
    std::istringstream row(line);
    for (Eigen::Index c = 0; c < cols; ++c) {
      std::string tok;
      row >> tok;
      f.matrix(r, c) = std::strtod(tok.c_str(), nullptr);
    }
    ++r;
  }
  EXPECT_EQ(r, rows) << path;
  return f;
}

/// Euclidean distances of X's rows, summed one column at a time in column order then sqrt:
/// the same operations as make_fixtures.py's euclidean(), so the bits agree.
inline Eigen::MatrixXd euclidean_distances(const Eigen::MatrixXd& X) {
  const Eigen::Index n = X.rows();
  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index c = 0; c < X.cols(); ++c) {
    for (Eigen::Index j = 0; j < n; ++j) {
      for (Eigen::Index i = 0; i < n; ++i) {
        const double d = X(i, c) - X(j, c);
        s(i, j) += d * d;
      }
    }
  }
  return s.cwiseSqrt();
}

/// scipy.spatial.procrustes's disparity: both maps centred and scaled to unit Frobenius norm,
/// B rotated/reflected and scaled onto A, then Σ(A − B′)².
inline double procrustes_disparity(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  Eigen::MatrixXd a = A.rowwise() - A.colwise().mean();
  Eigen::MatrixXd b = B.rowwise() - B.colwise().mean();
  a /= a.norm();
  b /= b.norm();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(b.transpose() * a,
                                        Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::MatrixXd R = svd.matrixU() * svd.matrixV().transpose();
  return (a - svd.singularValues().sum() * b * R).squaredNorm();
}

/// F frames of a smooth, roughly periodic trajectory in d dimensions.
inline Eigen::MatrixXd smooth_trajectory(int frames, int dims) {
  Eigen::MatrixXd X(frames, dims);
  const double two_pi = 2.0 * M_PI;
  for (int i = 0; i < frames; ++i) {
    const double s = double(i) / double(frames - 1);
    for (int j = 0; j < dims; ++j) {
      const double f = 1.0 + (j % 5) * 0.5 + 0.1 * (j % 3);
      const double amp = 1.0 / (1.0 + 0.1 * j);
      X(i, j) = amp * std::sin(two_pi * 4.0 * f * s + 0.37 * j) +
                0.3 * amp * s * std::cos(0.5 * j) + 0.01 * amp * std::sin(12.9898 * i + 78.233 * j);
    }
  }
  return X;
}

/// Two well separated blobs of `per_cluster` points each on noisy circles in 3-D.
inline Eigen::MatrixXd two_clusters(int per_cluster) {
  Eigen::MatrixXd X(2 * per_cluster, 3);
  for (int c = 0; c < 2; ++c) {
    for (int i = 0; i < per_cluster; ++i) {
      const double t = 2.0 * M_PI * i / per_cluster;
      X.row(c * per_cluster + i) << std::cos(t) + 100.0 * c, std::sin(t), 0.1 * std::sin(3 * t);
    }
  }
  return X;
}

}  // namespace motionmap::test
