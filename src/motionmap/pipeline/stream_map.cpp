#include "motionmap/pipeline/stream_map.h"

#include <algorithm>
#include <exception>
#include <filesystem>
#include <optional>
#include <utility>

#include "motionmap/core/error.h"
#include "motionmap/core/parallel.h"
#include "motionmap/embed/projection_stream.h"
#include "motionmap/io/load.h"

namespace motionmap::pipeline {

double estimate_load_bytes(std::span<const std::string> paths) {
  double bytes = 0.0;
  for (const std::string& path : paths) {
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    if (!ec) bytes += double(size);
  }
  return bytes * kLoadBytesPerFileByte;
}

std::string why_not_streamed(const ClipMapOptions& options) {
  const std::string method(embed::method_name(options.embed.method));
  if (options.embed.method != embed::Method::Pca && options.embed.method != embed::Method::Svd) {
    return method +
           " reads the pose distances between frames, not X alone; only pca and svd can read a "
           "library a clip at a time";
  }
  if (options.features.joints != features::JointSelection::All) {
    return "--joints common needs every clip's skeleton before the first clip's features; a "
           "library read a clip at a time maps by all joints";
  }
  if (options.metrics) {
    return "the metrics compare frames of the whole library with each other; a library read a "
           "clip at a time has no metrics";
  }
  return {};
}

bool streams_by_default(const ClipMapOptions& options, std::span<const std::string> paths,
                        std::optional<std::int64_t> available) {
  return available && why_not_streamed(options).empty() &&
         estimate_load_bytes(paths) > double(*available);
}

namespace {

// A clip without its poses: what the CSV, the map file and the caller read of it afterwards.
Clip header_of(Clip&& clip) {
  Clip header;
  header.path = std::move(clip.path);
  header.skeleton = std::move(clip.skeleton);
  header.motion.num_frames = clip.motion.num_frames;
  header.motion.num_joints = clip.motion.num_joints;
  header.motion.frame_time = clip.motion.frame_time;
  header.warnings = std::move(clip.warnings);
  header.sha256 = std::move(clip.sha256);
  return header;
}

}  // namespace

StreamedMap stream_map(std::span<const std::string> paths, const io::LoadClipsOptions& load,
                       const ClipMapOptions& options, const Control& control) {
  if (const std::string why = why_not_streamed(options); !why.empty()) {
    throw ParameterError("streaming: " + why);
  }
  options.features.validate();
  if (paths.empty()) throw ParameterError("streaming: no clip given");
  embed::ProjectionStream stream(options.embed);

  StreamedMap out;
  auto set = std::make_shared<features::FeatureSet>();
  set->distance = options.features.distance;
  Eigen::Index x_columns = 0, point_columns = 0;
  features::SamePoseCheck same_pose;
  std::vector<std::string> mapped;  // the paths of the clips that loaded, for pass 2

  // Clips are read a batch at a time, one per thread: each is loaded and its rows built and
  // summarised on its own (parallel_chunks), then the batch is merged in clip order, so the map
  // does not depend on the thread count. Cancellation is polled between clips.
  const int batch = worker_count();

  // Pass 1: each clip's rows of X, summarised and merged; the samples' bookkeeping.
  struct Slot {
    std::optional<Clip> clip;
    features::FeatureSet rows;
    embed::ProjectionStream::Block block;
    std::string failure;       // keep_going: why the clip did not load
    std::exception_ptr error;  // thrown in clip order, whichever thread met it first
  };
  const double n = double(paths.size());
  const Control pass1 = control.stage("pass 1: features and XᵀX", 0.0, 0.48);
  for (std::size_t b0 = 0; b0 < paths.size(); b0 += std::size_t(batch)) {
    const int count = static_cast<int>(std::min<std::size_t>(batch, paths.size() - b0));
    std::vector<Slot> slots(static_cast<std::size_t>(count));
    parallel_chunks(
        count,
        [&](int i, int) {
          Slot& slot = slots[std::size_t(i)];
          try {
            slot.clip = io::load_clip(paths[b0 + std::size_t(i)], load.load);
          } catch (const Error& e) {
            if (!load.keep_going) {
              slot.error = std::current_exception();
            } else {
              slot.failure = e.what();
            }
            return;
          }
          try {
            // (Checked against the set's first clip below, in order.)
            slot.rows = features::clip_rows(*slot.clip, *slot.clip, options.features);
            slot.block = embed::ProjectionStream::summarize(slot.rows.X);
            slot.rows.X.resize(0, slot.rows.X.cols());
          } catch (...) {
            slot.error = std::current_exception();
          }
        },
        [&](int done) { pass1.update((double(b0) + done) / n); });
    for (Slot& slot : slots) {
      if (slot.error) std::rethrow_exception(slot.error);
      if (!slot.clip) {
        out.failures.push_back(std::move(slot.failure));
        continue;
      }
      if (!out.clips.empty()) features::check_same_hierarchy(*slot.clip, out.clips.front());
      features::FeatureSet& rows = slot.rows;
      stream.merge(slot.block);
      same_pose.add(rows);
      const int c = static_cast<int>(out.clips.size());
      set->segment_starts.push_back(set->num_samples());
      for (const int f : rows.frame_of) {
        set->clip_of.push_back(c);
        set->frame_of.push_back(f);
      }
      for (std::string& note : rows.notes) set->notes.push_back(std::move(note));
      if (c == 0) set->joints = rows.joints;
      x_columns = rows.X.cols();
      point_columns = rows.distance_input.cols();
      mapped.push_back(slot.clip->path);
      out.clips.push_back(header_of(std::move(*slot.clip)));
    }
  }
  if (out.clips.empty()) throw io::no_clip_loaded(out.failures, paths.size());
  if (const auto note = same_pose.note(options.features.distance)) set->notes.push_back(*note);
  set->X.resize(0, x_columns);
  set->distance_input.resize(0, point_columns);

  control.stage("eigen", 0.48, 0.5);
  stream.fit();

  // Pass 2: the same clips again, each clip's rows placed on the axes (each clip writes its own
  // rows of the coordinates).
  Eigen::MatrixXd coordinates(stream.rows(), options.embed.dimensions);
  const int clips = static_cast<int>(mapped.size());
  const Control pass2 = control.stage("pass 2: features and projection", 0.5, 1.0);
  const Clip& first = out.clips.front();
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(clips));
  parallel_chunks(
      clips,
      [&](int c, int) {
        try {
          const Clip clip = io::load_clip(mapped[std::size_t(c)], load.load);
          const features::FeatureSet rows = features::clip_rows(clip, first, options.features);
          const int start = set->segment_starts[std::size_t(c)];
          const int end =
              c + 1 < clips ? set->segment_starts[std::size_t(c) + 1] : set->num_samples();
          if (clip.sha256 != out.clips[std::size_t(c)].sha256) {
            throw Error(mapped[std::size_t(c)] +
                        ": error: the file changed while it was being mapped (its SHA-256 "
                        "differs between the two passes)");
          }
          if (rows.num_samples() != end - start ||
              !std::equal(rows.frame_of.begin(), rows.frame_of.end(),
                          set->frame_of.begin() + start)) {
            throw Error(mapped[std::size_t(c)] +
                        ": error: the file changed while it was being mapped (" +
                        std::to_string(end - start) + " frames used in the first pass, " +
                        std::to_string(rows.num_samples()) + " in the second)");
          }
          coordinates.middleRows(start, end - start) = stream.project(rows.X);
        } catch (...) {
          errors[std::size_t(c)] = std::current_exception();
        }
      },
      [&](int done) { pass2.update(double(done) / clips); });
  for (const std::exception_ptr& error : errors) {
    if (error) std::rethrow_exception(error);
  }

  embed::MapModel model;
  out.map.embedding = stream.finish(std::move(coordinates), &model);
  out.map.model = std::move(model);
  out.map.features = std::move(set);
  const int frames = out.map.features->num_samples();
  // The path map_clips() would record (pca and svd read X alone on both).
  out.map.dense = options.path == MapPath::Dense ||
                  (options.path == MapPath::Auto && frames <= options.dense_limit);
  control.finish();
  return out;
}

}  // namespace motionmap::pipeline
