#include "motionmap/render/map_plot.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

#include <QCoreApplication>
#include <QFont>
#include <QFontMetricsF>
#include <QGuiApplication>
#include <QImage>
#include <QLinearGradient>
#include <QPolygonF>

#include "motionmap/core/error.h"
#include "motionmap/render/drawing_file.h"

namespace motionmap::render {
namespace {

// The classic "jet" ramp run backwards, as the reference system draws time: dark red, red,
// yellow, cyan, blue, dark blue at t = 0, 1/8, 3/8, 5/8, 7/8, 1 (green lies halfway).
constexpr int kTimeStops = 6;
constexpr double kTimeKnots[kTimeStops] = {0.0, 0.125, 0.375, 0.625, 0.875, 1.0};
constexpr int kTimeRgb[kTimeStops][3] = {{128, 0, 0},   {255, 0, 0}, {255, 255, 0},
                                         {0, 255, 255}, {0, 0, 255}, {0, 0, 128}};

// Runs of consecutive segments whose time falls in the same bin are stroked as one polyline:
// fewer draw calls and clean joins on long clips, no visible banding with 256 bins.
constexpr int kTimeBins = 256;

// Similarity data → unit square: u = (p - centre) * scale + 0.5.
struct UnitMapping {
  double cx = 0.0;
  double cy = 0.0;
  double scale = 1.0;
  QPointF map(double x, double y) const { return {(x - cx) * scale + 0.5, (y - cy) * scale + 0.5}; }
};

bool finite_row(const Eigen::MatrixXd& coords, Eigen::Index i) {
  return std::isfinite(coords(i, 0)) && std::isfinite(coords(i, 1));
}

void check_columns(const Eigen::MatrixXd& coords, const char* what = "coords") {
  if (coords.cols() < 2) {
    throw ParameterError(std::string("map plot: ") + what + " has " +
                         std::to_string(coords.cols()) + " column(s); need at least 2 (x, y)");
  }
}

// Row ranges of the clips: clip k is [bounds[k], bounds[k+1]). Validates segment_starts.
std::vector<int> clip_bounds(const Eigen::MatrixXd& coords, const std::vector<int>& starts) {
  check_columns(coords);
  if (coords.rows() > std::numeric_limits<int>::max() - 1) {
    throw ParameterError("map plot: too many samples (" + std::to_string(coords.rows()) + ")");
  }
  const int n = static_cast<int>(coords.rows());
  std::vector<int> bounds{0};
  for (std::size_t k = 0; k < starts.size(); ++k) {
    const int s = starts[k];
    if (s < 0 || s >= n) {
      throw ParameterError("map plot: segment_starts[" + std::to_string(k) + "] = " +
                           std::to_string(s) + " is outside [0, " + std::to_string(n) + ")");
    }
    if (k > 0 && s <= starts[k - 1]) {
      throw ParameterError("map plot: segment_starts must be strictly increasing, but [" +
                           std::to_string(k) + "] = " + std::to_string(s) + " follows " +
                           std::to_string(starts[k - 1]));
    }
    if (s > 0) bounds.push_back(s);
  }
  bounds.push_back(n);
  return bounds;
}

// A spread of coordinates this small next to their magnitude is rounding noise (the flat axis of
// a static clip: the same value up to the last bits), not a shape to blow up to the panel.
bool negligible_extent(double half_extent, double magnitude) {
  return !(half_extent > 1e-300) || half_extent <= 1e-12 * magnitude;
}

UnitMapping unit_mapping(const Eigen::MatrixXd& coords) {
  check_columns(coords);
  double xmin = std::numeric_limits<double>::infinity(), xmax = -xmin;
  double ymin = xmin, ymax = -xmin;
  for (Eigen::Index i = 0; i < coords.rows(); ++i) {
    if (!finite_row(coords, i)) continue;
    xmin = std::min(xmin, coords(i, 0));
    xmax = std::max(xmax, coords(i, 0));
    ymin = std::min(ymin, coords(i, 1));
    ymax = std::max(ymax, coords(i, 1));
  }
  UnitMapping m;
  if (!(xmin <= xmax)) return m;  // no finite sample
  // Halves before subtracting so that ±1e308 does not overflow.
  m.cx = xmin / 2 + xmax / 2;
  m.cy = ymin / 2 + ymax / 2;
  const double half = std::max(xmax / 2 - xmin / 2, ymax / 2 - ymin / 2);
  const double magnitude =
      std::max({std::abs(xmin), std::abs(xmax), std::abs(ymin), std::abs(ymax)});
  // No extent to speak of: keep scale 1 so the single point lands at the centre.
  m.scale = negligible_extent(half, magnitude) ? 1.0 : 0.5 / half;
  return m;
}

// The extent a panel frames: the coordinates, and the backdrop's points when there are any.
UnitMapping panel_mapping(const Eigen::MatrixXd& coords, const MapPlotOptions& options) {
  const QRectF& e = options.extent;
  if (e.width() >= 0 && e.height() >= 0 && std::isfinite(e.left()) && std::isfinite(e.right()) &&
      std::isfinite(e.top()) && std::isfinite(e.bottom())) {
    Eigen::MatrixXd corners(2, 2);
    corners << e.left(), e.top(), e.right(), e.bottom();
    return unit_mapping(corners);
  }
  if (options.backdrop.size() == 0) return unit_mapping(coords);
  check_columns(coords);
  check_columns(options.backdrop, "backdrop");
  Eigen::MatrixXd both(coords.rows() + options.backdrop.rows(), 2);
  both << coords.leftCols(2), options.backdrop.leftCols(2);
  return unit_mapping(both);
}

double clip_time(int i, int begin, int end) {
  return end - begin > 1 ? double(i - begin) / double(end - begin - 1) : 0.0;
}

int time_bin(double t) {
  return std::clamp(static_cast<int>(t * kTimeBins), 0, kTimeBins - 1);
}

// Where everything of one panel goes. Sizes scale with the panel so a figure and a single
// image look alike.
struct Layout {
  QRectF title;
  QRectF box;   // the frame
  QRectF data;  // the unit square's image, inside the frame
  QRectF legend;
  QRectF notes;
  double title_px = 0.0;
  double notes_px = 0.0;
};

struct Metrics {
  double pad, title_px, notes_px, title_h, legend_h, notes_h;
};

// Non-empty point categories must be one per sample.
void check_categories(const MapPlotOptions& o, Eigen::Index rows) {
  if (!o.point_category.empty() && o.point_category.size() != std::size_t(rows)) {
    throw ParameterError("map plot: " + std::to_string(o.point_category.size()) +
                         " point categories for " + std::to_string(rows) + " samples");
  }
}

// The category legend's entries: the categories, then "other" when there is one.
QStringList category_entries(const MapPlotOptions& o) {
  QStringList entries = o.categories;
  if (!o.other_category.isEmpty()) entries << o.other_category;
  return entries;
}

// The category legend as a grid of equal cells: a cell's width (from the longest entry, by an
// estimate of the text's width that needs no font: 0.62 em per character) and how many a row
// of `width` holds.
struct LegendGrid {
  double cell = 0.0;
  int per_row = 1;
  int rows = 0;
};

LegendGrid category_grid(const QStringList& entries, double width, double px) {
  LegendGrid g;
  qsizetype longest = 1;
  for (const QString& e : entries) longest = std::max(longest, e.size());
  g.cell = px * (1.2 + 0.4 + 1.2) + 0.62 * px * double(std::min<qsizetype>(longest, 28));
  g.per_row = std::max(1, static_cast<int>(width * 0.94 / g.cell));
  g.rows = static_cast<int>((entries.size() + g.per_row - 1) / g.per_row);
  return g;
}

int category_legend_rows(const MapPlotOptions& o, double width, double px) {
  return std::max(1, category_grid(category_entries(o), width, px).rows);
}

Metrics panel_metrics(double base, const MapPlotOptions& o) {
  Metrics m{};
  m.pad = base * 0.03;
  // Text grows with the square root of the panel: legible when small, not shouting when big.
  m.title_px = std::max(8.0, 0.9 * std::sqrt(base));
  m.notes_px = std::max(7.0, 0.67 * std::sqrt(base));
  m.title_h = o.title.isEmpty() ? 0.0 : m.title_px * 1.7;
  m.legend_h = o.time_legend ? m.notes_px * 1.9 : 0.0;
  if (o.time_legend && !o.categories.isEmpty()) {
    m.legend_h = m.notes_px * 1.6 * category_legend_rows(o, base, m.notes_px) + m.notes_px * 0.4;
  }
  m.notes_h = o.notes.isEmpty() ? 0.0 : (o.notes.size() + 0.4) * m.notes_px * 1.35;
  return m;
}

Layout layout_panel(const QRectF& rect, const MapPlotOptions& o) {
  const double base = std::max(1.0, std::min(rect.width(), rect.height()));
  const Metrics m = panel_metrics(base, o);
  Layout l;
  l.title_px = m.title_px;
  l.notes_px = m.notes_px;
  const double extra = m.title_h + m.legend_h + m.notes_h;
  const double side =
      std::max(0.0, std::min(rect.width() - 2 * m.pad, rect.height() - 2 * m.pad - extra));
  // The title, box, legend and notes form one block, centred in the rect.
  const double top = rect.top() + (rect.height() - side - extra) / 2;
  const double left = rect.left() + (rect.width() - side) / 2;
  l.title = QRectF(rect.left(), top, rect.width(), m.title_h);
  l.box = QRectF(left, top + m.title_h, side, side);
  l.legend = QRectF(rect.left(), l.box.bottom(), rect.width(), m.legend_h);
  l.notes = QRectF(rect.left() + m.pad, l.legend.bottom() + 0.4 * m.notes_px,
                   rect.width() - 2 * m.pad, m.notes_h);
  const double margin = side * 0.05;
  // Never empty, so the transforms built on it stay invertible (Qt's test is det > 1e-12).
  const double data_side = std::max(side - 2 * margin, 1e-3);
  l.data = QRectF(left + margin, l.box.top() + margin, data_side, data_side);
  return l;
}

// Height a panel needs to be `width` wide with a square box as wide as the layout allows.
double panel_height_for_width(double width, const MapPlotOptions& o) {
  const Metrics m = panel_metrics(std::max(1.0, width), o);
  return width + m.title_h + m.legend_h + m.notes_h;
}

QTransform unit_to_rect(const QRectF& data) {
  return QTransform(data.width(), 0, 0, -data.height(), data.left(), data.bottom());
}

QFont font_px(double px, bool bold = false) {
  QFont f;
  f.setPixelSize(std::max(1, static_cast<int>(std::lround(px))));
  f.setBold(bold);
  return f;
}

void draw_text_line(QPainter& p, const QRectF& r, const QString& text, const QFont& font,
                    const QColor& color) {
  p.setFont(font);
  p.setPen(color);
  const QString shown = QFontMetricsF(font).elidedText(text, Qt::ElideRight, r.width());
  p.drawText(r, Qt::AlignCenter, shown);
}

// "▬ name  ▬ name …": the clip colours, centred in `area` (names elided to fit).
void draw_clip_legend(QPainter& p, const QRectF& area, double px, const MapPlotOptions& o) {
  const QStringList& names = o.clip_names;
  const bool elide_right = o.legend_elide_right;
  const QFont font = font_px(px);
  const QFontMetricsF fm(font);
  const double swatch = px * 1.2, gap = px * 0.4, spacing = px * 1.2;
  const double max_name = std::max(
      px * 3, area.width() / std::max<qsizetype>(1, names.size()) - swatch - gap - spacing);
  QStringList shown;
  double total = 0.0;
  for (const QString& name : names) {
    shown << fm.elidedText(name, elide_right ? Qt::ElideRight : Qt::ElideMiddle, max_name);
    total += swatch + gap + fm.horizontalAdvance(shown.back()) + spacing;
  }
  double x = area.center().x() - (total - spacing) / 2;
  const double cy = area.center().y();
  p.setFont(font);
  for (qsizetype c = 0; c < shown.size(); ++c) {
    p.setPen(Qt::NoPen);
    const QRectF box(x, cy - px * 0.3, swatch, px * 0.6);
    // The clip's colours as drawn: light → dark as its time runs with a ramp, else flat.
    const QColor first = drawn_clip_color(o, static_cast<int>(c), 0.0);
    const QColor last = drawn_clip_color(o, static_cast<int>(c), 1.0);
    if (first != last) {
      QLinearGradient g(box.topLeft(), box.topRight());
      g.setColorAt(0.0, first);
      g.setColorAt(1.0, last);
      p.setBrush(g);
    } else {
      p.setBrush(first);
    }
    p.drawRect(box);
    x += swatch + gap;
    p.setPen(QColor(70, 70, 70));
    const double w = fm.horizontalAdvance(shown[c]) + 1;
    p.drawText(QRectF(x, area.top(), w, area.height()), Qt::AlignLeft | Qt::AlignVCenter, shown[c]);
    x += w + spacing;
  }
  p.setBrush(Qt::NoBrush);
}

// "▬ walk (512)  ▬ run (301) …": the categories' colours in a grid of rows centred in `area`.
void draw_category_legend(QPainter& p, const QRectF& area, double px, const MapPlotOptions& o) {
  const QStringList entries = category_entries(o);
  const LegendGrid g = category_grid(entries, area.width(), px);
  const QFont font = font_px(px);
  const QFontMetricsF fm(font);
  const double swatch = px * 1.2, gap = px * 0.4, row_h = px * 1.6;
  const int in_first_row = std::min<int>(g.per_row, int(entries.size()));
  const double left = area.center().x() - in_first_row * g.cell / 2;
  const double top = area.center().y() - g.rows * row_h / 2;
  p.setFont(font);
  for (qsizetype c = 0; c < entries.size(); ++c) {
    const double x = left + double(c % g.per_row) * g.cell;
    const double y = top + double(c / g.per_row) * row_h;
    const bool other = !o.other_category.isEmpty() && c == entries.size() - 1;
    p.setPen(Qt::NoPen);
    p.setBrush(category_color(other ? -1 : int(c)));
    p.drawRect(QRectF(x, y + row_h / 2 - px * 0.3, swatch, px * 0.6));
    p.setPen(QColor(70, 70, 70));
    const double w = g.cell - swatch - gap;
    p.drawText(QRectF(x + swatch + gap, y, w, row_h), Qt::AlignLeft | Qt::AlignVCenter,
               fm.elidedText(entries[c], Qt::ElideRight, w));
  }
  p.setBrush(Qt::NoBrush);
}

// "start ▬▬▬ end": the time colours, centred in `area`.
void draw_time_legend(QPainter& p, const QRectF& area, double px) {
  const QFont font = font_px(px);
  const QFontMetricsF fm(font);
  const double bar_w = std::min(area.width() * 0.35, px * 12);
  const double bar_h = px * 0.6;
  const double gap = px * 0.5;
  const QString left = QStringLiteral("start");
  const QString right = QStringLiteral("end");
  const double total = fm.horizontalAdvance(left) + gap + bar_w + gap + fm.horizontalAdvance(right);
  double x = area.center().x() - total / 2;
  const double cy = area.center().y();
  p.setFont(font);
  p.setPen(QColor(70, 70, 70));
  p.drawText(QRectF(x, area.top(), fm.horizontalAdvance(left) + 1, area.height()),
             Qt::AlignLeft | Qt::AlignVCenter, left);
  x += fm.horizontalAdvance(left) + gap;
  const QRectF bar(x, cy - bar_h / 2, bar_w, bar_h);
  QLinearGradient g(bar.topLeft(), bar.topRight());
  for (const double t : kTimeKnots) g.setColorAt(t, time_color(t));
  p.setPen(Qt::NoPen);
  p.setBrush(g);
  p.drawRect(bar);
  p.setBrush(Qt::NoBrush);
  x += bar_w + gap;
  p.setPen(QColor(70, 70, 70));
  p.drawText(QRectF(x, area.top(), fm.horizontalAdvance(right) + 1, area.height()),
             Qt::AlignLeft | Qt::AlignVCenter, right);
}

// Liang–Barsky: the part of segment a–b inside `box` (a and b moved onto it); false when none.
bool clip_segment(QPointF& a, QPointF& b, const QRectF& box) {
  const double dx = b.x() - a.x(), dy = b.y() - a.y();
  double t0 = 0.0, t1 = 1.0;
  const double p[4] = {-dx, dx, -dy, dy};
  const double q[4] = {a.x() - box.left(), box.right() - a.x(), a.y() - box.top(),
                       box.bottom() - a.y()};
  for (int k = 0; k < 4; ++k) {
    if (p[k] == 0.0) {
      if (q[k] < 0.0) return false;  // parallel to this edge and outside it
      continue;
    }
    const double t = q[k] / p[k];
    if (p[k] < 0.0) {
      t0 = std::max(t0, t);
    } else {
      t1 = std::min(t1, t);
    }
    if (t0 > t1) return false;
  }
  const QPointF from = a;
  a = from + QPointF(dx, dy) * t0;
  b = from + QPointF(dx, dy) * t1;
  return true;
}

}  // namespace

QColor category_color(int category) {
  static constexpr int kPalette[kCategoryColors][3] = {
      {31, 119, 180},  {255, 127, 14}, {44, 160, 44},   {214, 39, 40},
      {148, 103, 189}, {140, 86, 75},  {227, 119, 194}, {188, 189, 34},
      {23, 190, 207},  {28, 40, 110},  {240, 200, 0},   {35, 35, 35}};
  if (category < 0) return QColor(200, 200, 200);
  const int* c = kPalette[category % kCategoryColors];
  return QColor(c[0], c[1], c[2]);
}

std::vector<int> category_slots(std::span<const int> counts) {
  std::vector<int> order(counts.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return counts[std::size_t(a)] > counts[std::size_t(b)]; });
  const bool grouped = order.size() > std::size_t(kCategoryColors);
  const std::size_t coloured = grouped ? std::size_t(kCategoryColors - 1) : order.size();
  std::vector<bool> kept(counts.size(), false);
  for (std::size_t k = 0; k < coloured; ++k) kept[std::size_t(order[k])] = true;
  std::vector<int> slot_of(counts.size(), -1);
  int next = 0;
  for (std::size_t v = 0; v < counts.size(); ++v) {
    if (kept[v]) slot_of[v] = next++;
  }
  return slot_of;
}

