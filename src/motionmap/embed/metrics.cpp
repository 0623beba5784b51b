#include "motionmap/embed/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "motionmap/core/error.h"
#include "motionmap/core/parallel.h"
#include "motionmap/core/stats.h"
#include "motionmap/embed/neighbors.h"

namespace motionmap::embed {

namespace {

constexpr int kRowsPerChunk = 64;

// Σ term(i) over i < m for K terms at once, each summed exactly as Eigen sums a vectorised
// expression of m doubles with 2-double packets: two packet accumulators over blocks of 4
// elements, then the last whole packet, then the packet's two lanes, then the odd element. One
// pass gives what K separate .sum() calls over K temporary arrays gave, bit for bit.
// pair(i, v) writes the K terms of elements i and i + 1 as packets, one(i, v) those of element i.
#if defined(__SSE2__)
template <int K, class Pair, class One>
void packet_sums(Eigen::Index m, const Pair& pair, const One& one, double* out) {
  if (m < 2) {
    one(0, out);
    return;
  }
  const Eigen::Index packets = m & ~Eigen::Index(1), blocks = m & ~Eigen::Index(3);
  __m128d a[K], b[K], v[K];
  Eigen::Index i = 0;
  pair(0, a);
  if (packets > 2) {
    pair(2, b);
    for (i = 4; i < blocks; i += 4) {
      pair(i, v);
      for (int k = 0; k < K; ++k) a[k] = _mm_add_pd(a[k], v[k]);
      pair(i + 2, v);
      for (int k = 0; k < K; ++k) b[k] = _mm_add_pd(b[k], v[k]);
    }
    for (int k = 0; k < K; ++k) a[k] = _mm_add_pd(a[k], b[k]);
    if (packets > i) {
      pair(i, v);
      for (int k = 0; k < K; ++k) a[k] = _mm_add_pd(a[k], v[k]);
      i += 2;
    }
  } else {
    i = 2;
  }
  for (int k = 0; k < K; ++k) {
    alignas(16) double lanes[2];
    _mm_store_pd(lanes, a[k]);
    out[k] = lanes[0] + lanes[1];
  }
  if (i < m) {
    double last[K];
    one(i, last);
    for (int k = 0; k < K; ++k) out[k] += last[k];
  }
}
#endif

void check_pair(const Eigen::MatrixXd& T, const Eigen::MatrixXd& Y, const char* what) {
  if (T.rows() != T.cols() || T.rows() != Y.rows()) {
    throw ParameterError(std::string(what) + ": the distance matrix is " +
                         std::to_string(T.rows()) + " by " + std::to_string(T.cols()) +
                         " and the map has " + std::to_string(Y.rows()) +
                         " rows; expected #frames by #frames and #frames rows");
  }
  if (!T.allFinite() || !Y.allFinite()) {
    throw ParameterError(std::string(what) + ": the distances and the map must be finite");
  }
}

// Rank (1 = nearest) of j among i's neighbours by the values v, ties by index.
long rank_of(const double* v, int n, int i, int j) {
  const double dj = v[j];
  long rank = 1;
  for (int l = 0; l < n; ++l) {
    if (l == i) continue;
    rank += (v[l] < dj) || (v[l] == dj && l < j);
  }
  return rank;
}

}  // namespace

NeighborhoodQuality neighborhood_quality(const Eigen::MatrixXd& D, const Eigen::MatrixXd& Y, int k,
                                         const Control& control) {
  check_pair(D, Y, "trustworthiness");
  const int n = static_cast<int>(D.rows());
  if (k < 1 || 2 * k >= n) {
    throw ParameterError("trustworthiness: k = " + std::to_string(k) + " is out of range: with " +
                         std::to_string(n) + " frames it must satisfy 1 ≤ k < " +
                         std::to_string(n) + "/2");
  }
  const int chunks = (n + kRowsPerChunk - 1) / kRowsPerChunk;
  const int workers = worker_count(chunks);
  std::vector<Eigen::ArrayXd> scratch(static_cast<std::size_t>(workers));
  // Per-frame penalties, summed in frame order afterwards so the result is thread-independent.
  std::vector<long> trust_penalty(std::size_t(n), 0);
  std::vector<long> cont_penalty(std::size_t(n), 0);
  parallel_chunks(
      chunks,
      [&](int c, int w) {
        Eigen::ArrayXd& e = scratch[w];
        const auto kk = static_cast<std::size_t>(k);
        std::vector<int> nd(kk), ne(kk);
        std::vector<double> dd(kk), de(kk);
        const int end = std::min(n, (c + 1) * kRowsPerChunk);
        for (int i = c * kRowsPerChunk; i < end; ++i) {
          e.setZero(n);
          for (Eigen::Index a = 0; a < Y.cols(); ++a) e += (Y.col(a).array() - Y(i, a)).square();
          e = e.sqrt();
          const double* d = D.col(i).data();
          k_nearest(d, n, i, k, nd.data(), dd.data());
          k_nearest(e.data(), n, i, k, ne.data(), de.data());
          std::vector<int> sd(nd), se(ne);
          std::sort(sd.begin(), sd.end());
          std::sort(se.begin(), se.end());
          for (int j : ne) {
            if (!std::binary_search(sd.begin(), sd.end(), j))
              trust_penalty[i] += rank_of(d, n, i, j) - k;
          }
          for (int j : nd) {
            if (!std::binary_search(se.begin(), se.end(), j))
              cont_penalty[i] += rank_of(e.data(), n, i, j) - k;
          }
        }
      },
      [&](int done) { control.update(double(done) / chunks); });
  double trust_sum = 0.0, cont_sum = 0.0;
  for (int i = 0; i < n; ++i) {
    trust_sum += double(trust_penalty[i]);
    cont_sum += double(cont_penalty[i]);
  }
  const double norm = 2.0 / (double(n) * k * (2.0 * n - 3.0 * k - 1.0));
  return {1.0 - norm * trust_sum, 1.0 - norm * cont_sum};
}

double trustworthiness(const Eigen::MatrixXd& D, const Eigen::MatrixXd& Y, int k) {
  return neighborhood_quality(D, Y, k).trustworthiness;
}

double continuity(const Eigen::MatrixXd& D, const Eigen::MatrixXd& Y, int k) {
  return neighborhood_quality(D, Y, k).continuity;
}

double normalized_stress(const Eigen::MatrixXd& T, const Eigen::MatrixXd& Y,
                         const Control& control) {
  if (T.rows() != T.cols() || T.rows() != Y.rows()) {
    throw ParameterError("normalized_stress: the target distances are " + std::to_string(T.rows()) +
                         " by " + std::to_string(T.cols()) + " and the map has " +
                         std::to_string(Y.rows()) +
                         " rows; expected #frames by #frames and #frames rows");
  }
  const int n = static_cast<int>(T.rows());
  const int chunks = (n + kRowsPerChunk - 1) / kRowsPerChunk;
  // Pairs i > j, a column j of T at a time (contiguous), with the map distances of the same
  // pairs computed column-wise too; partial sums per chunk, combined in chunk order.
  std::vector<double> tt(std::size_t(chunks), 0.0), te(std::size_t(chunks), 0.0),
      ee(std::size_t(chunks), 0.0), rr(std::size_t(chunks), 0.0);
  auto pass = [&](bool residual, double s) {
    parallel_chunks(
        chunks,
        [&](int c, int) {
          const Eigen::Index dims = Y.cols();
          const double* y = Y.data();
          const Eigen::Index ld = Y.rows();
          const int end = std::min(n, (c + 1) * kRowsPerChunk);
          for (int j = c * kRowsPerChunk; j < end; ++j) {
            const Eigen::Index m = n - 1 - j;
            if (m == 0) continue;
            const double* t = T.col(j).data() + j + 1;
            // e_i: the map distance of the pair (j + 1 + i, j), as ((0 + d₀²) + d₁²)…, then √.
            auto map_distance = [&](Eigen::Index i) {
              double e = 0.0;
              for (Eigen::Index a = 0; a < dims; ++a) {
                const double d = y[a * ld + j + 1 + i] - y[a * ld + j];
                e += d * d;
              }
              return std::sqrt(e);
            };
#if defined(__SSE2__)
            auto map_distances = [&](Eigen::Index i) {
              __m128d e = _mm_setzero_pd();
              for (Eigen::Index a = 0; a < dims; ++a) {
                const __m128d d =
                    _mm_sub_pd(_mm_loadu_pd(y + a * ld + j + 1 + i), _mm_set1_pd(y[a * ld + j]));
                e = _mm_add_pd(e, _mm_mul_pd(d, d));
              }
              return _mm_sqrt_pd(e);
            };
            if (residual) {
              const __m128d sp = _mm_set1_pd(s);
              double sum[1];
              packet_sums<1>(
                  m,
                  [&](Eigen::Index i, __m128d* v) {
                    const __m128d r =
                        _mm_sub_pd(_mm_loadu_pd(t + i), _mm_mul_pd(sp, map_distances(i)));
                    v[0] = _mm_mul_pd(r, r);
                  },
                  [&](Eigen::Index i, double* v) {
                    const double r = t[i] - s * map_distance(i);
                    v[0] = r * r;
                  },
                  sum);
              rr[c] += sum[0];
            } else {
              double sum[3];
              packet_sums<3>(
                  m,
                  [&](Eigen::Index i, __m128d* v) {
                    const __m128d e = map_distances(i), ti = _mm_loadu_pd(t + i);
                    v[0] = _mm_mul_pd(ti, ti);
                    v[1] = _mm_mul_pd(ti, e);
                    v[2] = _mm_mul_pd(e, e);
                  },
                  [&](Eigen::Index i, double* v) {
                    const double e = map_distance(i);
                    v[0] = t[i] * t[i];
                    v[1] = t[i] * e;
                    v[2] = e * e;
                  },
                  sum);
              tt[c] += sum[0];
              te[c] += sum[1];
              ee[c] += sum[2];
            }
#else
            const auto tv = Eigen::Map<const Eigen::ArrayXd>(t, m);
            Eigen::ArrayXd e(m);
            for (Eigen::Index i = 0; i < m; ++i) e[i] = map_distance(i);
            if (residual) {
              rr[c] += (tv - s * e).square().sum();
            } else {
              tt[c] += tv.square().sum();
              te[c] += (tv * e).sum();
              ee[c] += e.square().sum();
            }
#endif
          }
        },
        [&](int done) { control.update((residual ? 0.5 : 0.0) + 0.5 * double(done) / chunks); });
  };
  pass(false, 0.0);
  double stt = 0.0, ste = 0.0, see = 0.0;
  for (int c = 0; c < chunks; ++c) {
    stt += tt[c];
    ste += te[c];
    see += ee[c];
  }
  if (stt == 0.0) return 0.0;
  if (see == 0.0) return 1.0;
  // stress² = 1 − (Σte)²/(Σt²·Σe²): the sums carry ~1e-14 relative error, so this is good to
  // ~1e-4 relative down to stress² = 1e-10; below, 1 − ratio has cancelled and a second pass
  // sums the residuals directly.
  const double ratio = (ste / stt) * (ste / see);
  if (1.0 - ratio > 1e-10) return std::sqrt(1.0 - ratio);
  pass(true, ste / see);
  double srr = 0.0;
  for (double r : rr) srr += r;
  return std::sqrt(srr / stt);
}

double jump_score(const Eigen::MatrixXd& Y) {
  if (Y.rows() < 2) {
    throw ParameterError("jump_score: the map has " + std::to_string(Y.rows()) +
                         " frames; it needs at least 2");
  }
  std::vector<double> steps(static_cast<std::size_t>(Y.rows() - 1));
  for (Eigen::Index f = 0; f + 1 < Y.rows(); ++f) steps[f] = (Y.row(f + 1) - Y.row(f)).norm();
  // Both by numpy's linear quantile (also the median: quantile(·, 0.5), not median(), so the
  // score stays what it has always been, bit for bit).
  const double median = quantile(steps, 0.5);
  const double p95 = quantile(steps, 0.95);
  if (median == 0.0) return p95 == 0.0 ? 1.0 : std::numeric_limits<double>::infinity();
  return p95 / median;
}

int knn_label_vote(std::span<const double> distances, std::span<const int> codes,
                   std::span<const int> groups, int group, int k) {
  if (k < 1) throw ParameterError("knn_label_vote: k is " + std::to_string(k) + "; it must be ≥ 1");
  if (codes.size() != distances.size() || groups.size() != distances.size()) {
    throw ParameterError("knn_label_vote: " + std::to_string(distances.size()) + " distances, " +
                         std::to_string(codes.size()) + " codes and " +
                         std::to_string(groups.size()) + " groups; they must be as many");
  }
  NearestVoters voters(k);
  for (std::size_t j = 0; j < distances.size(); ++j) {
    const double d = distances[j];
    if (codes[j] < 0 || groups[j] == group || !std::isfinite(d)) continue;
    voters.offer(d, int(j));
  }
  return voters.vote(codes);
}

NearestVoters::NearestVoters(int k) : m_k(k) {
  if (k < 1) throw ParameterError("knn_label_vote: k is " + std::to_string(k) + "; it must be ≥ 1");
  m_heap.reserve(static_cast<std::size_t>(k));
}

int NearestVoters::vote(std::span<const int> codes) const {
  // The kept candidates nearest first ((distance, index) pairs: ties to the smaller index).
  std::vector<std::pair<double, int>> nearest = m_heap;
  if (nearest.empty()) return -1;
  std::sort(nearest.begin(), nearest.end());
  // Votes per code, and the rank of each code's nearest voter (the tie-break).
  std::vector<std::pair<int, int>> votes;  // (code, count), in order of first (nearest) voter
  for (const auto& [d, j] : nearest) {
    const int code = codes[std::size_t(j)];
    auto it =
        std::find_if(votes.begin(), votes.end(), [&](const auto& v) { return v.first == code; });
    if (it == votes.end()) {
      votes.emplace_back(code, 1);
    } else {
      ++it->second;
    }
  }
  // The first code with the most votes: among tied codes, the one met first, i.e. nearest.
  int best = 0;
  for (std::size_t v = 1; v < votes.size(); ++v) {
    if (votes[v].second > votes[std::size_t(best)].second) best = int(v);
  }
  return votes[std::size_t(best)].first;
}

}  // namespace motionmap::embed
