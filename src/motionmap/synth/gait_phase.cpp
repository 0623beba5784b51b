#include "motionmap/synth/detail/gait_phase.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "motionmap/synth/detail/smoothing.h"

namespace motionmap::synth::detail {

namespace {

// x wrapped to [−0.5, 0.5] cycles.
double wrap(double x) {
  return x - std::round(x);
}

constexpr double kPi = std::numbers::pi;

// A frame's sources with a phase and a weight: index, phase, |weight|.
struct Phased {
  std::size_t index = 0;
  double phase = 0.0, magnitude = 0.0;
};

// What the registration reads of a frame (see the top of gait_phase.h).
struct Lead {
  std::vector<Phased> sources;
  double phase = 0.0, clarity = 0.0, cadence = 0.0;
  // Per run: the sources' weight on it and the phase of the heaviest one.
  struct Run {
    int run = 0;
    double weight = 0.0, phase = 0.0, heaviest = 0.0;
  };
  std::vector<Run> runs;
};

Lead lead_of(const PhaseFrame& frame, const PhaseOf& phase_of) {
  Lead out;
  double x = 0.0, y = 0.0, total = 0.0, rates = 0.0;
  for (std::size_t i = 0; i < frame.sources.size(); ++i) {
    const PhaseSource& src = frame.sources[i];
    const GaitPhase& p = phase_of(src.run);
    if (!p.known() || src.weight == 0.0) continue;
    double rate = 0.0;
    const double phase = p.at(src.seconds, &rate), w = std::abs(src.weight);
    out.sources.push_back({i, phase, w});
    auto run = std::find_if(out.runs.begin(), out.runs.end(),
                            [&](const Lead::Run& r) { return r.run == src.run; });
    if (run == out.runs.end()) run = out.runs.insert(out.runs.end(), {src.run});
    run->weight += src.weight;
    if (w > run->heaviest) {
      run->heaviest = w;
      run->phase = phase;
    }
    x += w * std::cos(2.0 * kPi * phase);
    y += w * std::sin(2.0 * kPi * phase);
    total += w;
    rates += w * rate;
  }
  if (total > 0.0) {
    out.phase = std::atan2(y, x) / (2.0 * kPi);
    out.clarity = std::hypot(x, y) / total;
    out.cadence = rates / total;
  }
  return out;
}

// How fast the leads of frames [lo, …) move on at frame k: the sum of their steps over the
// frames within `reach` of k that have one, against k's cadence (PhaseFrame::lead_pace); NaN
// where they jump about rather than step (their median step, per frame, over kLeadJumpy × the
// cadence's: a mix of phases, not legs held).
double lead_advance(const std::vector<Lead>& leads, std::size_t lo, std::size_t k,
                    std::size_t reach, double dt, std::vector<double>& steps) {
  const Lead& own = leads[k - lo];
  const std::size_t a = std::max(lo, k > reach ? k - reach : 0);
  const std::size_t b = std::min(lo + leads.size(), k + reach + 1);
  double advance = 0.0;
  std::size_t frames = 0, previous = b;
  steps.clear();
  for (std::size_t j = a; j < b; ++j) {
    if (leads[j - lo].sources.empty()) continue;
    if (previous < b) {
      const double step = wrap(leads[j - lo].phase - leads[previous - lo].phase);
      advance += step;
      frames += j - previous;
      steps.push_back(std::abs(step) / static_cast<double>(j - previous));
    }
    previous = j;
  }
  if (frames == 0 || !(own.cadence > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  const auto middle = steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2);
  std::nth_element(steps.begin(), middle, steps.end());
  if (*middle > kLeadJumpy * own.cadence * dt) return std::numeric_limits<double>::quiet_NaN();
  return std::clamp(advance / (static_cast<double>(frames) * dt * own.cadence), 0.0, kMaxPace);
}

// The second pass of register_phases(): frame k's weight on each run with a phase becomes the
// mean of the weights of the frames within `reach` of it on that run (a triangle; from `leads`,
// frames [lo, …) as located: the registration moves sources within their runs), scaled to k's
// own total. The difference goes, by k's registration h, to that run's time of k's phase φ, in
// the cycle nearest the run's heaviest source at the nearest frame on it; by 1 − h to that
// source's phase carried on at k's cadence.
void smooth_shares(std::span<PhaseFrame> frames, std::size_t first, std::size_t end, std::size_t lo,
                   const std::vector<Lead>& leads, std::size_t reach, double dt,
                   const PhaseOf& phase_of) {
  if (reach == 0) return;
  struct Mean {
    int run = 0;
    double weight = 0.0, phase = 0.0;
    double offset = 0.0;  // of the nearest frame on the run (frames, signed), whose `phase` it is
  };
  std::vector<Mean> mean;
  for (std::size_t k = first; k < end; ++k) {
    const std::vector<Lead::Run>& own = leads[k - lo].runs;
    if (own.empty()) continue;
    mean.clear();
    const std::size_t a = std::max(lo, k > reach ? k - reach : 0);
    const std::size_t b = std::min(lo + leads.size(), k + reach + 1);
    double norm = 0.0;
    for (std::size_t j = a; j < b; ++j) {
      const double offset = static_cast<double>(j) - static_cast<double>(k);
      const double t = 1.0 - std::abs(offset) / static_cast<double>(reach + 1);
      norm += t;
      for (const Lead::Run& r : leads[j - lo].runs) {
        auto it =
            std::find_if(mean.begin(), mean.end(), [&](const Mean& m) { return m.run == r.run; });
        if (it == mean.end()) {
          it = mean.insert(mean.end(), {r.run, 0.0, r.phase, offset});
        } else if (std::abs(offset) < std::abs(it->offset)) {
          it->phase = r.phase;
          it->offset = offset;
        }
        it->weight += t * r.weight;
      }
    }
    double own_total = 0.0, mean_total = 0.0;
    for (const Lead::Run& r : own) own_total += r.weight;
    for (const Mean& m : mean) mean_total += m.weight / norm;
    if (!(std::abs(mean_total) > 1e-9)) continue;
    PhaseFrame& f = frames[k];
    const double h = std::isnan(f.phase) ? 0.0 : f.registered;
    for (const Mean& m : mean) {
      const auto on =
          std::find_if(own.begin(), own.end(), [&](const Lead::Run& r) { return r.run == m.run; });
      const double change =
          m.weight / norm * own_total / mean_total - (on == own.end() ? 0.0 : on->weight);
      if (std::abs(change) <= kShareTolerance) continue;
      const GaitPhase& p = phase_of(m.run);
      if (h < 1.0) {
        const double carried = m.phase - m.offset * dt * f.cadence;
        f.sources.push_back({m.run, p.time_inside(carried), (1.0 - h) * change});
      }
      if (h > 0.0)
        f.sources.push_back({m.run, p.time_inside(m.phase + wrap(f.phase - m.phase)), h * change});
      f.moved = true;
    }
  }
}

}  // namespace

double GaitPhase::at(double seconds, double* rate) const {
  // The cycle [strikes[i], strikes[i + 1]] holding `seconds`, the first or last beyond the ends.
  const auto above = std::upper_bound(strikes.begin(), strikes.end(), seconds) - strikes.begin();
  const auto i = static_cast<std::size_t>(
      std::clamp<std::ptrdiff_t>(above, 1, static_cast<std::ptrdiff_t>(strikes.size()) - 1) - 1);
  if (!right.empty() && seconds >= strikes[i] && seconds <= strikes[i + 1]) {
    const double r = right[i];
    const bool first = seconds < r;
    const double from = first ? strikes[i] : r, to = first ? r : strikes[i + 1];
    if (rate != nullptr) *rate = 0.5 / (to - from);
    return static_cast<double>(i) + (first ? 0.0 : 0.5) + 0.5 * (seconds - from) / (to - from);
  }
  const double length = strikes[i + 1] - strikes[i];
  if (rate != nullptr) *rate = 1.0 / length;
  return static_cast<double>(i) + (seconds - strikes[i]) / length;
}

double GaitPhase::time_at(double phase) const {
  const auto i = static_cast<std::size_t>(
      std::clamp(std::floor(phase), 0.0, static_cast<double>(strikes.size()) - 2.0));
  const double f = phase - static_cast<double>(i);
  if (!right.empty() && f >= 0.0 && f <= 1.0) {
    const double r = right[i];
    return f < 0.5 ? strikes[i] + 2.0 * f * (r - strikes[i])
                   : r + 2.0 * (f - 0.5) * (strikes[i + 1] - r);
  }
  return strikes[i] + f * (strikes[i + 1] - strikes[i]);
}

GaitPhase gait_phase(const std::array<FootContacts, 2>& contacts, double frame_time, int start,
                     double duration) {
  std::array<std::vector<int>, 2> strikes;
  for (int side = 0; side < 2; ++side) {
    for (const ContactInterval& contact : contacts[static_cast<std::size_t>(side)].intervals) {
      if (contact.first > 0) strikes[static_cast<std::size_t>(side)].push_back(contact.first);
    }
  }
  const std::vector<int>& left = strikes[0];
  const std::vector<int>& right = strikes[1];
  // Whether left strikes i and i + 1 bound a gait cycle.
  const auto cycle = [&](std::size_t i) {
    if (static_cast<double>(left[i + 1] - left[i]) * frame_time > kMaxCycleSeconds) return false;
    const auto r = std::upper_bound(right.begin(), right.end(), left[i]);
    return r != right.end() && *r < left[i + 1];
  };
  // The longest run of cycles in a row: strikes [best, best + length].
  std::size_t best = 0, length = 0;
  for (std::size_t i = 0; i + 1 < left.size();) {
    std::size_t j = i;
    while (j + 1 < left.size() && cycle(j)) ++j;
    if (j - i > length) {
      best = i;
      length = j - i;
    }
    i = j + 1;
  }
  GaitPhase out;
  out.duration = duration;
  if (length < static_cast<std::size_t>(kMinCycles)) return out;
  for (std::size_t i = best; i <= best + length; ++i) {
    out.strikes.push_back(static_cast<double>(left[i] - start) * frame_time);
    if (i < best + length)
      out.right.push_back(
          static_cast<double>(*std::upper_bound(right.begin(), right.end(), left[i]) - start) *
          frame_time);
  }
  return out;
}

double GaitPhase::time_inside(double phase) const {
  double t = time_at(phase);
  while (t < 0.0) {
    const double next = time_at(phase + 1.0);
    if (next > duration) break;
    phase += 1.0;
    t = next;
  }
  while (t > duration) {
    const double before = time_at(phase - 1.0);
    if (before < 0.0) break;
    phase -= 1.0;
    t = before;
  }
  return std::clamp(t, 0.0, duration);
}

int phase_window(double dt) {
  return static_cast<int>(std::llround(std::min(kPhaseWindowSeconds / dt, 1e9)));
}

int pace_window(double dt) {
  return phase_window(dt) + kPaceFrames;
}

double pace(std::span<const PhaseFrame> frames, std::size_t k, double dt) {
  const PhaseFrame& own = frames[k];
  if (std::isnan(own.phase) || !(own.cadence > 0.0)) return 1.0;
  const auto known = [&](std::size_t j) {
    return j < frames.size() && !std::isnan(frames[j].phase);
  };
  const std::size_t before = k >= kPaceFrames && known(k - kPaceFrames) ? k - kPaceFrames : k;
  const std::size_t after = known(k + kPaceFrames) ? k + kPaceFrames : k;
  if (before == after) return 1.0;
  const double advance = wrap(frames[after].phase - frames[before].phase);
  const double rate = advance / (static_cast<double>(after - before) * dt * own.cadence);
  const double h = own.registered;
  return h * std::clamp(rate, 0.0, kMaxPace) + (1.0 - h);
}

double lead_pace(std::span<const PhaseFrame> frames, std::size_t k) {
  const PhaseFrame& f = frames[k];
  return f.registered < 0.5 && !std::isnan(f.lead_pace) ? f.lead_pace : 1.0;
}

void register_phases(std::span<PhaseFrame> frames, std::size_t first, std::size_t end, double dt,
                     const PhaseOf& phase_of) {
  const std::size_t count = frames.size();
  const auto window = static_cast<std::size_t>(phase_window(dt));
  const std::size_t lo = first > window ? first - window : 0;
  const std::size_t hi = std::min(count, end + window);
  std::vector<Lead> leads(hi - lo);
  for (std::size_t j = lo; j < hi; ++j) leads[j - lo] = lead_of(frames[j], phase_of);
  const auto within = [&](double seconds) {
    return std::min(window, static_cast<std::size_t>(std::lround(seconds / dt)));
  };
  const std::size_t lead_reach = within(kLeadPaceSeconds);
  std::vector<double> carried, weight, steps;
  for (std::size_t k = first; k < end; ++k) {
    const Lead& own = leads[k - lo];
    if (own.sources.empty()) continue;
    frames[k].lead_pace = lead_advance(leads, lo, k, lead_reach, dt, steps);
    // The window's leads carried to frame k at their cadence: r_j = ψ_j − ∫_k^j ω, weighted.
    const std::size_t a = std::max(lo, k > window ? k - window : 0);
    const std::size_t b = std::min(hi, k + window + 1);
    carried.assign(b - a, 0.0);
    for (std::size_t j = k + 1; j < b; ++j) {
      carried[j - a] =
          carried[j - 1 - a] + 0.5 * (leads[j - 1 - lo].cadence + leads[j - lo].cadence) * dt;
    }
    for (std::size_t j = k; j-- > a;) {
      carried[j - a] =
          carried[j + 1 - a] - 0.5 * (leads[j + 1 - lo].cadence + leads[j - lo].cadence) * dt;
    }
    double x = 0.0, y = 0.0, total = 0.0;
    weight.assign(b - a, 0.0);
    for (std::size_t j = a; j < b; ++j) {
      const Lead& l = leads[j - lo];
      const double span = static_cast<double>(window + 1);
      const double w = (1.0 - static_cast<double>(j > k ? j - k : k - j) / span) * l.clarity;
      if (!(w > 0.0)) continue;
      weight[j - a] = w;
      x += w * std::cos(2.0 * kPi * (l.phase - carried[j - a]));
      y += w * std::sin(2.0 * kPi * (l.phase - carried[j - a]));
      total += w;
    }
    if (!(total > 0.0)) continue;
    const double h = 1.0 - falloff((std::hypot(x, y) / total - kPhaseVague) / kPhaseVague);
    frames[k].cadence = own.cadence;
    frames[k].registered = h;
    if (!(h > 0.0)) continue;
    // φ: their mean on the circle, and a line fitted to them about it (weighted least squares
    // in time), at frame k: a path that leads faster or slower than the cadence leads where the
    // window is cut short (at the path's ends) too.
    const double mean = std::atan2(y, x) / (2.0 * kPi);
    double sw = 0.0, st = 0.0, sr = 0.0, stt = 0.0, str = 0.0;
    for (std::size_t j = a; j < b; ++j) {
      const double w = weight[j - a];
      if (w == 0.0) continue;
      const double t = static_cast<double>(j) - static_cast<double>(k);
      const double r = wrap(leads[j - lo].phase - carried[j - a] - mean);
      sw += w;
      st += w * t;
      sr += w * r;
      stt += w * t * t;
      str += w * t * r;
    }
    const double det = sw * stt - st * st;
    const double at_k = det > 1e-12 * sw * sw ? (sr * stt - st * str) / det : sr / sw;
    const double phi = mean + at_k;
    frames[k].phase = phi;
    // Each source to within kPhaseBand of φ, in its own cycle (sharing with the other one's time
    // nearly half a cycle off), by h; as it was by 1 − h.
    PhaseFrame& f = frames[k];
    std::vector<PhaseSource> moved;
    for (const Phased& src : own.sources) {
      const double off = wrap(src.phase - phi), distance = std::abs(off);
      if (distance <= kPhaseBand) continue;
      PhaseSource& s = f.sources[src.index];
      const GaitPhase& p = phase_of(s.run);
      const double split = 0.5 * (1.0 - falloff((distance - kPhaseSplit) / (0.5 - kPhaseSplit)));
      const double w = h * s.weight;
      moved.push_back({s.run, p.time_inside(src.phase - std::copysign(distance - kPhaseBand, off)),
                       (1.0 - split) * w});
      if (split > 0.0) {
        moved.push_back(
            {s.run,
             p.time_inside(src.phase +
                           std::copysign(std::max(1.0 - distance - kPhaseBand, 0.0), off)),
             split * w});
      }
      s.weight -= w;
    }
    if (moved.empty()) continue;
    std::erase_if(f.sources, [](const PhaseSource& s) { return s.weight == 0.0; });
    f.sources.insert(f.sources.end(), moved.begin(), moved.end());
    f.moved = true;
  }
  smooth_shares(frames, first, end, lo, leads, within(kShareSeconds), dt, phase_of);
}

}  // namespace motionmap::synth::detail