QColor drawn_clip_color(const MapPlotOptions& options, int clip, double t) {
  if (clip >= 0 && std::size_t(clip) < options.clip_colors.size() &&
      options.clip_colors[std::size_t(clip)].isValid())
    return options.clip_colors[std::size_t(clip)];
  return options.clip_time_ramp ? clip_time_color(clip, t) : clip_color(clip);
}

QColor clip_color(int clip) {
  static constexpr int kPalette[10][3] = {
      {78, 121, 167}, {242, 142, 43},  {225, 87, 89},   {118, 183, 178}, {89, 161, 79},
      {237, 201, 72}, {176, 122, 161}, {255, 157, 167}, {156, 117, 95},  {186, 176, 172}};
  if (clip < 0) return QColor(128, 128, 128);
  const int* c = kPalette[clip % 10];
  return QColor(c[0], c[1], c[2]);
}

QColor clip_time_color(int clip, double t) {
  const QColor base = clip_color(clip);
  if (std::isnan(t)) return base;
  t = std::clamp(t, 0.0, 1.0);
  // Towards white before the middle, towards black after it.
  const double towards = t < 0.5 ? 1.0 - 2.0 * t : 2.0 * t - 1.0;
  const double share = t < 0.5 ? 0.5 * towards : 0.4 * towards;
  const int target = t < 0.5 ? 255 : 0;
  auto mix = [&](int c) { return static_cast<int>(std::lround(c + share * (target - c))); };
  return QColor(mix(base.red()), mix(base.green()), mix(base.blue()));
}

