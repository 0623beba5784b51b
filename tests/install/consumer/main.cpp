// Maps the built-in sample swing with PCA through an installed MotionMap, and prints the map's
// size: "consumer: N rows, 2 columns".
#include <iostream>
#include <span>

#include "motionmap/pipeline/clip_map.h"
#include "motionmap/sample/sample_clip.h"

int main() {
  const motionmap::Clip clip =
      motionmap::sample::make_sample_clip(motionmap::sample::SampleKind::Swing);
  motionmap::pipeline::ClipMapOptions options;
  options.embed.method = motionmap::embed::Method::Pca;
  const motionmap::pipeline::ClipMap map =
      motionmap::pipeline::map_clips(std::span<const motionmap::Clip>(&clip, 1), options);
  std::cout << "consumer: " << map.embedding.coordinates.rows() << " rows, "
            << map.embedding.coordinates.cols() << " columns\n";
  return 0;
}
