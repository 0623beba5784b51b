// `motionmap inbetween FILE… --keys walk.bvh:9,walk.bvh:40 -o out.bvh`: a motion through key
// poses, each segment following a route through the clips' own frames (--route clips) or the
// cheapest route through the valid region of the clips' map (--route grid) (synth/inbetween.h;
// docs/synthesis.md, "Key poses and in-betweening"). With `--map lib.mmap.h5`
// no FILE is given: the saved map's clips are loaded on demand and checked against their SHA-256.
//
// A key is FILE:FRAME (a frame, 0-based, of any clip of the map's skeleton, FILE a path or the end
// of a map clip's path; a frame that is not a sample of the map is placed on it as `map --onto`
// places frames) or X:Y (a map point), either followed by @SECONDS.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <type_traits>

#include "blend_setup.h"
#include "commands.h"
#include "map_options.h"
#include "motionmap/core/error.h"
#include "motionmap/core/files.h"
#include "motionmap/core/format.h"
#include "motionmap/io/bvh.h"
#include "motionmap/io/load.h"
#include "motionmap/mapfile/frame_key.h"
#include "motionmap/mapfile/map_file.h"
#include "motionmap/mapfile/saved_map.h"
#include "motionmap/synth/inbetween.h"

namespace motionmap::cli {

namespace {

struct InbetweenCommand {
  BlendCliOptions o;
  std::vector<std::string> keys;
  int frames_between = -1;
  std::vector<double> times;
  std::string route = "clips";
  int grid = 0;
  bool no_smooth = false;
  bool no_clean_feet = false;
  bool free_roots = false;
  std::string output;
  std::string route_csv;
};

// A key as written: FILE:FRAME or X:Y, and its time.
struct KeyText {
  std::string text;
  std::string file;    // empty for a map point
  bool named = false;  // `file` is no file here: the name of one of the map's clips
  int frame = 0;
  Eigen::Vector2d point = Eigen::Vector2d::Zero();
  std::optional<double> time;
};

template <class T>
bool parse_whole(std::string_view s, T& value) {
  if (s.empty()) return false;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec != std::errc() || ptr != s.data() + s.size()) return false;
  if constexpr (std::is_floating_point_v<T>) return std::isfinite(value);
  return true;
}

KeyText parse_key(const std::string& text) {
  KeyText key;
  key.text = text;
  std::string_view body = text;
  const auto bad = [&](const std::string& why) {
    return CLI::ValidationError("--keys", "'" + text + "': " + why);
  };
  if (const auto at = body.rfind('@'); at != std::string_view::npos && at > body.rfind(':')) {
    double t = 0.0;
    if (!parse_whole(body.substr(at + 1), t))
      throw bad("the time after '@' is not a finite number of seconds");
    key.time = t;
    body = body.substr(0, at);
  }
  const auto colon = body.rfind(':');
  if (colon == std::string_view::npos) {
    throw bad(
        "a key is FILE:FRAME (a clip and a frame, from 0) or X:Y (a map point), with an "
        "optional @SECONDS");
  }
  const std::string_view left = body.substr(0, colon), right = body.substr(colon + 1);
  std::error_code ec;
  if (std::filesystem::is_regular_file(std::string(left), ec)) {
    key.file = std::string(left);
    if (!parse_whole(right, key.frame) || key.frame < 0)
      throw bad("'" + std::string(right) + "' is not a frame number (0, 1, …)");
    return key;
  }
  if (parse_whole(left, key.point.x()) && parse_whole(right, key.point.y())) return key;
  if (!left.empty() && parse_whole(right, key.frame)) {
    if (key.frame < 0) throw bad("'" + std::string(right) + "' is not a frame number (0, 1, …)");
    key.file = std::string(left);
    key.named = true;
    return key;
  }
  throw bad(
      "neither FILE:FRAME (a clip file, or a clip of the map by name, and a frame number) nor X:Y "
      "(a map point)");
}

// Keys that name no file here name a clip of the map (mapfile::map_clip_named of `clips`, the
// map's clip files). @throws CLI::ValidationError when none or several do.
void resolve_names(std::vector<KeyText>& keys, const std::vector<std::string>& clips) {
  for (KeyText& key : keys) {
    if (!key.named) continue;
    try {
      key.file = mapfile::map_clip_named(clips, key.file);
    } catch (const ParameterError& e) {
      throw CLI::ValidationError("--keys", "'" + key.text + "': " + e.what());
    }
    key.named = false;
  }
}

// The map, its blender and what placing frames on it needs.
struct Prepared {
  PreparedBlender b;
  std::vector<std::string> clip_files;  // per map clip: the file it was read from
  Clip reference;                       // a clip of the map, for the skeleton check
  // Placing: the map as a MapFile with its model, made or read when a key first needs it.
  std::function<const mapfile::MapFile&()> map_file;
};

Prepared prepare(const InbetweenCommand& cmd) {
  Prepared p;
  p.b = prepare_blender(cmd.o, "inbetween", /*csv_allowed=*/false);
  if (const auto saved = p.b.saved) {
    for (int c = 0; c < saved->num_clips(); ++c) p.clip_files.push_back(saved->resolve_path(c));
    p.reference = *saved->clip(0);
    auto with_model = std::make_shared<std::optional<mapfile::MapFile>>();
    p.map_file = [with_model, path = cmd.o.map_path]() -> const mapfile::MapFile& {
      if (!*with_model) *with_model = mapfile::read_map_file(path);
      return **with_model;
    };
    return p;
  }
  p.clip_files = p.b.clip_paths;
  p.reference = p.b.clips->front();
  auto file = std::make_shared<std::optional<mapfile::MapFile>>();
  p.map_file = [file, clips = p.b.clips, map = p.b.map,
                options = p.b.options]() -> const mapfile::MapFile& {
    if (!*file) *file = mapfile::make_map_file(*clips, std::move(*map), options);
    return **file;
  };
  return p;
}

// The keys on the map: FILE:FRAME at its sample's point, or placed (mapfile::frame_key); X:Y as
// it is.
std::vector<synth::Key> resolve_keys(const InbetweenCommand& cmd, const std::vector<KeyText>& texts,
                                     Prepared& p) {
  std::map<std::string, std::shared_ptr<const Clip>> loaded;
  io::LoadOptions load;
  load.asf_path = cmd.o.map.asf;
  load.fps = cmd.o.map.fps;
  mapfile::KeyMap on;
  on.blender = p.b.blender.get();
  on.samples = &p.b.samples;
  on.clip_files = p.clip_files;
  on.reference = &p.reference;
  on.map_file = p.map_file;
  std::vector<synth::Key> keys;
  for (const KeyText& t : texts) {
    synth::Key key;
    if (t.file.empty()) {
      key.point = t.point;
    } else {
      auto& clip = loaded[t.file];
      if (!clip) {
        try {
          clip = std::make_shared<const Clip>(io::load_clip(t.file, load));
        } catch (const Error& e) {
          throw Error("--keys " + t.text + ": the clip cannot be loaded: " + e.what());
        }
      }
      mapfile::FrameKey found;
      try {
        found = mapfile::frame_key(on, *clip, t.frame);
      } catch (const ParameterError& e) {
        throw ParameterError("--keys " + t.text + ": " + e.what());
      }
      key = std::move(found.key);
      if (found.placed && !cmd.o.map.quiet) {
        std::cerr << "note: key " << t.text << " is not a sample of the map: placed at ("
                  << format_number(key.point.x(), 4) << ", " << format_number(key.point.y(), 4)
                  << ") as `map --onto` places frames\n";
      }
    }
    key.label = t.text;
    key.time = t.time;
    keys.push_back(std::move(key));
  }
  return keys;
}

void write_route_csv(const std::string& path, const synth::InbetweenResult& r,
                     const std::vector<synth::Key>& keys) {
  std::ofstream out(path);
  if (!out) throw Error(path + ": cannot write the route CSV");
  out << "# the map point of every frame of the in-betweened motion (a path `motionmap synth "
         "--path` reads)\n";
  for (std::size_t i = 0; i < keys.size(); ++i) {
    out << "# key " << i + 1 << " " << keys[i].label << " at frame " << r.key_frames[i] << '\n';
  }
  out << "t,x,y\n";
  char buf[96];
  for (std::size_t k = 0; k < r.points.size(); ++k) {
    std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g\n",
                  static_cast<double>(k) * r.motion.frame_time, r.points[k].x(), r.points[k].y());
    out << buf;
  }
  if (!out.flush()) throw Error(path + ": cannot write the route CSV");
}

}  // namespace