QColor time_color(double t) {
  if (std::isnan(t)) return QColor(128, 128, 128);
  t = std::clamp(t, 0.0, 1.0);
  int k = 0;
  while (k < kTimeStops - 2 && t > kTimeKnots[k + 1]) ++k;
  const double f = (t - kTimeKnots[k]) / (kTimeKnots[k + 1] - kTimeKnots[k]);
  int c[3];
  for (int j = 0; j < 3; ++j) {
    c[j] =
        static_cast<int>(std::lround(kTimeRgb[k][j] + f * (kTimeRgb[k + 1][j] - kTimeRgb[k][j])));
  }
  return QColor(c[0], c[1], c[2]);
}

QTransform data_to_unit(const Eigen::MatrixXd& coords) {
  const UnitMapping m = unit_mapping(coords);
  return QTransform(m.scale, 0, 0, m.scale, 0.5 - m.cx * m.scale, 0.5 - m.cy * m.scale);
}

Eigen::MatrixXd fill_axes(const Eigen::MatrixXd& coords) {
  check_columns(coords);
  Eigen::MatrixXd out = coords;
  double extent[2] = {0.0, 0.0}, centre[2] = {0.0, 0.0};
  for (int c = 0; c < 2; ++c) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (Eigen::Index i = 0; i < coords.rows(); ++i) {
      if (!finite_row(coords, i)) continue;
      lo = std::min(lo, coords(i, c));
      hi = std::max(hi, coords(i, c));
    }
    if (lo <= hi && !negligible_extent(hi / 2 - lo / 2, std::max(std::abs(lo), std::abs(hi)))) {
      extent[c] = hi / 2 - lo / 2;
      centre[c] = lo / 2 + hi / 2;
    }
  }
  const double target = std::max(extent[0], extent[1]);
  for (int c = 0; c < 2; ++c) {
    if (extent[c] == 0.0 || !std::isfinite(target / extent[c])) continue;  // flat: left alone
    out.col(c) = (coords.col(c).array() - centre[c]) * (target / extent[c]) + centre[c];
  }
  return out;
}

