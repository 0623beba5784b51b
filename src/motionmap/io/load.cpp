#include "motionmap/io/load.h"

#include <filesystem>
#include <string>
#include <vector>

#include "motionmap/core/error.h"
#include "motionmap/core/files.h"
#include "motionmap/core/sha256.h"
#include "motionmap/core/text_cursor.h"
#include "motionmap/io/amc.h"
#include "motionmap/io/bvh.h"

namespace motionmap::io {

namespace fs = std::filesystem;

namespace {

std::string lower_extension(const std::string& path) {
  return ascii_lower(fs::path(path).extension().string());
}

// CMU names takes SUBJECT_TRIAL.amc next to SUBJECT.asf; otherwise accept a lone .asf.
std::string find_asf_for(const std::string& amc_path) {
  const fs::path amc(amc_path);
  const fs::path dir = amc.has_parent_path() ? amc.parent_path() : fs::path(".");
  const std::string stem = amc.stem().string();
  if (const auto underscore = stem.find('_'); underscore != std::string::npos) {
    const fs::path candidate = dir / (stem.substr(0, underscore) + ".asf");
    if (fs::exists(candidate)) return candidate.string();
  }
  std::vector<fs::path> found;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    if (lower_extension(entry.path().string()) == ".asf") found.push_back(entry.path());
  }
  if (found.size() == 1) return found.front().string();
  throw Error(amc_path + ": error: cannot tell which .asf skeleton belongs to this motion (" +
              std::to_string(found.size()) + " .asf files beside it); pass it explicitly (--asf)");
}

// The clip in `path`, as its format's loader produced it (with the fps override applied), and
// the SHA-256 of the bytes parsed when asked for.
Clip read_clip(const std::string& path, const LoadOptions& options) {
  const std::string ext = lower_extension(path);
  if (ext == ".asf") {
    throw Error(path +
                ": error: an .asf file holds only a skeleton; open the .amc motion (with "
                "--asf " +
                path + ")");
  }
  if (ext != ".bvh" && ext != ".amc") {
    throw Error(path + ": error: unknown file type '" + ext + "', expected .bvh or .amc");
  }
  // An .amc's skeleton is found before its motion is read (a missing .asf is the first error).
  const std::string asf =
      ext == ".amc" && options.asf_path.empty() ? find_asf_for(path) : options.asf_path;
  const std::string text = read_text_file(path);
  Clip clip;
  if (ext == ".bvh") {
    clip = load_bvh_text(text, path);
    if (options.fps > 0) clip.motion.frame_time = 1.0 / options.fps;
  } else {
    clip = load_asf_amc_text(asf, path, text, options.fps > 0 ? options.fps : 120.0);
  }
  if (options.sha256) clip.sha256 = sha256_hex(text);
  return clip;
}

}  // namespace

Clip load_clip(const std::string& path, const LoadOptions& options) {
  Clip clip = read_clip(path, options);
  // What the loaders or an fps override produce is what the rest of the library trusts.
  check_clip(clip);
  return clip;
}

}  // namespace motionmap::io
