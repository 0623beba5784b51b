// `motionmap convert IN -o OUT.bvh`: any supported clip to BVH.
#include <filesystem>
#include <iostream>
#include <memory>

#include "commands.h"
#include "motionmap/core/error.h"
#include "motionmap/io/bvh.h"
#include "motionmap/io/load.h"

namespace motionmap::cli {

namespace {
struct ConvertOptions {
  std::string input;
  std::string output;
  std::string asf;
  double fps = 0.0;
};
}  // namespace

void setup_convert(CLI::App& app) {
  auto opt = std::make_shared<ConvertOptions>();
  auto* sub = app.add_subcommand(
      "convert",
      "Convert a clip (BVH, or Acclaim AMC with its ASF skeleton) to BVH. A BVH input is written\n"
      "back value for value with its channel order; an AMC input gets the root channels\n"
      "Xposition Yposition Zposition Zrotation Yrotation Xrotation and ZYX rotations elsewhere.");
  sub->add_option("input", opt->input, "Input clip (.bvh or .amc)")
      ->required()
      ->check(CLI::ExistingFile);
  sub->add_option("-o,--output", opt->output, "Output .bvh file")->required();
  sub->add_option("--asf", opt->asf, "ASF skeleton for an .amc input (default: the .asf beside it)")
      ->check(CLI::ExistingFile);
  sub->add_option("--fps", opt->fps,
                  "Frame rate of the input: AMC stores none (default 120); for BVH it replaces the "
                  "file's frame time (no resampling)")
      ->check(CLI::PositiveNumber);
  sub->callback([opt] {
    const std::string ext = std::filesystem::path(opt->input).extension().string();
    io::BvhDocument doc;
    if (ext == ".bvh" || ext == ".BVH") {
      doc = io::read_bvh(opt->input);  // lossless: the raw values as read
      if (opt->fps > 0) doc.frame_time = 1.0 / opt->fps;
    } else {
      io::LoadOptions load;
      load.asf_path = opt->asf;
      load.fps = opt->fps;
      const Clip clip = io::load_clip(opt->input, load);
      doc = io::from_motion(clip.skeleton, clip.motion);
      doc.warnings = clip.warnings;
    }
    for (const auto& w : doc.warnings) std::cerr << w << '\n';
    io::write_bvh(doc, opt->output);
    std::cerr << "wrote " << opt->output << ": " << doc.skeleton.num_joints() << " joints, "
              << doc.num_frames << " frames\n";
  });
}

}  // namespace motionmap::cli