namespace {

std::vector<ColoredSegment> segments_in(const Eigen::MatrixXd& coords,
                                        const std::vector<int>& segment_starts,
                                        const UnitMapping& m) {
  const std::vector<int> bounds = clip_bounds(coords, segment_starts);
  std::vector<ColoredSegment> out;
  out.reserve(coords.rows() > 0 ? static_cast<std::size_t>(coords.rows() - 1) : 0);
  for (std::size_t k = 0; k + 1 < bounds.size(); ++k) {
    const int begin = bounds[k], end = bounds[k + 1];
    for (int i = begin; i + 1 < end; ++i) {
      if (!finite_row(coords, i) || !finite_row(coords, i + 1)) continue;
      ColoredSegment s;
      s.from = m.map(coords(i, 0), coords(i, 1));
      s.to = m.map(coords(i + 1, 0), coords(i + 1, 1));
      s.sample = i;
      s.clip = static_cast<int>(k);
      s.time = (clip_time(i, begin, end) + clip_time(i + 1, begin, end)) / 2;
      s.color = time_color(s.time);
      out.push_back(s);
    }
  }
  return out;
}

}  // namespace

std::vector<ColoredSegment> trajectory_segments(const Eigen::MatrixXd& coords,
                                                const std::vector<int>& segment_starts) {
  return segments_in(coords, segment_starts, unit_mapping(coords));
}

