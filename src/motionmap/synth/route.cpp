#include "motionmap/synth/route.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <queue>
#include <string>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/synth/detail/point_tree.h"

namespace motionmap::synth {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Where a point is pulled into the data: this fraction of the reach from its nearest sample.
constexpr double kPullFraction = 0.9;
// A segment's cost is integrated at steps of at most reach / kCheckSteps.
constexpr double kCheckSteps = 8.0;
// Most steps a segment's cost is integrated in (a map whose reach is tiny beside its extent).
constexpr double kMaxSteps = 1e5;
// How often a segment is halved to show it valid (to 2⁻⁴⁰ of its length).
constexpr int kValidDepth = 40;
// How often an invalid segment may be split at its pulled midpoint.
constexpr int kRepairDepth = 12;
constexpr int kChaikinRounds = 2;

}  // namespace

void RouteOptions::validate() const {
  if (grid != 0 && (grid < 2 || grid > kMaxGridOption)) {
    throw ParameterError("grid: " + std::to_string(grid) +
                         " cells is out of range (must be 0 = from the map's density, or in [2, " +
                         std::to_string(kMaxGridOption) + "])");
  }
}

struct MapField::Tree : detail::PointTree {
  using PointTree::PointTree;
};

MapField::MapField(const MapBlender& blender)
    : MapField(
          [&] {
            std::vector<Eigen::Vector2d> points(static_cast<std::size_t>(blender.num_samples()));
            for (int i = 0; i < blender.num_samples(); ++i) points[i] = blender.sample_point(i);
            return points;
          }(),
          blender.reach_distance()) {
  m_gp = blender.options().gplvm;
}

MapField::MapField(std::vector<Eigen::Vector2d> points, double reach_distance)
    : m_reach(reach_distance) {
  if (points.empty()) throw ParameterError("route: the map has no samples");
  if (!(reach_distance > 0.0) || !std::isfinite(reach_distance)) {
    throw ParameterError("reach: the reach distance " + format_number(reach_distance) +
                         " is not a finite number > 0 (a map whose samples never move has no "
                         "routes)");
  }
  m_min = m_max = points.front();
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) {
      throw ParameterError("route: sample " + std::to_string(i) + " has a non-finite map point");
    }
    m_min = m_min.cwiseMin(points[i]);
    m_max = m_max.cwiseMax(points[i]);
  }
  m_tree = std::make_unique<Tree>(std::move(points));
  m_tree->index.buildIndex();
}

MapField::~MapField() = default;
MapField::MapField(MapField&&) noexcept = default;
MapField& MapField::operator=(MapField&&) noexcept = default;

int MapField::num_samples() const {
  return static_cast<int>(m_tree->set.points.size());
}

const Eigen::Vector2d& MapField::sample(int i) const {
  return m_tree->set.points[static_cast<std::size_t>(i)];
}

double MapField::distance(const Eigen::Vector2d& p, int* nearest) const {
  std::uint32_t idx = 0;
  double d2 = 0.0;
  m_tree->index.knnSearch(p.data(), 1, &idx, &d2);
  if (nearest) *nearest = static_cast<int>(idx);
  return std::sqrt(d2);
}

int MapField::nearest(const Eigen::Vector2d& p, int k, std::vector<int>& indices) const {
  const std::size_t want =
      std::min<std::size_t>(static_cast<std::size_t>(std::max(k, 0)), m_tree->set.points.size());
  std::vector<std::uint32_t> idx(want);
  std::vector<double> d2(want);
  const std::size_t found =
      want == 0 ? 0 : m_tree->index.knnSearch(p.data(), want, idx.data(), d2.data());
  indices.assign(idx.begin(), idx.begin() + static_cast<std::ptrdiff_t>(found));
  return static_cast<int>(found);
}

bool MapField::valid(const Eigen::Vector2d& p) const {
  if (m_gp) return m_gp->inside(p);
  return distance(p) <= m_reach;
}

double MapField::cost(const Eigen::Vector2d& p) const {
  if (m_gp) {
    const double v = m_gp->variance(p), tau = m_gp->threshold();
    if (!(v <= tau)) return kInf;
    return 1.0 + kRoutePenalty * (v / tau) * (v / tau);
  }
  const double d = distance(p);
  if (!(d <= m_reach)) return kInf;
  const double u = d / m_reach;
  return 1.0 + kRoutePenalty * u * u;
}

