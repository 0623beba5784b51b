// Maps the built-in sample swing with PCA through an installed MotionMap, and prints the map's
// size: "consumer: N rows, 2 columns"; then saves it as a map file and reads it back (the
// installed MotionMap::mapfile and the HDF5 library MotionMapConfig.cmake found for it):
// "consumer: map file read back, N rows".
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <span>
#include <string>

#include "motionmap/io/bvh.h"
#include "motionmap/io/load.h"
#include "motionmap/mapfile/map_file.h"
#include "motionmap/pipeline/clip_map.h"
#include "motionmap/sample/sample_clip.h"

int main() {
  const motionmap::Clip sample =
      motionmap::sample::make_sample_clip(motionmap::sample::SampleKind::Swing);
  // A map file hashes its clips' files: map the sample as a file.
  const std::string bvh =
      (std::filesystem::temp_directory_path() / "motionmap-consumer.bvh").string();
  motionmap::io::write_bvh(motionmap::io::from_motion(sample.skeleton, sample.motion), bvh);
  const motionmap::Clip clip = motionmap::io::load_clip(bvh);
  motionmap::pipeline::ClipMapOptions options;
  options.embed.method = motionmap::embed::Method::Pca;
  const std::span<const motionmap::Clip> clips(&clip, 1);
  const motionmap::pipeline::ClipMap map = motionmap::pipeline::map_clips(clips, options);
  std::cout << "consumer: " << map.embedding.coordinates.rows() << " rows, "
            << map.embedding.coordinates.cols() << " columns\n";

  const std::string saved = bvh + ".mmap.h5";
  motionmap::mapfile::write_map_file(saved, motionmap::mapfile::make_map_file(clips, map, options));
  const motionmap::mapfile::MapFile read = motionmap::mapfile::read_map_file(saved);
  std::cout << "consumer: map file read back, " << read.coordinates.rows() << " rows\n";
  std::remove(saved.c_str());
  std::remove(bvh.c_str());
  return read.coordinates == map.embedding.coordinates ? 0 : 1;
}