QRectF data_area(const QRectF& rect, const MapPlotOptions& options) {
  return layout_panel(rect, options).data;
}

QTransform unit_transform(const QRectF& rect, const MapPlotOptions& options) {
  return unit_to_rect(data_area(rect, options));
}

namespace {

// Calls visit(i, pixel) for each point i of `points` that falls in the image of `size` at
// `data_to_pixel`, pixel its row-major index; points outside and non-finite rows are skipped.
// The transform is a similarity (scale, translate, maybe flip): its affine part, applied here.
template <class Visit>
void for_each_binned(const Eigen::MatrixXd& points, const QTransform& data_to_pixel,
                     const QSize& size, Visit visit) {
  const int w = size.width(), h = size.height();
  const double m11 = data_to_pixel.m11(), m12 = data_to_pixel.m12(), m21 = data_to_pixel.m21(),
               m22 = data_to_pixel.m22(), dx = data_to_pixel.dx(), dy = data_to_pixel.dy();
  const Eigen::Index n = points.rows();
  const double* xs = points.data();
  const double* ys = points.data() + n;  // column-major: column 1 follows column 0
  for (Eigen::Index i = 0; i < n; ++i) {
    const double px = m11 * xs[i] + m21 * ys[i] + dx, py = m12 * xs[i] + m22 * ys[i] + dy;
    if (!(px >= 0.0 && px < w && py >= 0.0 && py < h)) continue;  // outside, or NaN
    visit(std::size_t(i), std::size_t(int(py)) * std::size_t(w) + std::size_t(int(px)));
  }
}

// The opacity (0–255) of a pixel holding `count` of at most `most` points:
// 0.12 + 0.88 · log(1 + count) / log(1 + most), through a table (counts repeat, logarithms are
// dear).
class DensityAlpha {
 public:
  explicit DensityAlpha(std::uint32_t most) : m_scale(1.0 / std::log1p(double(most))) {
    m_table.resize(std::min<std::uint32_t>(most, 4096) + 1);
    for (std::uint32_t c = 1; c < m_table.size(); ++c) m_table[c] = compute(c);
  }
  int operator()(std::uint32_t count) const {
    return count < m_table.size() ? m_table[count] : compute(count);
  }

