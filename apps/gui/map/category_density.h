#pragma once
// A density image coloured by category: render::density_image's log-scaled 2-D histogram (the
// same opacity per count), each pixel in the mean colour of the samples that fall in it, each
// sample in render::category_color of its category (the CLI's palette). For a saved map of a
// library coloured by a label: one pass over the points, one over the pixels.
#include <vector>

#include <Eigen/Core>
#include <QImage>
#include <QSize>
#include <QTransform>

namespace motionmap::studio {

/// `points` (#points by ≥ 2) binned at `data_to_pixel` (an affine map) into an image of `size`
/// pixels; `categories` (one per point) gives each point's colour (render::category_color; −1:
/// grey); a category below −1 leaves its point out. Pixels without points are transparent.
/// Format_ARGB32_Premultiplied; a null image for an empty size.
/// @throws ParameterError if points has < 2 columns or categories is not one per point.
QImage categoryDensityImage(const Eigen::MatrixXd& points, const std::vector<int>& categories,
                            const QTransform& data_to_pixel, const QSize& size);

}  // namespace motionmap::studio
