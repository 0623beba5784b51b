// `motionmap reach FILE… --joint LeftHand --to x,y,z [--pin RightFoot] -o pose.bvh`: the valid map
// point whose blended pose brings a joint closest to a target (synth/reach.h), written as a
// one-frame BVH; prints the remaining error and the map point. The map as for `pose`: computed
// from FILE…, read with --map map.csv, or a saved map --map lib.mmap.h5.
#include <charconv>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "blend_setup.h"
#include "commands.h"
#include "map_options.h"
#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/features/joint_match.h"
#include "motionmap/io/bvh.h"
#include "motionmap/mapfile/saved_map.h"
#include "motionmap/pipeline/map_csv.h"
#include "motionmap/skeleton/forward_kinematics.h"
#include "motionmap/synth/reach.h"

namespace motionmap::cli {

namespace {

struct ReachCommand {
  BlendCliOptions o;
  std::string output;
  std::string joint;
  std::string to;
  std::vector<std::string> pins;
  double pin_weight = 1.0;
  std::string from;
  int evaluations = synth::ReachOptions{}.max_evaluations;
  bool json = false;
};

Eigen::Vector3d parse_position(const std::string& option, const std::string& text) {
  const auto v = parse_numbers<3>(text);
  if (!v) {
    throw CLI::ValidationError(option, "'" + text +
                                           "' is not a position x,y,z of three finite numbers "
                                           "(write " +
                                           option + "=x,y,z when x is negative)");
  }
  return *v;
}

std::string json_number(double v) {
  return std::isfinite(v) ? format_number(v) : "null";
}

template <class Vector>
std::string json_array(const Vector& v) {
  std::string out = "[";
  for (int k = 0; k < v.size(); ++k) out += (k ? "," : "") + json_number(v[k]);
  return out + "]";
}

template <class Vector>
std::string text_point(const Vector& v) {
  std::string out;
  for (int k = 0; k < v.size(); ++k) out += (k ? ", " : "") + format_number(v[k], 4);
  return out;
}

/// find_joint(), its error a usage error of `option`.
int joint_named(const Skeleton& skeleton, const std::string& option, const std::string& name) {
  try {
    return synth::find_joint(skeleton, name);
  } catch (const ParameterError& e) {
    throw CLI::ValidationError(option, e.what());
  }
}

}  // namespace

void setup_reach(CLI::App& app) {
  auto cmd = std::make_shared<ReachCommand>();
  auto* sub = app.add_subcommand(
      "reach",
      "Pose by dragging a joint: find the point of the clips' map whose blended pose brings\n"
      "--joint closest to the position --to (among the map's valid points: every pose is a\n"
      "blend of real frames), write that pose as a one-frame BVH and print the remaining error\n"
      "and the map point. Positions are in the frame of `motionmap pose`'s poses: the root at the\n"
      "floor origin facing the heading-0 direction (+Z for Y-up files).\n"
      "The map: computed from FILE…, read with --map map.csv, or a saved map --map lib.mmap.h5.");
  add_blend_options(
      sub, cmd->o,
      "A saved map (lib.mmap.h5 from `motionmap map --save`): no FILE, its clips are loaded "
      "from the paths it records and checked against their SHA-256; or a map CSV from "
      "`motionmap map` on the same files and options");
  sub->add_option("--joint", cmd->joint, "The joint to move, by name (e.g. LeftHand, Hand_L, Head)")
      ->required();
  sub->add_option("--to", cmd->to, "Its target position x,y,z (write --to=x,y,z when x < 0)")
      ->required();
  sub->add_option("--pin", cmd->pins,
                  "NAME=x,y,z: a joint that should stay at x,y,z; NAME alone: where it is in the "
                  "pose at --from. Repeatable")
      ->expected(1)
      ->take_all();
  sub->add_option("--pin-weight", cmd->pin_weight,
                  "Weight of each pin against the target's 1 (default 1)")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--from", cmd->from,
                  "The map point X,Y of the pose being dragged: the search starts there and "
                  "prefers to stay near it (write --from=X,Y when X < 0)");
  sub->add_option("--evaluations", cmd->evaluations,
                  "Most pose evaluations the search spends (default 200)")
      ->check(CLI::Range(8, 1000000));
  sub->add_option("-o,--output", cmd->output, "BVH file to write")->required();
  sub->add_flag("--json", cmd->json,
                "Print the result as one JSON object on stdout instead of lines of text");
  sub->callback([cmd] {
    const Eigen::Vector3d target = parse_position("--to", cmd->to);
    std::optional<Eigen::Vector2d> from;
    if (!cmd->from.empty()) {
      from = parse_numbers<2>(cmd->from);
      if (!from) {
        throw CLI::ValidationError("--from", "'" + cmd->from +
                                                 "' is not a map point X,Y of two finite numbers "
                                                 "(write --from=X,Y when X is negative)");
      }
    }
    struct PinText {
      std::string name;
      std::optional<Eigen::Vector3d> position;
    };
    std::vector<PinText> pin_texts;
    for (const std::string& text : cmd->pins) {
      const std::size_t eq = text.find('=');
      PinText pin{text.substr(0, eq), std::nullopt};
      if (eq != std::string::npos) pin.position = parse_position("--pin", text.substr(eq + 1));
      if (!pin.position && !from) {
        throw CLI::ValidationError("--pin", "'" + text + "': give the position it keeps (--pin " +
                                                pin.name +
                                                "=x,y,z) or the pose it is kept from (--from X,Y)");
      }
      pin_texts.push_back(pin);
    }

    const PreparedBlender prepared = prepare_blender(cmd->o, "reach");
    const synth::MapBlender& blender = *prepared.blender;
    const Skeleton& skeleton = blender.skeleton();
    synth::ReachGoal goal;
    goal.joint = joint_named(skeleton, "--joint", cmd->joint);
    goal.target = target;
    goal.start = from;
    std::optional<WorldPose> from_pose;
    if (from) from_pose = forward_kinematics(skeleton, blender.pose_at(*from), 0);
    for (const PinText& pin : pin_texts) {
      const int j = joint_named(skeleton, "--pin", pin.name);
      goal.pins.push_back({j, pin.position ? *pin.position : from_pose->positions[std::size_t(j)],
                           cmd->pin_weight});
    }
    synth::ReachOptions options;
    options.max_evaluations = cmd->evaluations;
    const synth::Reacher reacher(blender, progress_line(cmd->o.map, "reach"));
    const synth::ReachResult r = reacher.reach(goal, options);
    io::write_bvh(io::from_motion(skeleton, r.pose), cmd->output);

    const int nearest = r.validity.nearest_sample;
    const std::string nearest_clip =
        prepared.clip_paths[std::size_t(prepared.samples.clip_of[std::size_t(nearest)])];
    const int nearest_frame = prepared.samples.frame_of[std::size_t(nearest)];
    const double percent = 100.0 * r.error_fraction;
    const std::string joint_name = skeleton.joints[std::size_t(goal.joint)].name;
    if (cmd->json) {
      std::string pins;
      for (std::size_t k = 0; k < goal.pins.size(); ++k) {
        pins += std::string(k ? "," : "") + "{\"joint\":\"" +
                json_escape(skeleton.joints[std::size_t(goal.pins[k].joint)].name) +
                "\",\"position\":" + json_array(goal.pins[k].position) +
                ",\"weight\":" + json_number(goal.pins[k].weight) +
                ",\"error\":" + json_number(r.pin_errors[k]) + "}";
      }
      std::cout << "{\"joint\":\"" << json_escape(joint_name)
                << "\",\"target\":" << json_array(goal.target)
                << ",\"reached\":" << json_array(r.reached) << ",\"error\":" << json_number(r.error)
                << ",\"error_percent\":" << json_number(percent)
                << ",\"height\":" << json_number(r.height) << ",\"point\":" << json_array(r.point)
                << ",\"distance\":" << json_number(r.validity.distance)
                << ",\"reach_distance\":" << json_number(blender.reach_distance())
                << ",\"nearest_sample\":{\"clip\":\"" << json_escape(nearest_clip)
                << "\",\"frame\":" << nearest_frame << "},\"pins\":[" << pins
                << "],\"evaluations\":" << r.evaluations << ",\"output\":\""
                << json_escape(cmd->output) << "\"}\n";
    } else {
      std::cout << "map point: " << format_number(r.point.x()) << "," << format_number(r.point.y())
                << "\n";
      std::cout << "error: " << format_number(r.error, 4) << " (" << format_number(percent, 4)
                << " % of the body's height " << format_number(r.height, 4) << "): " << joint_name
                << " at " << text_point(r.reached) << ", target " << text_point(goal.target)
                << "\n";
      for (std::size_t k = 0; k < goal.pins.size(); ++k) {
        std::cout << "pin " << skeleton.joints[std::size_t(goal.pins[k].joint)].name << ": "
                  << format_number(r.pin_errors[k], 4) << " from "
                  << text_point(goal.pins[k].position) << "\n";
      }
    }
    if (!cmd->o.map.quiet) {
      std::cerr << "wrote " << cmd->output << ": 1 frame; nearest sample: " << nearest_clip
                << " frame " << nearest_frame << " at " << format_number(r.validity.distance, 4)
                << " (reach " << format_number(blender.reach_distance(), 4) << "), "
                << r.evaluations << " poses evaluated\n";
    }
  });
}

}  // namespace motionmap::cli