 private:
  int compute(std::uint32_t count) const {
    const double a = 0.12 + 0.88 * std::log1p(double(count)) * m_scale;
    return std::clamp(int(std::lround(255.0 * a)), 0, 255);
  }
  double m_scale;
  std::vector<int> m_table;
};

}  // namespace

QImage density_image(const Eigen::MatrixXd& points, const QTransform& data_to_pixel,
                     const QSize& size, const QColor& ink) {
  check_columns(points, "density points");
  if (size.isEmpty()) return {};
  const int w = size.width(), h = size.height();
  std::vector<std::uint32_t> counts(std::size_t(w) * std::size_t(h), 0);
  std::uint32_t most = 0;
  for_each_binned(points, data_to_pixel, size,
                  [&](std::size_t, std::size_t pixel) { most = std::max(most, ++counts[pixel]); });
  QImage image(size, QImage::Format_ARGB32_Premultiplied);
  image.fill(Qt::transparent);
  if (most == 0) return image;
  const DensityAlpha alpha_of(most);
  for (int y = 0; y < h; ++y) {
    auto* line = reinterpret_cast<QRgb*>(image.scanLine(y));
    const std::uint32_t* row = counts.data() + std::size_t(y) * std::size_t(w);
    for (int x = 0; x < w; ++x) {
      if (row[x] == 0) continue;
      const int alpha = alpha_of(row[x]);
      line[x] = qRgba(ink.red() * alpha / 255, ink.green() * alpha / 255, ink.blue() * alpha / 255,
                      alpha);
    }
  }
  return image;
}

QImage category_density_image(const Eigen::MatrixXd& points, const std::vector<int>& categories,
                              const QTransform& data_to_pixel, const QSize& size) {
  check_columns(points, "density points");
  if (Eigen::Index(categories.size()) != points.rows()) {
    throw ParameterError("categories: " + std::to_string(categories.size()) + " for " +
                         std::to_string(points.rows()) + " points");
  }
  if (size.isEmpty()) return {};
  // The palette once: slot 0 is "other" (−1), slot c + 1 category c (cycling as category_color).
  std::vector<QRgb> palette(std::size_t(kCategoryColors) + 1);
  for (int c = -1; c < kCategoryColors; ++c) palette[std::size_t(c + 1)] = category_color(c).rgb();
  struct Bin {
    std::uint32_t count = 0, r = 0, g = 0, b = 0;
  };
  const int w = size.width(), h = size.height();
  std::vector<Bin> bins(std::size_t(w) * std::size_t(h));
  std::uint32_t most = 0;
  for_each_binned(points, data_to_pixel, size, [&](std::size_t i, std::size_t pixel) {
    const int category = categories[i];
    if (category < -1) return;  // hidden
    Bin& bin = bins[pixel];
    const QRgb colour = palette[std::size_t(category % kCategoryColors + 1)];
    bin.r += std::uint32_t(qRed(colour));
    bin.g += std::uint32_t(qGreen(colour));
    bin.b += std::uint32_t(qBlue(colour));
    most = std::max(most, ++bin.count);
  });
  QImage image(size, QImage::Format_ARGB32_Premultiplied);
  image.fill(Qt::transparent);
  if (most == 0) return image;
  const DensityAlpha alpha_of(most);
  for (int y = 0; y < h; ++y) {
    auto* line = reinterpret_cast<QRgb*>(image.scanLine(y));
    const Bin* row = bins.data() + std::size_t(y) * std::size_t(w);
    for (int x = 0; x < w; ++x) {
      const Bin& bin = row[x];
      if (bin.count == 0) continue;
      const auto alpha = std::uint64_t(alpha_of(bin.count));
      // The mean colour, premultiplied: sum · alpha / (count · 255).
      const std::uint64_t div = std::uint64_t(bin.count) * 255u;
      line[x] = qRgba(int(bin.r * alpha / div), int(bin.g * alpha / div), int(bin.b * alpha / div),
                      int(alpha));
    }
  }
  return image;
}

QTransform map_transform(const Eigen::MatrixXd& coords, const QRectF& rect,
                         const MapPlotOptions& options) {
  const UnitMapping m = panel_mapping(coords, options);
  const QTransform to_unit(m.scale, 0, 0, m.scale, 0.5 - m.cx * m.scale, 0.5 - m.cy * m.scale);
  return to_unit * unit_transform(rect, options);
}

