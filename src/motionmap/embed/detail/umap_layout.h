#pragma once
// UMAP's stochastic layout (umap.cpp), on as many threads as the pool has, with the same map for
// one seed and one thread count (docs/methods/umap.md, "Threads and determinism"):
//
//   UmapChunks chunks = umap_layout_chunks(edges.head, frames, umap_layout_chunk_count(frames));
//   umap_layout(edges, chunks, Y, rng, progress);
//
// The frames are cut into contiguous ranges, one per chunk, balanced by their edges. Chunk c
// owns its frames and the edges leaving them, and has its own random numbers (chunk 0 continues
// the generator it is given, chunk c > 0 has a generator seeded from the seed and c). In an epoch
// every chunk moves only its own frames: an edge i → j moves i, and moves j too when j is the
// chunk's; a frame of another chunk is read as it was when the epoch began (a copy made before
// it), so no chunk reads what another writes in the same epoch. With one chunk this is
// umap-learn's serial layout (every edge moves both ends, every frame is read as it is now).
#include <cstdint>
#include <random>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "motionmap/embed/detail/progress.h"
#include "motionmap/embed/neighbors.h"
#include "motionmap/embed/umap.h"

namespace motionmap::embed {

/// The directed edges the layout samples, grouped by head frame (non-decreasing `head`).
struct UmapEdges {
  std::vector<int> head;
  std::vector<int> tail;
  std::vector<double> every;  ///< the edge is sampled every `every` epochs (max weight ÷ weight)
};

/// The partition of the frames and of their edges between the layout's chunks: chunk c owns
/// frames [first[c], first[c + 1]) and edges [edge[c], edge[c + 1]).
struct UmapChunks {
  std::vector<int> first;
  std::vector<std::size_t> edge;
  int count() const { return static_cast<int>(first.size()) - 1; }
};

/// The frames in breadth-first order of `graph` (each component from its lowest frame, a frame's
/// neighbours in CSR order): neighbours come near each other. The layout of more than 65 536
/// frames runs in this order, so that the frames an edge reads are mostly in cache.
std::vector<int> umap_breadth_first_order(const Graph& graph);

/// The layout's chunks for `frames` frames: one per thread of the pool (worker_count(),
/// MOTIONMAP_THREADS), at most one per 1 000 frames, at least 1.
int umap_layout_chunk_count(int frames);

/// `count` contiguous ranges of frames whose edge counts are as equal as frame boundaries allow
/// (`head` non-decreasing, every value in [0, frames)).
UmapChunks umap_layout_chunks(std::span<const int> head, int frames, int count);

/// Runs `epochs` epochs of the layout on Y (frames × dimensions), starting from Y: attraction
/// along the edges, 5 negative samples per edge visit on average, the learning rate falling
/// linearly from 1. `rng` is chunk 0's generator; chunk c > 0's is seeded from `seed` and c. The
/// chunks run on the pool's threads (on the calling thread alone with `serial`, same result);
/// progress is reported once per epoch and cancellation polled then. @throws Cancelled.
void umap_layout(const UmapEdges& edges, const UmapChunks& chunks, const UmapCurve& curve,
                 int epochs, std::uint64_t seed, Eigen::MatrixXd& Y, std::mt19937_64& rng,
                 Progress& progress, bool serial = false);

}  // namespace motionmap::embed
