#include "map/category_density.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "motionmap/core/error.h"
#include "motionmap/render/map_plot.h"

namespace motionmap::studio {

QImage categoryDensityImage(const Eigen::MatrixXd& points, const std::vector<int>& categories,
                            const QTransform& data_to_pixel, const QSize& size) {
  if (points.cols() < 2)
    throw ParameterError("density points need 2 columns, got " + std::to_string(points.cols()));
  if (Eigen::Index(categories.size()) != points.rows()) {
    throw ParameterError("categories: " + std::to_string(categories.size()) + " for " +
                         std::to_string(points.rows()) + " points");
  }
  if (size.isEmpty()) return {};
  // The palette once: slot 0 is "other" (−1), slot c + 1 category c (cycling as category_color).
  std::vector<QRgb> palette(std::size_t(render::kCategoryColors) + 1);
  for (int c = -1; c < render::kCategoryColors; ++c)
    palette[std::size_t(c + 1)] = render::category_color(c).rgb();
  struct Bin {
    std::uint32_t count = 0, r = 0, g = 0, b = 0;
  };
  const int w = size.width(), h = size.height();
  std::vector<Bin> bins(std::size_t(w) * std::size_t(h));
  const double m11 = data_to_pixel.m11(), m12 = data_to_pixel.m12(), m21 = data_to_pixel.m21(),
               m22 = data_to_pixel.m22(), dx = data_to_pixel.dx(), dy = data_to_pixel.dy();
  const Eigen::Index n = points.rows();
  const double* xs = points.data();
  const double* ys = points.data() + n;  // column-major: column 1 follows column 0
  std::uint32_t most = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const int category = categories[std::size_t(i)];
    if (category < -1) continue;  // hidden
    const double px = m11 * xs[i] + m21 * ys[i] + dx, py = m12 * xs[i] + m22 * ys[i] + dy;
    if (!(px >= 0.0 && px < w && py >= 0.0 && py < h)) continue;  // outside, or NaN
    Bin& bin = bins[std::size_t(int(py)) * std::size_t(w) + std::size_t(int(px))];
    const QRgb colour = palette[std::size_t(category % render::kCategoryColors + 1)];
    bin.r += std::uint32_t(qRed(colour));
    bin.g += std::uint32_t(qGreen(colour));
    bin.b += std::uint32_t(qBlue(colour));
    most = std::max(most, ++bin.count);
  }
  QImage image(size, QImage::Format_ARGB32_Premultiplied);
  image.fill(Qt::transparent);
  if (most == 0) return image;
  // Opacity per count as render::density_image, through a table: logarithms are dear.
  const double scale = 1.0 / std::log1p(double(most));
  const auto alphaOf = [&](std::uint32_t c) {
    const double a = 0.12 + 0.88 * std::log1p(double(c)) * scale;
    return std::uint32_t(std::clamp(int(std::lround(255.0 * a)), 0, 255));
  };
  std::vector<std::uint32_t> alphas(std::min<std::uint32_t>(most, 4096) + 1);
  for (std::uint32_t c = 1; c < alphas.size(); ++c) alphas[c] = alphaOf(c);
  for (int y = 0; y < h; ++y) {
    auto* line = reinterpret_cast<QRgb*>(image.scanLine(y));
    const Bin* row = bins.data() + std::size_t(y) * std::size_t(w);
    for (int x = 0; x < w; ++x) {
      const Bin& bin = row[x];
      if (bin.count == 0) continue;
      const std::uint32_t alpha =
          bin.count < alphas.size() ? alphas[bin.count] : alphaOf(bin.count);
      // The mean colour, premultiplied: sum · alpha / (count · 255).
      const std::uint64_t div = std::uint64_t(bin.count) * 255u;
      line[x] =
          qRgba(int(std::uint64_t(bin.r) * alpha / div), int(std::uint64_t(bin.g) * alpha / div),
                int(std::uint64_t(bin.b) * alpha / div), int(alpha));
    }
  }
  return image;
}

}  // namespace motionmap::studio