void paint_map(QPainter& painter, const QRectF& rect, const Eigen::MatrixXd& coords,
               const std::vector<int>& segment_starts, const MapPlotOptions& options) {
  const std::vector<int> bounds = clip_bounds(coords, segment_starts);  // validates first
  require_gui_application("paint_map");
  const UnitMapping unit = panel_mapping(coords, options);
  const std::vector<ColoredSegment> segments = segments_in(coords, segment_starts, unit);
  const Layout l = layout_panel(rect, options);
  const QTransform to_px = unit_to_rect(l.data);
  const double lw =
      std::isfinite(options.line_width) ? std::clamp(options.line_width, 0.0, 100.0) : 2.0;
  const bool by_clip = !options.clip_names.isEmpty();
  const bool by_category = !options.point_category.empty();
  check_categories(options, coords.rows());
  // A sample's colour: its category's, its clip's (ramped over the clip's time or flat), or its
  // time's (t: the time within its clip, in [0, 1]).
  const auto sample_color = [&](int sample, int clip, double t) {
    if (by_category) return category_color(options.point_category[std::size_t(sample)]);
    if (!by_clip) return time_color(t);
    return drawn_clip_color(options, clip, t);
  };

  painter.save();
  painter.setRenderHints(QPainter::Antialiasing | QPainter::TextAntialiasing);
  if (options.background.isValid()) painter.fillRect(rect, options.background);

  if (!options.title.isEmpty()) {
    draw_text_line(painter, l.title, options.title, font_px(l.title_px, true), QColor(25, 25, 25));
  }

  painter.setPen(QPen(QColor(150, 150, 150), 1.0));
  painter.setBrush(Qt::NoBrush);
  painter.drawRect(l.box);
  painter.save();  // the data's clip (clip_to_frame), restored before the legend and notes
  if (options.clip_to_frame) painter.setClipRect(l.box, Qt::IntersectClip);

  if (options.backdrop.size() > 0) {
    const double r = std::max(1.0, lw * 0.75);
    painter.setPen(Qt::NoPen);
    painter.setBrush(options.backdrop_color);
    for (Eigen::Index i = 0; i < options.backdrop.rows(); ++i) {
      if (!finite_row(options.backdrop, i)) continue;
      painter.drawEllipse(to_px.map(unit.map(options.backdrop(i, 0), options.backdrop(i, 1))), r,
                          r);
    }
    painter.setBrush(Qt::NoBrush);
  }

  // Trajectory: consecutive segments in the same time bin become one polyline. Clipped to the
  // frame (a zoomed view), each segment is first cut to the frame's box (widened by the pen), so
  // segments thousands of pixels long off the view cost nothing to stroke.
  auto segment_color = [&](const ColoredSegment& s) {
    return by_clip || by_category ? sample_color(s.sample, s.clip, s.time) : s.color;
  };
  // Segments of one polyline share this: their category, or their time bin.
  auto colour_key = [&](const ColoredSegment& s) {
    return by_category ? options.point_category[std::size_t(s.sample)] : time_bin(s.time);
  };
  QPolygonF run;
  if (options.clip_to_frame) {
    const double pad = lw + 2.0;
    const QRectF keep = l.box.adjusted(-pad, -pad, pad, pad);
    QColor run_color;
    int last_sample = -2, run_bin = -1;
    auto flush = [&] {
      if (run.size() >= 2) {
        painter.setPen(QPen(run_color, lw, Qt::SolidLine, Qt::RoundCap, Qt::RoundJoin));
        painter.drawPolyline(run);
      }
      run.clear();
    };
    for (const ColoredSegment& s : segments) {
      QPointF a = to_px.map(s.from), b = to_px.map(s.to);
      if (!clip_segment(a, b, keep)) {
        flush();
        continue;
      }
      // One polyline per time bin, as below (its first segment's colour).
      if (run.isEmpty() || s.sample != last_sample + 1 || colour_key(s) != run_bin ||
          run.back() != a) {
        flush();
        run << a;
        run_color = segment_color(s);
        run_bin = colour_key(s);
      }
      run << b;
      last_sample = s.sample;
    }
    flush();
  }
  for (std::size_t k = 0; !options.clip_to_frame && k < segments.size();) {
    const auto same_colour = [&](std::size_t a, std::size_t b) {
      return colour_key(segments[a]) == colour_key(segments[b]);
    };
    run.clear();
    run << to_px.map(segments[k].from) << to_px.map(segments[k].to);
    std::size_t j = k + 1;
    while (j < segments.size() && segments[j].sample == segments[j - 1].sample + 1 &&
           same_colour(k, j)) {
      run << to_px.map(segments[j].to);
      ++j;
    }
    const QColor color = segment_color(segments[k]);
    painter.setPen(QPen(color, lw, Qt::SolidLine, Qt::RoundCap, Qt::RoundJoin));
    painter.drawPolyline(run);
    k = j;
  }

  bool any_finite = false;
  const double dot_r = std::max(1.0, lw * 1.1);
  const double marker_r = std::max(4.0, lw * 2.5);
  for (std::size_t k = 0; k + 1 < bounds.size(); ++k) {
    const int begin = bounds[k], end = bounds[k + 1];
    int first = -1;
    for (int i = begin; i < end; ++i) {
      if (!finite_row(coords, i)) continue;
      any_finite = true;
      if (first < 0) first = i;
      if (!options.draw_points && !by_category) break;
      painter.setPen(Qt::NoPen);
      painter.setBrush(sample_color(i, static_cast<int>(k), clip_time(i, begin, end)));
      painter.drawEllipse(to_px.map(unit.map(coords(i, 0), coords(i, 1))), dot_r, dot_r);
    }
    if (options.start_marker && first >= 0) {
      painter.setPen(QPen(Qt::black, std::max(1.2, lw * 0.6)));
      painter.setBrush(Qt::white);
      painter.drawEllipse(to_px.map(unit.map(coords(first, 0), coords(first, 1))), marker_r,
                          marker_r);
    }
  }
  painter.restore();
  painter.setBrush(Qt::NoBrush);
  if (!any_finite) {
    draw_text_line(painter, l.box, QStringLiteral("no data"), font_px(l.notes_px),
                   QColor(140, 140, 140));
  }

  if (options.time_legend) {
    if (!options.categories.isEmpty()) {
      draw_category_legend(painter, l.legend, l.notes_px, options);
    } else if (by_clip) {
      draw_clip_legend(painter, l.legend, l.notes_px, options);
    } else {
      draw_time_legend(painter, l.legend, l.notes_px);
    }
  }
  const QFont notes_font = font_px(l.notes_px);
  for (qsizetype k = 0; k < options.notes.size(); ++k) {
    const QRectF line(l.notes.left(), l.notes.top() + k * l.notes_px * 1.35, l.notes.width(),
                      l.notes_px * 1.35);
    draw_text_line(painter, line, options.notes[k], notes_font, QColor(55, 55, 55));
  }
  painter.restore();
}