void setup_inbetween(CLI::App& app) {
  auto cmd = std::make_shared<InbetweenCommand>();
  auto* sub = app.add_subcommand(
      "inbetween",
      "In-betweening: a motion through key poses, exactly, each segment playing the clips' own\n"
      "frames (jumping between clips where their poses meet on the map; --route grid: the\n"
      "cheapest route through the valid region of the map), written as BVH.\n"
      "A key is FILE:FRAME (frame from 0 of any clip of the map's skeleton; FILE a path, or the\n"
      "end of a map clip's path, e.g. walk.bvh; a frame that is not a sample of the map is placed\n"
      "on it as `map --onto` does) or X:Y (a map point), each with an optional @SECONDS.\n"
      "Then each foot is held still through its contacts with the floor, the keys' frames left\n"
      "exact (--no-clean-feet: not).\n"
      "The map: computed from FILE…, or a saved map --map lib.mmap.h5.");
  add_blend_options(sub, cmd->o,
                    "A saved map (lib.mmap.h5 from `motionmap map --save`): no FILE, its clips "
                    "are loaded from the paths it records and checked against their SHA-256");
  sub->add_option("--keys", cmd->keys,
                  "The keys, comma-separated, at least 2: FILE:FRAME or X:Y, each optionally "
                  "@SECONDS (then every key needs a time), e.g. walk.bvh:9,walk.bvh:40 or "
                  "--keys=-1.5:0.2@0,walk.bvh:40@1.2")
      ->required()
      ->delimiter(',');
  auto* between = sub->add_option("--frames-between", cmd->frames_between,
                                  "Frames between consecutive keys (default: the keys' times, or "
                                  "the samples' own speed along each route, at least the time "
                                  "the clips take to walk the keys' distance; keys of one clip: "
                                  "its own time between them; keys of two clips: at least "
                                  "the " +
                                      format_number(synth::kJumpFadeSeconds) +
                                      " s of a jump's crossfade, and of two gaits (walks, "
                                      "runs) the nearest time at which the later key's gait "
                                      "phase comes round; far fewer frames make the root "
                                      "glide, or the legs step out of the gait's time, with a "
                                      "note)")
                      ->check(CLI::Range(0, synth::kMaxFramesBetween));
  sub->add_option("--times", cmd->times,
                  "Seconds of each key, comma-separated, increasing (instead of @SECONDS on "
                  "each key); keys land on the nearest frames")
      ->delimiter(',')
      ->excludes(between);
  sub->add_option("--route", cmd->route,
                  "How the motion goes from key to key: clips (the default: the clips' own frames "
                  "played on, jumping between clips where their map points meet, crossfaded; "
                  "where no jumps join two keys' clips, each played towards the middle) or grid "
                  "(Shin & Lee's cheapest path through the valid region, blended along)")
      ->check(CLI::IsMember({"clips", "grid"}));
  sub->add_option("--grid", cmd->grid,
                  "Route grid: cells along the longer side of the map (default: from the map's "
                  "density, cells of half the reach, 20 to 200)")
      ->check(CLI::Range(2, synth::kMaxGridOption));
  sub->add_flag("--no-smooth", cmd->no_smooth,
                "Follow the grid's cells instead of the smoothed route");
  sub->add_flag("--no-clean-feet", cmd->no_clean_feet,
                "Keep the feet as blended: by default each foot is held still through its "
                "contacts with the floor (docs/synthesis.md, \"Clean feet\"), the keys' frames "
                "left exact");
  sub->add_flag("--free-roots", cmd->free_roots,
                "Only the first key's root stands where it stood in its clip; each later key's "
                "pose is still exact, its root where the clips carry it (for keys of takes "
                "captured in different places, between which the root would glide)");
  sub->add_option("-o,--output", cmd->output, "BVH file to write (the map's skeleton)")->required();
  sub->add_option("--route-csv", cmd->route_csv,
                  "Also write the map point of every frame as t,x,y rows (a path `synth` reads; "
                  "the keys in # lines)");
  sub->callback([cmd] {
    std::vector<KeyText> texts;
    for (const std::string& k : cmd->keys) texts.push_back(parse_key(k));
    if (texts.size() < 2) {
      throw CLI::ValidationError(
          "--keys", "give at least 2 keys (" + std::to_string(texts.size()) + " given)");
    }
    if (!cmd->times.empty()) {
      if (cmd->times.size() != texts.size()) {
        throw CLI::ValidationError("--times", std::to_string(cmd->times.size()) + " times for " +
                                                  std::to_string(texts.size()) +
                                                  " keys; give one per key");
      }
      for (std::size_t i = 0; i < texts.size(); ++i) {
        if (texts[i].time) {
          throw CLI::ValidationError("--times", "key '" + texts[i].text +
                                                    "' has its own @time; give times either "
                                                    "with --times or with @ on every key");
        }
        texts[i].time = cmd->times[i];
      }
    }
    // Keys naming a clip of the map: the clips given are checked before their map is made; a
    // saved map's, once it is read (which reads no clip).
    const bool named = std::any_of(texts.begin(), texts.end(), [](auto& t) { return t.named; });
    if (named && cmd->o.map_path.empty()) resolve_names(texts, input_paths(cmd->o.map));
    Prepared p = prepare(*cmd);
    if (named) resolve_names(texts, p.clip_files);
    const std::vector<synth::Key> keys = resolve_keys(*cmd, texts, p);
    synth::InbetweenOptions options;
    options.frames_between = cmd->frames_between;
    options.route.mode = synth::parse_route_mode(cmd->route);
    options.route.grid = cmd->grid;
    options.route.smooth = !cmd->no_smooth;
    options.clean_feet = !cmd->no_clean_feet;
    options.free_roots = cmd->free_roots;
    const Control line = progress_line(cmd->o.map, "inbetween");
    const synth::InbetweenResult r =
        synth::inbetween(*p.b.blender, p.b.samples, keys, options, line);
    if (r.outside_frames > 0) {
      std::cerr << "note: " << r.outside_frames << " of " << r.motion.num_frames
                << " frames lie outside the data (" << outside_rule(*p.b.blender)
                << ": a key outside the data, or a gap between parts of the "
                   "map that the route had to cross) and were blended at the nearest edge of the "
                   "data\n";
    }
    for (const std::string& note : r.notes) std::cerr << "note: " << note << '\n';
    io::write_bvh(io::from_motion(p.b.blender->skeleton(), r.motion), cmd->output);
    if (!cmd->route_csv.empty()) write_route_csv(cmd->route_csv, r, keys);
    std::string at;
    for (std::size_t i = 0; i < r.key_frames.size(); ++i)
      at += (i ? ", " : "") + std::to_string(r.key_frames[i]);
    std::cerr << "wrote " << cmd->output << ": " << r.motion.num_frames << " frames at "
              << format_number(r.motion.fps(), 4) << " fps ("
              << format_number(r.motion.duration(), 4) << " s); keys at frames " << at
              << (options.route.mode == synth::RouteMode::Clips
                      ? std::string("; routes through the clips' frames")
                      : "; route grid " + std::to_string(r.grid.nx) + "×" +
                            std::to_string(r.grid.ny))
              << "\n";
  });
}

}  // namespace motionmap::cli
