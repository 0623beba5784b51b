#pragma once
// The valid range of k, the neighbours per frame of a k-NN graph (Isomap, the Laplacian eigenmap,
// LLE): 1 ≤ k ≤ #frames − 1, since a frame's neighbours are the other frames. The methods'
// parameter check (embed.cpp) uses it, and applications show it (Studio's Parameters… dialog).
namespace motionmap::embed {

/// The smallest valid k.
inline constexpr int kMinNeighbors = 1;
/// The largest valid k for `num_frames` frames.
constexpr int max_neighbors(int num_frames) {
  return num_frames - 1;
}
/// Whether `k` is valid for `num_frames` frames.
constexpr bool valid_neighbors(int k, int num_frames) {
  return k >= kMinNeighbors && k <= max_neighbors(num_frames);
}

}  // namespace motionmap::embed
