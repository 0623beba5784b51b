// `motionmap sample --kind swing|walk -o FILE.bvh`: the built-in procedural clips.
#include <iostream>
#include <map>
#include <memory>

#include "commands.h"
#include "motionmap/io/bvh.h"
#include "motionmap/sample/sample_clip.h"

namespace motionmap::cli {

namespace {
struct SampleCliOptions {
  sample::SampleKind kind = sample::SampleKind::Swing;
  std::string output;
  sample::SampleOptions options;
};
}  // namespace

void setup_sample(CLI::App& app) {
  auto opt = std::make_shared<SampleCliOptions>();
  auto* sub = app.add_subcommand(
      "sample",
      "Write a built-in procedural clip as BVH: a golf-like swing or a walk cycle of a CMU-like\n"
      "31-joint skeleton (centimetres, Y up), so everything can be tried without mocap files.");
  const std::map<std::string, sample::SampleKind> kinds{{"swing", sample::SampleKind::Swing},
                                                        {"walk", sample::SampleKind::Walk}};
  sub->add_option("--kind", opt->kind, "swing or walk (default swing)")
      ->transform(CLI::CheckedTransformer(kinds, CLI::ignore_case));
  sub->add_option("-o,--output", opt->output, "Output .bvh file")->required();
  sub->add_option("--fps", opt->options.fps, "Frames per second (default 120)")
      ->check(CLI::PositiveNumber);
  sub->add_option("--seconds", opt->options.seconds,
                  "Length in seconds (default: the kind's natural length)")
      ->check(CLI::NonNegativeNumber);
  sub->callback([opt] {
    const Clip clip = sample::make_sample_clip(opt->kind, opt->options);
    io::write_bvh(io::from_motion(clip.skeleton, clip.motion), opt->output);
    std::cerr << "wrote " << opt->output << ": " << sample::sample_kind_name(opt->kind) << ", "
              << clip.motion.num_frames << " frames at " << clip.motion.fps() << " fps\n";
  });
}

}  // namespace motionmap::cli
