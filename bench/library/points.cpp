// motionmap-points: the points the points path of `motionmap map` reads (embed.h, "Two paths"),
// for the scripts that judge its maps (bench/accuracy_table.py): the features of the clips as
// `map` builds them by default (heading-local point clouds; the leading bind poses left out),
// written as raw little-endian float64, row-major, after a header line "ROWS COLS\n".
//
//   motionmap-points OUT.f64 CLIP…
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "motionmap/core/error.h"
#include "motionmap/features/features.h"
#include "motionmap/io/load.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: motionmap-points OUT.f64 CLIP...\n";
    return 2;
  }
  try {
    std::vector<motionmap::Clip> clips;
    for (int i = 2; i < argc; ++i) clips.push_back(motionmap::io::load_clip(argv[i]));
    const motionmap::features::FeatureSet set =
        motionmap::features::build_features(clips, {}, {}, motionmap::features::Distances::Later);
    const motionmap::RowMatrix& P = set.distance_input;
    std::ofstream out(argv[1], std::ios::binary);
    out << P.rows() << ' ' << P.cols() << '\n';
    out.write(reinterpret_cast<const char*>(P.data()),
              static_cast<std::streamsize>(P.size() * sizeof(double)));
    if (!out) throw motionmap::Error(std::string(argv[1]) + ": cannot write");
  } catch (const motionmap::Error& e) {
    std::cerr << "error: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
