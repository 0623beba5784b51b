#include "motionmap/render/reach_shading.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "motionmap/core/error.h"
#include "motionmap/core/parallel.h"

namespace motionmap::render {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Felzenszwalb and Huttenlocher's 1-D distance transform of sampled functions: d[q] =
/// min over p of (q − p)² + f[p], for the finite f[p] (all infinite: d infinite). O(n).
/// v, z: scratch of at least n and n + 1.
void lower_envelope(const double* f, int n, double* d, int* v, double* z) {
  int k = -1;
  for (int q = 0; q < n; ++q) {
    if (!std::isfinite(f[q])) continue;
    double s = -kInf;
    while (k >= 0) {
      const int p = v[k];
      s = ((f[q] + double(q) * q) - (f[p] + double(p) * p)) / (2.0 * (q - p));
      if (s > z[k]) break;
      --k;
    }
    ++k;
    v[k] = q;
    z[k] = k == 0 ? -kInf : s;
    z[k + 1] = kInf;
  }
  if (k < 0) {
    std::fill(d, d + n, kInf);
    return;
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[k + 1] < q) ++k;
    const double dq = q - v[k];
    d[q] = dq * dq + f[v[k]];
  }
}

}  // namespace

ReachField::ReachField(const Eigen::MatrixXd& points, double reach, int cells) {
  if (points.cols() < 2)
    throw ParameterError("reach field: points have " + std::to_string(points.cols()) +
                         " columns (need at least 2)");
  if (cells < 16)
    throw ParameterError("reach field: cells = " + std::to_string(cells) + " (need at least 16)");
  if (!(std::isfinite(reach) && reach > 0.0)) return;
  Eigen::Vector2d lo(kInf, kInf), hi(-kInf, -kInf);
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    const double x = points(i, 0), y = points(i, 1);
    if (!std::isfinite(x) || !std::isfinite(y)) continue;
    lo = lo.cwiseMin(Eigen::Vector2d(x, y));
    hi = hi.cwiseMax(Eigen::Vector2d(x, y));
  }
  if (!(lo.x() <= hi.x())) return;  // no finite sample
  // Cells of side h over the box grown by reach + 2h: a point off the grid is farther than the
  // reach from every sample.
  const double extent = (hi - lo).maxCoeff() + 2.0 * reach;
  if (!std::isfinite(extent)) return;  // a box wider than a double holds: no grid
  m_cell = extent / double(cells - 4);
  m_inv_cell = 1.0 / m_cell;
  const double pad = reach + 2.0 * m_cell;
  m_origin = lo - Eigen::Vector2d::Constant(pad);
  m_nx = std::clamp(int(std::ceil((hi.x() - lo.x() + 2.0 * pad) * m_inv_cell)), 1, cells);
  m_ny = std::clamp(int(std::ceil((hi.y() - lo.y() + 2.0 * pad) * m_inv_cell)), 1, cells);
  m_reach = reach;
  const std::size_t nx = std::size_t(m_nx), ny = std::size_t(m_ny);

  // The samples' cells, then along each row the squared distance (in cells) to the nearest
  // sampled cell of the row: two sweeps.
  std::vector<std::uint8_t> seeded(nx * ny, 0);
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    const double x = points(i, 0), y = points(i, 1);
    if (!std::isfinite(x) || !std::isfinite(y)) continue;
    const int cx = std::clamp(int((x - m_origin.x()) * m_inv_cell), 0, m_nx - 1);
    const int cy = std::clamp(int((y - m_origin.y()) * m_inv_cell), 0, m_ny - 1);
    seeded[std::size_t(cy) * nx + std::size_t(cx)] = 1;
  }
  std::vector<double> d2(nx * ny, kInf);
  for (std::size_t y = 0; y < ny; ++y) {
    const std::uint8_t* row = seeded.data() + y * nx;
    double* out = d2.data() + y * nx;
    double run = kInf;
    for (std::size_t x = 0; x < nx; ++x) {
      run = row[x] ? 0.0 : run + 1.0;
      out[x] = run;
    }
    run = kInf;
    for (std::size_t x = nx; x-- > 0;) {
      run = row[x] ? 0.0 : run + 1.0;
      out[x] = std::min(out[x], run);
    }
    for (std::size_t x = 0; x < nx; ++x) out[x] *= out[x];
  }
  // Down each column, the lower envelope: the exact squared distance to the nearest sampled
  // cell's centre.
  std::vector<double> f(ny), d(ny), z(ny + 1);
  std::vector<int> v(ny);
  for (std::size_t x = 0; x < nx; ++x) {
    for (std::size_t y = 0; y < ny; ++y) f[y] = d2[y * nx + x];
    lower_envelope(f.data(), m_ny, d.data(), v.data(), z.data());
    for (std::size_t y = 0; y < ny; ++y) d2[y * nx + x] = d[y];
  }
  // A point of a cell and a sample of a cell each lie within half a diagonal of its centre: the
  // point's distance to the nearest sample is the cell's within h·√2 (and a hair for rounding).
  const double margin = m_cell * (std::sqrt(2.0) + 1e-6);
  m_side.resize(nx * ny);
  for (std::size_t c = 0; c < nx * ny; ++c) {
    const double distance = std::sqrt(d2[c]) * m_cell;
    m_side[c] = std::uint8_t(distance + margin <= reach  ? Side::Inside
                             : distance - margin > reach ? Side::Outside
                                                         : Side::Unsure);
  }
}

