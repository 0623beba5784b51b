#pragma once
// What the map-file fuzz targets share: their seeds — small map files of every method, on the
// dense and the landmark path, of a procedural swing, with a label, written afresh at each start so
// that they are of the layout this build writes (no map file is committed) — and what they do with
// a file the reader accepts.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "motionmap/core/error.h"
#include "motionmap/embed/placement.h"
#include "motionmap/io/bvh.h"
#include "motionmap/io/load.h"
#include "motionmap/mapfile/map_file.h"
#include "motionmap/pipeline/clip_map.h"
#include "motionmap/sample/sample_clip.h"

namespace motionmap::fuzz {

/// Writes the seed maps into `folder` and returns their paths. Their clip is written to
/// `clip_path` and left there when `keep_clip` (a SavedMap of a seed then loads it), else removed.
inline std::vector<std::filesystem::path> write_map_seeds(const std::filesystem::path& folder,
                                                          const std::string& clip_path,
                                                          bool keep_clip) {
  sample::SampleOptions options;
  options.fps = 30;
  options.seconds = 2;
  const Clip sample = sample::make_sample_clip(sample::SampleKind::Swing, options);
  io::write_bvh(io::from_motion(sample.skeleton, sample.motion), clip_path);
  const std::vector<Clip> clips{io::load_clip(clip_path)};
  const embed::Method methods[] = {embed::Method::Pca,
                                   embed::Method::Svd,
                                   embed::Method::Mds,
                                   embed::Method::Isomap,
                                   embed::Method::LaplacianEigenmap,
                                   embed::Method::Lle,
                                   embed::Method::Umap,
                                   embed::Method::Gplvm};
  std::vector<std::filesystem::path> written;
  for (const embed::Method method : methods) {
    for (const bool landmarks : {false, true}) {
      if (landmarks && (method == embed::Method::Pca || method == embed::Method::Svd ||
                        method == embed::Method::Gplvm)) {
        continue;
      }
      pipeline::ClipMapOptions o;
      o.embed.method = method;
      o.embed.k = 6;
      if (landmarks) o.path = pipeline::MapPath::Landmarks;
      const std::string name = std::string(embed::method_name(method)) +
                               (landmarks ? "-landmarks" : "-dense") + ".mmap.h5";
      try {
        mapfile::MapFile file = mapfile::make_map_file(clips, pipeline::map_clips(clips, o), o);
        // Labels (group /labels), so that their datasets are fuzzed too: "phase", two values.
        pipeline::LabelColumn phase{"phase", {"back", "through"}, {}};
        for (int i = 0; i < file.num_samples(); ++i) {
          phase.codes.push_back(2 * i < file.num_samples() ? 0 : 1);
        }
        file.labels.columns = {phase};
        mapfile::write_map_file((folder / name).string(), file);
        written.push_back(folder / name);
      } catch (const Error& e) {  // a seed fewer, said
        std::fprintf(stderr, "map seeds: no seed %s: %s\n", name.c_str(), e.what());
      }
    }
  }
  if (!keep_clip) std::filesystem::remove(clip_path);
  return written;
}

/// Places three frames on `map`'s model: what read_map_file() returns can be placed on without
/// further checks.
inline void place_on(const mapfile::MapFile& map) {
  Eigen::MatrixXd X = Eigen::MatrixXd::Zero(3, map.x_columns);
  RowMatrix points = RowMatrix::Zero(3, map.point_columns);
  for (Eigen::Index i = 0; i < points.size(); ++i) points.data()[i] = double(i % 7) - 3.0;
  for (Eigen::Index i = 0; i < X.size(); ++i) X.data()[i] = double(i % 5) * 0.25;
  embed::place(map.model, embed::PlaceInput{&X, &points});
}

}  // namespace motionmap::fuzz