bool MapField::segment_valid(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const {
  if (m_gp) {
    // The variance changes on the scale ℓ: checked at steps of ℓ/8.
    const int steps = static_cast<int>(std::clamp(
        std::ceil((b - a).norm() / (m_gp->lengthscale() / kCheckSteps)), 1.0, kMaxSteps));
    for (int s = 0; s <= steps; ++s) {
      const double t = double(s) / steps;
      if (!m_gp->inside((1.0 - t) * a + t * b)) return false;
    }
    return true;
  }
  const double da = distance(a), db = distance(b);
  return da <= m_reach && db <= m_reach && interval_valid(a, da, b, db, kValidDepth);
}

// The distance to the samples is 1-Lipschitz, so on the segment p–q it is at most
// (d(p) + d(q) + |p − q|) / 2: where that bound is within the reach the segment is valid; where
// not, its midpoint is checked and both halves are, down to kValidDepth halvings.
Eigen::Vector2d MapField::pulled_in(const Eigen::Vector2d& p) const {
  int nearest = 0;
  const double d = distance(p, &nearest);
  const Eigen::Vector2d s = sample(nearest);
  if (!m_gp) return d <= m_reach ? p : Eigen::Vector2d(s + (p - s) * (kPullFraction * m_reach / d));
  if (m_gp->inside(p)) return p;
  if (!m_gp->inside(s)) return s;
  return s + kPullFraction * m_gp->edge_fraction(s, p) * (p - s);
}

bool MapField::interval_valid(const Eigen::Vector2d& p, double dp, const Eigen::Vector2d& q,
                              double dq, int depth) const {
  if (0.5 * (dp + dq + (q - p).norm()) <= m_reach) return true;
  if (depth == 0) return false;
  const Eigen::Vector2d m = 0.5 * (p + q);
  const double dm = distance(m);
  return dm <= m_reach && interval_valid(p, dp, m, dm, depth - 1) &&
         interval_valid(m, dm, q, dq, depth - 1);
}

double MapField::segment_cost(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const {
  if (!valid(a) || !valid(b)) return kInf;
  const double length = (b - a).norm();
  if (length == 0.0) return 0.0;
  const int steps =
      static_cast<int>(std::clamp(std::ceil(length * kCheckSteps / m_reach), 1.0, kMaxSteps));
  double sum = 0.0;
  for (int s = 0; s < steps; ++s) {
    const double t = (s + 0.5) / steps;
    sum += cost((1.0 - t) * a + t * b);
  }
  return std::isfinite(sum) ? sum * length / steps : kInf;
}

// ---- the grid ---------------------------------------------------------------------------------

int RouteGrid::cell_of(const Eigen::Vector2d& p) const {
  const int x = std::clamp(static_cast<int>(std::floor((p.x() - origin.x()) / cell)), 0, nx - 1);
  const int y = std::clamp(static_cast<int>(std::floor((p.y() - origin.y()) / cell)), 0, ny - 1);
  return index(x, y);
}

bool RouteGrid::passable(int c) const {
  return std::isfinite(cost[static_cast<std::size_t>(c)]);
}

RouteGrid make_grid(const MapField& field, const RouteOptions& options) {
  options.validate();
  const double r = field.reach_distance();
  RouteGrid g;
  g.origin = field.min() - Eigen::Vector2d::Constant(r);
  const Eigen::Vector2d extent = field.max() - field.min() + Eigen::Vector2d::Constant(2 * r);
  const double longer = extent.maxCoeff();
  const int cells =
      options.grid > 0 ? options.grid
                       : static_cast<int>(std::clamp(std::ceil(longer / (0.5 * r)),
                                                     double(kMinGridCells), double(kMaxGridCells)));
  g.cell = longer / cells;
  g.nx = std::max(1, static_cast<int>(std::ceil(extent.x() / g.cell - 1e-9)));
  g.ny = std::max(1, static_cast<int>(std::ceil(extent.y() / g.cell - 1e-9)));
  const auto n = static_cast<std::size_t>(g.nx) * static_cast<std::size_t>(g.ny);
  g.cost.assign(n, kInf);
  g.gap_cost.assign(n, kInf);
  g.node.resize(n);
  std::vector<char> holds(n, 0);
  for (int i = 0; i < field.num_samples(); ++i)
    holds[static_cast<std::size_t>(g.cell_of(field.sample(i)))] = 1;
  for (int y = 0; y < g.ny; ++y) {
    for (int x = 0; x < g.nx; ++x) {
      const auto c = static_cast<std::size_t>(g.index(x, y));
      const Eigen::Vector2d centre = g.origin + g.cell * Eigen::Vector2d(x + 0.5, y + 0.5);
      int nearest = 0;
      const double d = field.distance(centre, &nearest);
      Eigen::Vector2d node = centre;
      if (!field.valid(centre)) {
        if (!holds[c]) {
          // Impassable: only a route across a gap in the data goes through it.
          const double u = d / r;
          g.node[c] = centre;
          g.gap_cost[c] = kGapPenalty * (1.0 + kRoutePenalty * u * u);
          continue;
        }
        node = field.pulled_in(centre);
      }
      g.node[c] = node;
      g.cost[c] = g.gap_cost[c] = field.cost(node);
    }
  }
  return g;
}

double polyline_length(std::span<const Eigen::Vector2d> points) {
  double length = 0.0;
  for (std::size_t i = 1; i < points.size(); ++i) length += (points[i] - points[i - 1]).norm();
  return length;
}

namespace {

// The passable cell whose node is nearest p: p's own cell when passable, else the nearest node.
int entry_cell(const RouteGrid& g, const Eigen::Vector2d& p) {
  const int own = g.cell_of(p);
  if (g.passable(own)) return own;
  int best = -1;
  double best_d = kInf;
  for (int c = 0; c < static_cast<int>(g.cost.size()); ++c) {
    if (!g.passable(c)) continue;
    const double d = (g.node[static_cast<std::size_t>(c)] - p).squaredNorm();
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  return best;
}

// A* over the 8-connected passable cells (with `cross`, every cell at its gap cost) from cell
// `from` to cell `to`; the cells in order, or empty when none joins them.
std::vector<int> grid_path(const RouteGrid& g, int from, int to, bool cross) {
  const std::vector<double>& cost = cross ? g.gap_cost : g.cost;
  const std::size_t n = g.cost.size();
  std::vector<double> dist(n, kInf);
  std::vector<int> prev(n, -1);
  std::vector<char> done(n, 0);
  const Eigen::Vector2d goal = g.node[static_cast<std::size_t>(to)];
  using Item = std::pair<double, int>;  // (g + h, cell)
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  dist[static_cast<std::size_t>(from)] = 0.0;
  open.emplace((g.node[static_cast<std::size_t>(from)] - goal).norm(), from);
  while (!open.empty()) {
    const int c = open.top().second;
    open.pop();
    const auto cs = static_cast<std::size_t>(c);
    if (done[cs]) continue;
    done[cs] = 1;
    if (c == to) break;
    const int cx = c % g.nx, cy = c / g.nx;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if (dx == 0 && dy == 0) continue;
        const int x = cx + dx, y = cy + dy;
        if (x < 0 || y < 0 || x >= g.nx || y >= g.ny) continue;
        const int e = g.index(x, y);
        const auto es = static_cast<std::size_t>(e);
        if (done[es] || !std::isfinite(cost[es])) continue;
        const double step = (g.node[es] - g.node[cs]).norm() * 0.5 * (cost[cs] + cost[es]);
        const double nd = dist[cs] + step;
        if (nd < dist[es]) {
          dist[es] = nd;
          prev[es] = c;
          open.emplace(nd + (g.node[es] - goal).norm(), e);
        }
      }
    }
  }
  if (!done[static_cast<std::size_t>(to)]) return {};
  std::vector<int> cells;
  for (int c = to; c >= 0; c = prev[static_cast<std::size_t>(c)]) cells.push_back(c);
  std::reverse(cells.begin(), cells.end());
  return cells;
}

Eigen::Vector2d pull_in(const MapField& field, const Eigen::Vector2d& p) {
  return field.pulled_in(p);
}

// Appends the segment a–b (without a) to `out`, split at pulled midpoints where it leaves the
// valid region between two valid ends.
void append_repaired(const MapField& field, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                     int depth, std::vector<Eigen::Vector2d>& out) {
  if (depth > 0 && field.valid(a) && field.valid(b) && !field.segment_valid(a, b)) {
    const Eigen::Vector2d m = pull_in(field, 0.5 * (a + b));
    append_repaired(field, a, m, depth - 1, out);
    append_repaired(field, m, b, depth - 1, out);
    return;
  }
  out.push_back(b);
}

std::vector<Eigen::Vector2d> repaired(const MapField& field,
                                      const std::vector<Eigen::Vector2d>& p) {
  std::vector<Eigen::Vector2d> out{p.front()};
  for (std::size_t i = 1; i < p.size(); ++i)
    append_repaired(field, p[i - 1], p[i], kRepairDepth, out);
  return out;
}

// String pulling: from each kept vertex, jump to the farthest following vertex whose straight
// line is valid and costs no more than the stretch it replaces (stops at the first that is not).
std::vector<Eigen::Vector2d> pulled(const MapField& field, const std::vector<Eigen::Vector2d>& p) {
  const std::size_t n = p.size();
  std::vector<double> segment(n, 0.0);  // segment[i]: cost of p[i−1]–p[i]
  for (std::size_t i = 1; i < n; ++i) segment[i] = field.segment_cost(p[i - 1], p[i]);
  std::vector<Eigen::Vector2d> out{p.front()};
  std::size_t i = 0;
  while (i + 1 < n) {
    std::size_t next = i + 1;
    double along = segment[i + 1];
    for (std::size_t j = i + 2; j < n; ++j) {
      along += segment[j];
      if (!std::isfinite(along)) break;
      const double direct = field.segment_cost(p[i], p[j]);
      if (!(direct <= along * (1.0 + 1e-12)) || !field.segment_valid(p[i], p[j])) break;
      next = j;
    }
    out.push_back(p[next]);
    i = next;
  }
  return out;
}

// Chaikin corner cutting with the ends kept; a corner whose cut would leave the valid region
// (where the corner's own two segments were valid) is kept.
std::vector<Eigen::Vector2d> chaikin(const MapField& field, const std::vector<Eigen::Vector2d>& p) {
  const std::size_t n = p.size();
  if (n < 3) return p;
  std::vector<Eigen::Vector2d> out{p.front()};
  for (std::size_t i = 1; i + 1 < n; ++i) {
    // The corner at p[i], cut from R (¾ along the segment before it) to Q (¼ along the next).
    const Eigen::Vector2d r = 0.25 * p[i - 1] + 0.75 * p[i];
    const Eigen::Vector2d q = 0.75 * p[i] + 0.25 * p[i + 1];
    const bool corner_valid = field.segment_valid(r, p[i]) && field.segment_valid(p[i], q);
    out.push_back(r);
    if (corner_valid && !field.segment_valid(r, q)) out.push_back(p[i]);
    out.push_back(q);
  }
  out.push_back(p.back());
  return out;
}

// Consecutive repeated points dropped (the ends stay).
std::vector<Eigen::Vector2d> deduplicated(const std::vector<Eigen::Vector2d>& p) {
  std::vector<Eigen::Vector2d> out{p.front()};
  for (std::size_t i = 1; i + 1 < p.size(); ++i) {
    if (p[i] != out.back()) out.push_back(p[i]);
  }
  if (p.size() > 1) {
    if (out.size() > 1 && out.back() == p.back()) out.pop_back();
    out.push_back(p.back());
  }
  return out;
}

}  // namespace

std::vector<Eigen::Vector2d> find_route(const MapField& field, const RouteGrid& grid,
                                        const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                        const RouteOptions& options) {
  options.validate();
  if (!a.allFinite() || !b.allFinite())
    throw ParameterError("route: a key's map point is not finite");
  std::vector<Eigen::Vector2d> raw{a};
  if (!(field.segment_valid(a, b) && grid.cell_of(a) == grid.cell_of(b))) {
    const int from = entry_cell(grid, a), to = entry_cell(grid, b);
    if (from < 0 || to < 0) throw ParameterError("route: the map's grid has no passable cell");
    std::vector<int> cells = grid_path(grid, from, to, false);
    if (cells.empty() && options.cross_gaps) cells = grid_path(grid, from, to, true);
    if (cells.empty()) {
      throw ParameterError(
          "route: no route through the valid region joins the map points " + format_number(a.x()) +
          "," + format_number(a.y()) + " and " + format_number(b.x()) + "," + format_number(b.y()) +
          ": the data between them is cut (farther apart than the reach " +
          format_number(field.reach_distance()) +
          "); a larger --reach joins more of the map, and cross_gaps crosses the gap");
    }
    for (int c : cells) raw.push_back(grid.node[static_cast<std::size_t>(c)]);
  }
  raw.push_back(b);
  std::vector<Eigen::Vector2d> route = repaired(field, deduplicated(raw));
  if (options.smooth && route.size() > 2) {
    route = pulled(field, route);
    for (int round = 0; round < kChaikinRounds; ++round) route = chaikin(field, route);
    route = repaired(field, deduplicated(route));
  }
  return route;
}

}  // namespace motionmap::synth