ReachField ReachField::level_set(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, int cells,
                                 const std::function<double(const Eigen::Vector2d&)>& value,
                                 double threshold, double margin) {
  if (cells < 16)
    throw ParameterError("level field: cells = " + std::to_string(cells) + " (need at least 16)");
  if (!(margin >= 0.0 && margin < 1.0))
    throw ParameterError("level field: margin " + std::to_string(margin) + " is not in [0, 1)");
  if (!lo.allFinite() || !hi.allFinite() || !(lo.x() <= hi.x() && lo.y() <= hi.y()))
    throw ParameterError("level field: the box is not finite");
  ReachField f;
  const double extent = (hi - lo).maxCoeff();
  f.m_cell = extent > 0.0 ? extent / double(cells) : 1.0;
  f.m_inv_cell = 1.0 / f.m_cell;
  f.m_origin = lo;
  f.m_nx = std::clamp(int(std::ceil((hi.x() - lo.x()) * f.m_inv_cell)), 1, cells);
  f.m_ny = std::clamp(int(std::ceil((hi.y() - lo.y()) * f.m_inv_cell)), 1, cells);
  f.m_reach = threshold;
  const int cx = f.m_nx + 1, cy = f.m_ny + 1;  // corners
  std::vector<double> corner(std::size_t(cx) * std::size_t(cy));
  parallel_for(cy, [&](int y) {
    for (int x = 0; x < cx; ++x)
      corner[std::size_t(y) * std::size_t(cx) + std::size_t(x)] =
          value(lo + Eigen::Vector2d(x * f.m_cell, y * f.m_cell));
  });
  f.m_side.resize(std::size_t(f.m_nx) * std::size_t(f.m_ny));
  f.m_level = corner;
  const double below = threshold * (1.0 - margin), above = threshold * (1.0 + margin);
  for (int y = 0; y < f.m_ny; ++y) {
    for (int x = 0; x < f.m_nx; ++x) {
      const std::size_t c = std::size_t(y) * std::size_t(cx) + std::size_t(x);
      const double a = corner[c], b = corner[c + 1], d = corner[c + std::size_t(cx)],
                   e = corner[c + std::size_t(cx) + 1];
      const double most = std::max({a, b, d, e}), least = std::min({a, b, d, e});
      f.m_side[std::size_t(y) * std::size_t(f.m_nx) + std::size_t(x)] =
          std::uint8_t(most < below    ? Side::Inside
                       : least > above ? Side::Outside
                                       : Side::Unsure);
    }
  }
  return f;
}

double ReachField::level(double x, double y) const {
  if (m_level.empty()) return kInf;
  const double gx = (x - m_origin.x()) * m_inv_cell, gy = (y - m_origin.y()) * m_inv_cell;
  if (!(gx >= 0.0 && gy >= 0.0 && gx <= m_nx && gy <= m_ny)) return kInf;
  const int ix = std::min(int(gx), m_nx - 1), iy = std::min(int(gy), m_ny - 1);
  const double u = gx - ix, v = gy - iy;
  const std::size_t cx = std::size_t(m_nx) + 1, c = std::size_t(iy) * cx + std::size_t(ix);
  return (1 - v) * ((1 - u) * m_level[c] + u * m_level[c + 1]) +
         v * ((1 - u) * m_level[c + cx] + u * m_level[c + cx + 1]);
}

QImage reach_image(const ReachField& field, const QTransform& pixel_to_map, const QSize& size,
                   const QColor& color, const std::function<bool(const Eigen::Vector2d&)>& within,
                   const QRect& clip) {
  QImage image(size.expandedTo(QSize(0, 0)), QImage::Format_ARGB32_Premultiplied);
  image.fill(Qt::transparent);
  const QRect area = clip.isEmpty() ? image.rect() : clip.intersected(image.rect());
  if (field.empty() || area.isEmpty() || pixel_to_map.type() == QTransform::TxProject) return image;
  QColor opaque = color;
  opaque.setAlpha(255);
  const QRgb ink = opaque.rgba();
  // Grid coordinates of the pixel centres, stepped along each row.
  const double inv = field.m_inv_cell;
  const double ox = field.m_origin.x(), oy = field.m_origin.y();
  const double stepX = pixel_to_map.m11() * inv, stepY = pixel_to_map.m12() * inv;
  const int nx = field.m_nx, ny = field.m_ny;
  const auto* sides = field.m_side.data();
  for (int j = area.top(); j <= area.bottom(); ++j) {
    auto* line = reinterpret_cast<QRgb*>(image.scanLine(j));
    const QPointF first = pixel_to_map.map(QPointF(area.left() + 0.5, j + 0.5));
    double gx = (first.x() - ox) * inv, gy = (first.y() - oy) * inv;
    for (int i = area.left(); i <= area.right(); ++i, gx += stepX, gy += stepY) {
      if (!(gx >= 0.0 && gy >= 0.0 && gx < nx && gy < ny)) continue;
      const auto side =
          ReachField::Side(sides[std::size_t(int(gy)) * std::size_t(nx) + std::size_t(int(gx))]);
      if (side == ReachField::Side::Outside) continue;
      if (side == ReachField::Side::Unsure) {
        const QPointF p = pixel_to_map.map(QPointF(i + 0.5, j + 0.5));
        if (!within(Eigen::Vector2d(p.x(), p.y()))) continue;
      }
      line[i] = ink;
    }
  }
  return image;
}

}  // namespace motionmap::render