void save_map_plot(const std::string& path, const Eigen::MatrixXd& coords,
                   const std::vector<int>& segment_starts, const MapPlotOptions& options,
                   int size_px) {
  if (size_px < 16 || size_px > 16384) {
    throw ParameterError("save_map_plot: size_px = " + std::to_string(size_px) +
                         " is outside [16, 16384]");
  }
  clip_bounds(coords, segment_starts);  // invalid data must not leave a half-written file
  if (options.backdrop.size() > 0) check_columns(options.backdrop, "backdrop");
  check_categories(options, coords.rows());
  write_drawing("save_map_plot", path, QSize(size_px, size_px), options.title,
                [&](QPainter& painter, const QRectF& area) {
                  paint_map(painter, area, coords, segment_starts, options);
                });
}

void save_figure(const std::string& path, const std::vector<FigurePanel>& panels, int columns,
                 int panel_px, const QString& title) {
  if (panels.empty()) throw ParameterError("save_figure: no panels");
  if (columns < 1 || columns > 64) {
    throw ParameterError("save_figure: columns = " + std::to_string(columns) +
                         " is outside [1, 64]");
  }
  if (panel_px < 64 || panel_px > 4096) {
    throw ParameterError("save_figure: panel_px = " + std::to_string(panel_px) +
                         " is outside [64, 4096]");
  }
  for (const FigurePanel& p : panels) {
    clip_bounds(p.coords, p.segment_starts);
    if (p.options.backdrop.size() > 0) check_columns(p.options.backdrop, "backdrop");
    check_categories(p.options, p.coords.rows());
  }

  const std::size_t n = panels.size();
  const std::size_t cols = std::min<std::size_t>(columns, n);
  const std::size_t rows = (n + cols - 1) / cols;
  double cell_h = 0.0;
  for (const FigurePanel& p : panels) {
    cell_h = std::max(cell_h, panel_height_for_width(panel_px, p.options));
  }
  const double title_px = 1.1 * std::sqrt(double(panel_px));
  const double legend_px = 0.67 * std::sqrt(double(panel_px));
  const double width = double(cols) * panel_px;
  const MapPlotOptions& first = panels.front().options;
  const bool category_legend = !first.categories.isEmpty();
  const double legend_h =
      category_legend ? legend_px * (1.6 * category_legend_rows(first, width, legend_px) + 0.6)
                      : legend_px * 2.2;
  const double header_h = (title.isEmpty() ? 0.0 : title_px * 1.8) + legend_h + panel_px * 0.02;
  const double height = header_h + rows * cell_h;
  if (width * height > 1e8) {
    throw ParameterError("save_figure: the figure would be " + std::to_string(int(width)) + "x" +
                         std::to_string(static_cast<long long>(height)) +
                         " pixels, more than 10^8");
  }

  write_drawing("save_figure", path, QSize(int(width), int(std::ceil(height))), title,
                [&](QPainter& painter, const QRectF& area) {
                  painter.fillRect(area, Qt::white);
                  painter.setRenderHints(QPainter::Antialiasing | QPainter::TextAntialiasing);
                  double y = area.top() + panel_px * 0.02;
                  if (!title.isEmpty()) {
                    draw_text_line(painter, QRectF(0, y, width, title_px * 1.8), title,
                                   font_px(title_px, true), QColor(20, 20, 20));
                    y += title_px * 1.8;
                  }
                  if (category_legend) {
                    draw_category_legend(painter, QRectF(0, y, width, legend_h), legend_px, first);
                  } else if (!first.clip_names.isEmpty()) {
                    draw_clip_legend(painter, QRectF(0, y, width, legend_h), legend_px, first);
                  } else {
                    draw_time_legend(painter, QRectF(0, y, width, legend_px * 2.2), legend_px);
                  }
                  for (std::size_t i = 0; i < n; ++i) {
                    const FigurePanel& p = panels[i];
                    // Each panel exactly as tall as it needs, at the top of its cell, so the
                    // boxes of a row line up even when the panels carry different notes.
                    const QRectF cell((i % cols) * double(panel_px), header_h + (i / cols) * cell_h,
                                      panel_px, panel_height_for_width(panel_px, p.options));
                    paint_map(painter, cell, p.coords, p.segment_starts, p.options);
                  }
                });
}

}  // namespace motionmap::render
