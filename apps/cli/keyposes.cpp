// `motionmap keyposes FILE… -n 8 -o sheet.png`: key poses picked from the shape of each clip's map
// trajectory (pipeline/key_poses.h), drawn as a contact sheet, and measured against evenly spaced
// frames: the RMS joint-angle error of the clip rebuilt by interpolating between its key poses.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "commands.h"
#include "map_options.h"
#include "motionmap/core/error.h"
#include "motionmap/pipeline/key_poses.h"
#include "motionmap/render/pose_sheet.h"
#include "motionmap/skeleton/bones.h"

namespace motionmap::cli {

namespace {

struct KeyPosesCommand {
  MapCliOptions map;
  int count = 8;
  std::string output;
  bool json = false;
  int pose_px = 150;
};

// A clip's key poses and how well each set rebuilds it.
struct ClipKeys {
  std::vector<int> keys;     // file frames
  std::vector<int> rows;     // their rows of the map
  std::vector<int> uniform;  // evenly spaced file frames, as many
  double error = 0.0;        // RMS joint-angle error (degrees) rebuilt from `keys`
  double uniform_error = 0.0;
  int first = 0, last = 0;  // the file frames the map holds of it
};

ClipKeys clip_keys(const pipeline::ClipMap& map, const Clip& clip, int c, int count) {
  const features::FeatureSet& set = *map.features;
  const std::vector<int> rows = pipeline::clip_rows(map, c);
  ClipKeys out;
  out.rows = pipeline::clip_key_rows(map, c, count);
  for (const int r : out.rows) out.keys.push_back(set.frame_of[std::size_t(r)]);
  for (const int u : pipeline::uniform_key_poses(static_cast<int>(rows.size()), count)) {
    out.uniform.push_back(set.frame_of[std::size_t(rows[std::size_t(u)])]);
  }
  out.first = set.frame_of[std::size_t(rows.front())];
  out.last = set.frame_of[std::size_t(rows.back())];
  out.error = pipeline::rms_rotation_error(
      clip.motion, pipeline::interpolate_keys(clip.motion, out.keys), out.first, out.last);
  out.uniform_error = pipeline::rms_rotation_error(
      clip.motion, pipeline::interpolate_keys(clip.motion, out.uniform), out.first, out.last);
  return out;
}

std::string frames_text(const std::vector<int>& frames) {
  std::string s;
  for (std::size_t i = 0; i < frames.size(); ++i) s += (i ? "," : "") + std::to_string(frames[i]);
  return s;
}

}  // namespace

void setup_keyposes(CLI::App& app) {
  auto cmd = std::make_shared<KeyPosesCommand>();
  auto* sub = app.add_subcommand(
      "keyposes",
      "Pick each clip's key poses from the shape of its map trajectory — the first and last\n"
      "frames, then one at a time the frame farthest from the straight, constant-speed path\n"
      "between the keys around it (turning points and extremes of the curve) — and draw them as a\n"
      "contact sheet with the map. Prints, per clip, the frames and the RMS joint-angle error of\n"
      "the clip rebuilt by interpolating between them (slerp per joint), beside the error of as\n"
      "many evenly spaced frames.");
  // The PCA map by default: a linear projection of the poses, whose interpolation error is
  // closest to that of the poses (pipeline/key_poses.h).
  cmd->map.method = embed::Method::Pca;
  add_map_options(sub, cmd->map, MapOptionsFor::Map);
  sub->get_option("--method")
      ->description("pca, svd, mds, isomap, le, lle, umap or gplvm (default pca for key poses)");
  sub->add_option("-n,--count", cmd->count, "Key poses per clip (default 8)")
      ->check(CLI::Range(2, 1000));
  sub->add_option("-o,--output", cmd->output, "Contact sheet to write: .png, .svg or .pdf");
  sub->add_flag("--json", cmd->json, "Print the key poses and errors as JSON instead of a table");
  sub->add_option("--pose-size", cmd->pose_px, "Pixels per pose on the sheet (default 150)")
      ->check(CLI::Range(32, 2000));
  sub->callback([cmd] {
    const std::vector<Clip> clips = load_inputs(cmd->map);
    const pipeline::ClipMapOptions options =
        clip_map_options(cmd->map, cmd->map.method, /*metrics=*/false);
    const pipeline::ClipMap map =
        pipeline::map_clips(clips, options, progress_line(cmd->map, "keyposes"));
    print_diagnostics(map);

    std::vector<ClipKeys> found;
    for (std::size_t c = 0; c < clips.size(); ++c) {
      found.push_back(clip_keys(map, clips[c], static_cast<int>(c), cmd->count));
    }
    if (cmd->json) {
      std::printf("{\"method\": \"%s\", \"clips\": [",
                  std::string(embed::method_name(map.embedding.method)).c_str());
      for (std::size_t c = 0; c < clips.size(); ++c) {
        const ClipKeys& k = found[c];
        std::printf(
            "%s\n  {\"path\": \"%s\", \"first\": %d, \"last\": %d, \"frames\": [%s], "
            "\"rms_degrees\": %.6g, \"uniform_frames\": [%s], \"uniform_rms_degrees\": %.6g}",
            c ? "," : "", json_escape(clips[c].path).c_str(), k.first, k.last,
            frames_text(k.keys).c_str(), k.error, frames_text(k.uniform).c_str(), k.uniform_error);
      }
      std::printf("\n]}\n");
    } else {
      std::printf("%-40s %9s %9s  %s\n", "clip", "keys", "uniform", "key frames");
      for (std::size_t c = 0; c < clips.size(); ++c) {
        std::printf("%-40s %8.2f° %8.2f°  %s\n", clips[c].path.c_str(), found[c].error,
                    found[c].uniform_error, frames_text(found[c].keys).c_str());
      }
    }
    if (cmd->output.empty()) return;
    std::vector<render::SheetRow> rows;
    const Eigen::MatrixXd& coords = map.embedding.coordinates;
    for (std::size_t c = 0; c < clips.size(); ++c) {
      render::SheetRow row;
      row.title = QString::fromStdString(std::filesystem::path(clips[c].path).filename().string());
      const int begin = map.features->segment_starts[c];
      const int end = c + 1 < clips.size() ? map.features->segment_starts[c + 1]
                                           : static_cast<int>(coords.rows());
      row.coords = coords.middleRows(begin, end - begin);
      const std::vector<bool> detached = detached_joints(clips[c].skeleton, clips[c].motion);
      for (std::size_t i = 0; i < found[c].keys.size(); ++i) {
        row.poses.push_back(
            render::sheet_pose(clips[c].skeleton, clips[c].motion, detached, found[c].keys[i]));
        row.marked.push_back(found[c].rows[i] - begin);
      }
      rows.push_back(std::move(row));
    }
    render::PoseSheetOptions sheet;
    sheet.pose_px = cmd->pose_px;
    sheet.up_axis = static_cast<int>(options.features.up);
    sheet.title = QString::number(cmd->count) + " key poses per clip from the " +
                  QString::fromStdString(std::string(embed::method_name(map.embedding.method))) +
                  " map";
    ensure_gui_application();
    render::save_pose_sheet(cmd->output, rows, sheet);
    std::cerr << "wrote " << cmd->output << '\n';
  });
}

}  // namespace motionmap::cli
