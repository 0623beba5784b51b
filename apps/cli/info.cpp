// `motionmap info FILE…`: what a clip holds and what looks wrong in it.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

#include "commands.h"
#include "motionmap/core/error.h"
#include "motionmap/features/diagnostics.h"
#include "motionmap/io/load.h"
#include "motionmap/skeleton/forward_kinematics.h"

namespace motionmap::cli {

namespace {

struct InfoOptions {
  std::vector<std::string> files;
  std::string asf;
  double fps = 0.0;
  bool json = false;
};

struct ClipSummary {
  Eigen::Vector3d box_min = Eigen::Vector3d::Zero();
  Eigen::Vector3d box_max = Eigen::Vector3d::Zero();
  std::vector<std::string> warnings;
};

ClipSummary summarize(const Clip& clip) {
  ClipSummary s;
  if (clip.motion.num_frames > 0) {
    const auto points = world_points(clip.skeleton, clip.motion);
    s.box_min.setConstant(INFINITY);
    s.box_max.setConstant(-INFINITY);
    for (Eigen::Index c = 0; c < points.cols(); c += 3) {
      s.box_min = s.box_min.cwiseMin(points.middleCols<3>(c).colwise().minCoeff().transpose());
      s.box_max = s.box_max.cwiseMax(points.middleCols<3>(c).colwise().maxCoeff().transpose());
    }
  }
  s.warnings = clip.warnings;
  for (auto& w : features::clip_warnings(clip.skeleton, clip.motion))
    s.warnings.push_back(std::move(w));
  return s;
}

std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string vec(const Eigen::Vector3d& v) {
  return "[" + num(v.x()) + ", " + num(v.y()) + ", " + num(v.z()) + "]";
}

void print_text(const Clip& clip, const ClipSummary& s) {
  const Skeleton& sk = clip.skeleton;
  const Motion& m = clip.motion;
  std::string roots;
  for (int r : sk.roots()) roots += (roots.empty() ? "" : ", ") + sk.joints[r].name;
  std::cout << clip.path << '\n'
            << "  joints      " << sk.num_joints() << " (" << sk.roots().size()
            << (sk.roots().size() == 1 ? " root: " : " roots: ") << roots << "), "
            << sk.num_end_sites() << " end sites\n"
            << "  channels    " << sk.num_channels() << '\n'
            << "  frames      " << m.num_frames << " at " << num(m.fps()) << " fps (frame time "
            << num(m.frame_time) << " s), " << num(m.duration()) << " s\n"
            << "  bounding    min " << vec(s.box_min) << "  max " << vec(s.box_max)
            << " (file units)\n";
  if (s.warnings.empty()) {
    std::cout << "  warnings    none\n";
  } else {
    std::cout << "  warnings    " << s.warnings.size() << '\n';
    for (const auto& w : s.warnings) std::cout << "    - " << w << '\n';
  }
}

std::string json_vec(const Eigen::Vector3d& v) {
  return "[" + num(v.x()) + "," + num(v.y()) + "," + num(v.z()) + "]";
}

void print_json(const Clip& clip, const ClipSummary& s) {
  const Skeleton& sk = clip.skeleton;
  const Motion& m = clip.motion;
  std::string roots;
  for (int r : sk.roots())
    roots += std::string(roots.empty() ? "" : ",") + "\"" + json_escape(sk.joints[r].name) + "\"";
  std::string warnings;
  for (const auto& w : s.warnings)
    warnings += std::string(warnings.empty() ? "" : ",") + "\"" + json_escape(w) + "\"";
  char frame_time[64];
  std::snprintf(frame_time, sizeof frame_time, "%.17g", m.frame_time);
  std::cout << "{\"file\":\"" << json_escape(clip.path) << "\",\"joints\":" << sk.num_joints()
            << ",\"roots\":" << sk.roots().size() << ",\"root_names\":[" << roots << "]"
            << ",\"channels\":" << sk.num_channels() << ",\"end_sites\":" << sk.num_end_sites()
            << ",\"frames\":" << m.num_frames << ",\"frame_time\":" << frame_time
            << ",\"fps\":" << num(m.fps()) << ",\"duration\":" << num(m.duration())
            << ",\"bounding_box\":{\"min\":" << json_vec(s.box_min)
            << ",\"max\":" << json_vec(s.box_max) << "},\"warnings\":[" << warnings << "]}\n";
}

}  // namespace

void setup_info(CLI::App& app) {
  auto opt = std::make_shared<InfoOptions>();
  auto* sub = app.add_subcommand(
      "info",
      "Print what clips hold: joints, roots, channels, frames, fps, duration, bounding box, and\n"
      "warnings (what the reader accepted with a warning, e.g. a BVH root declared with JOINT;\n"
      "a leading bind/T-pose frame; joints whose rotation flips by >90° between consecutive\n"
      "frames at ≥ 60 fps, with the frames).");
  sub->add_option("files", opt->files, "BVH or AMC files")->required()->check(CLI::ExistingFile);
  sub->add_option("--asf", opt->asf, "ASF skeleton for .amc files (default: the .asf beside it)")
      ->check(CLI::ExistingFile);
  sub->add_option("--fps", opt->fps, "Frame rate to assume (AMC stores none: default 120)")
      ->check(CLI::PositiveNumber);
  sub->add_flag("--json", opt->json,
                "One JSON object per file and line: joints, roots, root_names, channels, "
                "end_sites, frames, frame_time, fps, duration, bounding_box, warnings");
  sub->callback([opt] {
    int failures = 0;
    for (const auto& file : opt->files) {
      try {
        io::LoadOptions load;
        load.asf_path = opt->asf;
        load.fps = opt->fps;
        const Clip clip = io::load_clip(file, load);
        const ClipSummary s = summarize(clip);
        if (opt->json) {
          print_json(clip, s);
        } else {
          print_text(clip, s);
        }
      } catch (const Error& e) {
        std::cerr << "motionmap: " << e.what() << '\n';
        ++failures;
      }
    }
    if (failures > 0)
      throw Error(std::to_string(failures) + " of " + std::to_string(opt->files.size()) +
                  " files could not be read");
  });
}

}  // namespace motionmap::cli
