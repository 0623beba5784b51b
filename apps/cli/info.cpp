// `motionmap info FILE…`: what a clip holds and what looks wrong in it.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>

#include "commands.h"
#include "motionmap/core/error.h"
#include "motionmap/features/diagnostics.h"
#include "motionmap/io/load.h"
#include "motionmap/mapfile/map_file.h"
#include "motionmap/skeleton/contacts.h"
#include "motionmap/skeleton/forward_kinematics.h"

namespace motionmap::cli {

namespace {

struct InfoOptions {
  std::vector<std::string> files;
  std::string asf;
  double fps = 0.0;
  bool json = false;
  bool contacts = false;
  bool skating = false;
  bool keep_first = false;
  std::string up = "y";
};

struct ClipSummary {
  Eigen::Vector3d box_min = Eigen::Vector3d::Zero();
  Eigen::Vector3d box_max = Eigen::Vector3d::Zero();
  std::vector<std::string> warnings;
  LengthUnits units;
  // --contacts, --skating: the feet, or why there are none.
  std::optional<Feet> feet;
  std::string no_feet;
  // The frame the feet are looked at from: 1 when frame 0 is a bind pose, left out as `map`
  // leaves it out (the T-pose of CMU's 02_03 jog stands 5 cm under the jog's lowest ankles, and
  // with it the skating measure read 3 of 173 transitions skating instead of 37 of 172).
  int first = 0;
  std::array<FootContacts, 2> contacts;
  Skating skating;
};

ClipSummary summarize(const Clip& clip, const InfoOptions& opt) {
  ClipSummary s;
  s.units = detect_length_units(clip.skeleton, clip.motion);
  if (opt.contacts || opt.skating) {
    const Axis up = parse_axis(opt.up).value_or(Axis::Y);  // --up accepts only y and z
    s.feet = try_find_feet(clip.skeleton, up, &s.no_feet);
    if (s.feet && !opt.keep_first && clip.motion.num_frames >= 3 &&
        features::check_leading_bind_pose(
            features::heading_local_points(clip.skeleton, clip.motion, up))
            .detected)
      s.first = 1;
    const Motion trimmed =
        s.first > 0 ? clip.motion.frames(s.first, clip.motion.num_frames) : Motion();
    const Motion& motion = s.first > 0 ? trimmed : clip.motion;
    if (s.feet && opt.contacts) {
      ContactOptions co;
      co.up = up;
      s.contacts = detect_contacts(clip.skeleton, motion, *s.feet, co);
      for (FootContacts& fc : s.contacts) {
        for (ContactInterval& c : fc.intervals) {
          c.first += s.first;
          c.last += s.first;
        }
      }
    }
    if (s.feet && opt.skating)
      s.skating = measure_skating(clip.skeleton, motion, *s.feet, s.units, up);
  }
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

std::string units_text(const LengthUnits& u) {
  const std::string size = num(u.size) + " (" + num(u.size * u.metres_per_unit) + " m)";
  return std::string(length_unit_name(u.unit)) +
         (u.plausible ? ", detected from the body's size " + size
                      : "? the body's size " + size + " does not look human");
}

std::string seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", s);
  return buf;
}

void print_text(const Clip& clip, const ClipSummary& s, const InfoOptions& opt) {
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
            << "  bounding    min " << vec(s.box_min) << "  max " << vec(s.box_max) << " ("
            << units_text(s.units) << ")\n";
  if ((opt.contacts || opt.skating) && !s.feet) std::cout << "  feet        " << s.no_feet << '\n';
  if ((opt.contacts || opt.skating) && s.first > 0) {
    std::cout << "  feet        from frame " << s.first
              << ": frame 0 looks like a bind pose (--keep-first looks at it too)\n";
  }
  if (opt.contacts && s.feet) {
    for (const FootContacts& fc : s.contacts) {
      std::cout << "  contacts    " << foot_side_name(fc.leg.side) << " ("
                << sk.joints[fc.leg.ankle].name << "): " << fc.intervals.size() << '\n';
      for (const ContactInterval& c : fc.intervals) {
        std::cout << "    - frames " << c.first << "-" << c.last << " ("
                  << seconds(c.first * m.frame_time) << "-" << seconds((c.last + 1) * m.frame_time)
                  << " s)\n";
      }
    }
  }
  if (opt.skating && s.feet) {
    const Skating& k = s.skating;
    std::cout << "  skating     ratio " << num(k.ratio) << " (" << k.skating_transitions << " of "
              << k.transitions << " frame transitions), in contact " << num(k.contact_speed_cm_s)
              << " cm/s, a foot up " << seconds(k.longest_raised_s) << " s at most (ankles "
              << sk.joints[s.feet->legs[0].ankle].name << ", "
              << sk.joints[s.feet->legs[1].ankle].name << "; units "
              << length_unit_name(k.units.unit) << ")\n";
  }
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

// A map file (`map --save`): its method, size and clips, and each label's values with counts.
void print_map_file(const std::string& path, bool json) {
  mapfile::ReadOptions read;
  read.model = false;  // what info shows needs no model
  const mapfile::MapFile f = mapfile::read_map_file(path, read);
  const std::string method(embed::method_name(f.options.embed.method));
  if (json) {
    std::cout << "{\"file\":\"" << json_escape(path) << "\",\"map\":{\"method\":\"" << method
              << "\",\"dims\":" << f.coordinates.cols() << ",\"samples\":" << f.num_samples()
              << ",\"clips\":" << f.clips.size() << ",\"parameters\":\""
              << json_escape(f.parameters) << "\",\"labels\":{";
    for (std::size_t l = 0; l < f.labels.columns.size(); ++l) {
      const pipeline::LabelColumn& column = f.labels.columns[l];
      const std::vector<int> counts = column.counts();
      std::cout << (l ? "," : "") << '"' << json_escape(column.name) << "\":{";
      for (std::size_t c = 0; c < counts.size(); ++c) {
        std::cout << (c ? "," : "") << '"' << json_escape(column.categories[c])
                  << "\":" << counts[c];
      }
      std::cout << '}';
    }
    std::cout << "}}}\n";
    return;
  }
  std::cout << path << ": map file, " << method << ", " << f.coordinates.cols() << " dims, "
            << f.num_samples() << " frames of " << f.clips.size()
            << (f.clips.size() == 1 ? " clip\n" : " clips\n");
  std::cout << "  parameters  " << f.parameters << '\n';
  for (const std::string& note : f.read_notes) std::cout << "  note        " << note << '\n';
  if (f.labels.empty()) {
    std::cout << "  labels      none\n";
    return;
  }
  std::cout << "  labels      " << f.labels.columns.size() << '\n';
  for (const pipeline::LabelColumn& column : f.labels.columns) {
    const std::vector<int> counts = column.counts();
    std::cout << "    " << column.name << " (" << counts.size()
              << (counts.size() == 1 ? " value):" : " values):");
    for (std::size_t c = 0; c < counts.size(); ++c) {
      std::cout << (c ? ", " : " ")
                << (column.categories[c].empty() ? "(none)" : column.categories[c]) << ' '
                << counts[c];
    }
    std::cout << '\n';
  }
}

void print_json(const Clip& clip, const ClipSummary& s, const InfoOptions& opt) {
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
            << ",\"max\":" << json_vec(s.box_max) << "},\"warnings\":[" << warnings << "]";
  if (opt.contacts || opt.skating) {
    std::cout << ",\"units\":\"" << json_escape(std::string(length_unit_name(s.units.unit)))
              << "\",\"metres_per_unit\":" << num(s.units.metres_per_unit);
    if (!s.feet) std::cout << ",\"feet\":null,\"no_feet\":\"" << json_escape(s.no_feet) << "\"";
    if (s.feet) std::cout << ",\"feet_from_frame\":" << s.first;
  }
  if (opt.contacts && s.feet) {
    std::cout << ",\"contacts\":{";
    for (std::size_t i = 0; i < s.contacts.size(); ++i) {
      const FootContacts& fc = s.contacts[i];
      std::cout << (i ? "," : "") << "\"" << foot_side_name(fc.leg.side) << "\":[";
      for (std::size_t c = 0; c < fc.intervals.size(); ++c) {
        std::cout << (c ? "," : "") << "[" << fc.intervals[c].first << "," << fc.intervals[c].last
                  << "]";
      }
      std::cout << "]";
    }
    std::cout << "}";
  }
  if (opt.skating && s.feet) {
    const double speed = s.skating.contact_speed_cm_s;
    std::cout << ",\"skating\":{\"ratio\":" << num(s.skating.ratio)
              << ",\"contact_speed_cm_s\":" << (std::isfinite(speed) ? num(speed) : "null")
              << ",\"transitions\":" << s.skating.transitions
              << ",\"skating_transitions\":" << s.skating.skating_transitions
              << ",\"longest_raised_s\":" << num(s.skating.longest_raised_s) << "}";
  }
  std::cout << "}\n";
}

}  // namespace

void setup_info(CLI::App& app) {
  auto opt = std::make_shared<InfoOptions>();
  auto* sub = app.add_subcommand(
      "info",
      "Print what clips hold: joints, roots, channels, frames, fps, duration, bounding box, and\n"
      "warnings (what the reader accepted with a warning, e.g. a BVH root declared with JOINT;\n"
      "a leading bind/T-pose frame; joints whose rotation flips by >90° between consecutive\n"
      "frames at ≥ 60 fps, with the frames), and the length unit detected from the body's size\n"
      "(m, CMU units, in, cm or mm). --contacts and --skating look at the feet. A map file\n"
      "(map --save) shows its method, size and labels with each value's count.");
  sub->add_option("files", opt->files, "BVH or AMC files, or map files (.mmap.h5)")
      ->required()
      ->check(CLI::ExistingFile);
  sub->add_option("--asf", opt->asf, "ASF skeleton for .amc files (default: the .asf beside it)")
      ->check(CLI::ExistingFile);
  sub->add_option("--fps", opt->fps, "Frame rate to assume (AMC stores none: default 120)")
      ->check(CLI::PositiveNumber);
  sub->add_flag(
      "--json", opt->json,
      "One JSON object per file and line: joints, roots, root_names, channels, "
      "end_sites, frames, frame_time, fps, duration, bounding_box, warnings (and with "
      "--contacts/--skating: units, metres_per_unit, feet_from_frame, contacts {left, "
      "right: [[first, last], …]}, skating {ratio, contact_speed_cm_s, transitions, "
      "skating_transitions, longest_raised_s}; feet null and no_feet when none are found)");
  sub->add_flag("--contacts", opt->contacts,
                "Each foot's contacts with the floor, as frame intervals and seconds: the ankle "
                "within 6 % of the leg length of its floor level, slower than 1 leg length per "
                "second horizontally and 0.1 up or down (docs/synthesis.md)");
  sub->add_flag(
      "--skating", opt->skating,
      "The skating measure: the fraction of frame transitions where a foot (ankle) "
      "less than 5 cm above its lowest point moves faster than 0.5 m/s horizontally, "
      "the ankles' mean horizontal speed in contact (cm/s), in the units detected, and the "
      "longest a foot stays 5 cm or more above its lowest (s): a foot held up never "
      "skates");
  sub->add_flag("--keep-first", opt->keep_first,
                "--contacts and --skating look at a leading bind/T-pose frame too (by default "
                "they start at frame 1 when frame 0 is one, as `map` does: a T-pose's ankles "
                "stand off the motion's floor)");
  sub->add_option("--up", opt->up,
                  "Up axis of the files for --contacts and --skating: y (default) or z")
      ->check(CLI::IsMember({"y", "z", "Y", "Z"}));
  sub->callback([opt] {
    int failures = 0;
    for (const auto& file : opt->files) {
      try {
        if (mapfile::looks_like_map_file(file)) {
          print_map_file(file, opt->json);
          continue;
        }
        io::LoadOptions load;
        load.asf_path = opt->asf;
        load.fps = opt->fps;
        const Clip clip = io::load_clip(file, load);
        const ClipSummary s = summarize(clip, *opt);
        if (opt->json) {
          print_json(clip, s, *opt);
        } else {
          print_text(clip, s, *opt);
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
