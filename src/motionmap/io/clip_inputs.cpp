#include "motionmap/io/clip_inputs.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <filesystem>
#include <optional>

#include "motionmap/core/error.h"
#include "motionmap/core/files.h"
#include "motionmap/core/format.h"
#include "motionmap/core/parallel.h"
#include "motionmap/core/text_cursor.h"

namespace motionmap::io {

namespace fs = std::filesystem;

namespace {

bool hidden(const fs::path& p) {
  const std::string name = p.filename().string();
  return !name.empty() && name.front() == '.';
}

}  // namespace

bool is_clip_file(std::string_view path) {
  const std::string ext = ascii_lower(fs::path(path).extension().string());
  return ext == ".bvh" || ext == ".amc";
}

std::vector<std::string> clip_files_in_folder(const std::string& folder,
                                              const ExpandOptions& options) {
  std::vector<std::string> out;
  std::error_code ec;
  auto fail = [&](const std::error_code& e) {
    throw Error(folder + ": error: cannot read the folder: " + e.message());
  };
  auto take = [&](const fs::directory_entry& entry) {
    std::error_code type_ec;
    if (entry.is_regular_file(type_ec) && is_clip_file(entry.path().string())) {
      out.push_back(entry.path().string());
    }
  };
  if (options.recursive) {
    fs::recursive_directory_iterator it(folder, fs::directory_options::skip_permission_denied, ec);
    if (ec) fail(ec);
    for (const fs::recursive_directory_iterator end; it != end; it.increment(ec)) {
      if (ec) fail(ec);
      if (hidden(it->path())) {
        std::error_code dir_ec;
        if (it->is_directory(dir_ec)) it.disable_recursion_pending();
        continue;
      }
      take(*it);
    }
    if (ec) fail(ec);
  } else {
    fs::directory_iterator it(folder, ec);
    if (ec) fail(ec);
    for (const fs::directory_iterator end; it != end; it.increment(ec)) {
      if (ec) fail(ec);
      if (!hidden(it->path())) take(*it);
    }
    if (ec) fail(ec);
  }
  if (out.empty()) {
    throw Error(folder + ": error: no clip (.bvh or .amc file) in this folder" +
                (options.recursive ? std::string(" or its subfolders")
                                   : std::string(" (--recursive looks in its subfolders too)")));
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::string> parse_clip_list(std::string_view text, const std::string& list_path,
                                         const ExpandOptions& options) {
  const fs::path base = fs::path(list_path).parent_path();
  std::vector<std::string> out;
  bool any = false;
  std::size_t line_no = 0;
  std::size_t pos = 0;
  // A UTF-8 byte order mark is not part of the first path.
  if (text.substr(0, 3) == "\xEF\xBB\xBF") pos = 3;
  while (pos <= text.size()) {
    std::size_t end = text.find_first_of("\r\n", pos);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = text.substr(pos, end - pos);
    ++line_no;
    // LF, CRLF and CR line ends.
    pos = end + ((end + 1 < text.size() && text[end] == '\r' && text[end + 1] == '\n') ? 2 : 1);

    const std::size_t first = line.find_first_not_of(" \t");
    if (first == std::string_view::npos || line[first] == '#') continue;
    const std::size_t last = line.find_last_not_of(" \t");
    const std::string entry(line.substr(first, last + 1 - first));
    const fs::path entry_path(entry);
    const fs::path resolved =
        entry_path.is_absolute() || base.empty() ? entry_path : base / entry_path;
    std::error_code ec;
    const fs::file_status status = fs::status(resolved, ec);
    if (!fs::exists(status)) {
      throw ParseError(list_path, line_no, first + 1,
                       "no such file or folder: '" + entry + "'" +
                           (resolved.string() == entry
                                ? std::string()
                                : " (looked for " + resolved.string() +
                                      "; relative paths are relative to the list's folder)"));
    }
    any = true;
    if (fs::is_directory(status)) {
      const auto files = clip_files_in_folder(resolved.string(), options);
      out.insert(out.end(), files.begin(), files.end());
    } else {
      out.push_back(resolved.string());
    }
  }
  if (!any) throw Error(list_path + ": error: the list names no clip");
  return out;
}

std::vector<std::string> read_clip_list(const std::string& list_path,
                                        const ExpandOptions& options) {
  return parse_clip_list(read_text_file(list_path), list_path, options);
}

std::vector<std::string> expand_clip_inputs(std::span<const std::string> inputs,
                                            const ExpandOptions& options) {
  std::vector<std::string> out;
  for (const std::string& input : inputs) {
    if (!input.empty() && input.front() == '@') {
      const auto files = read_clip_list(input.substr(1), options);
      out.insert(out.end(), files.begin(), files.end());
      continue;
    }
    std::error_code ec;
    const fs::file_status status = fs::status(input, ec);
    if (!fs::exists(status)) throw Error(input + ": error: no such file or folder");
    if (fs::is_directory(status)) {
      const auto files = clip_files_in_folder(input, options);
      out.insert(out.end(), files.begin(), files.end());
    } else {
      out.push_back(input);
    }
  }
  return out;
}

LoadedClips load_clips(std::span<const std::string> paths, const LoadClipsOptions& options,
                       const Control& control) {
  if (paths.empty()) throw ParameterError("load_clips: no clip given");
  // A clip per thread (parsing is most of a library's loading); the results are taken in path
  // order, so the clips, the failures and the error thrown are those of a serial loop. Without
  // keep_going, no file after one that failed is started.
  const int n = static_cast<int>(paths.size());
  std::vector<std::optional<Clip>> loaded(paths.size());
  std::vector<std::exception_ptr> errors(paths.size());
  std::atomic<int> first_failure{n};
  std::atomic<long long> frames{0};
  const std::string total = std::to_string(paths.size());
  control.stage("loading 1/" + total + " clips (0 frames)", 0.0, 1.0 / n);
  parallel_chunks(
      n,
      [&](int i, int) {
        if (!options.keep_going && i > first_failure.load()) return;
        try {
          Clip clip = load_clip(paths[std::size_t(i)], options.load);
          frames += clip.motion.num_frames;
          loaded[std::size_t(i)] = std::move(clip);
        } catch (const Error&) {
          errors[std::size_t(i)] = std::current_exception();
          int seen = first_failure.load();
          while (i < seen && !first_failure.compare_exchange_weak(seen, i)) {
          }
        }
      },
      [&](int done) {  // "loaded …" follows the last
        if (done < n) {
          control.stage("loading " + std::to_string(done + 1) + "/" + total + " clips (" +
                            format_count(frames.load()) + " frames)",
                        double(done) / n, double(done + 1) / n);
        }
      });
  LoadedClips out;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    if (errors[i]) {
      if (!options.keep_going) std::rethrow_exception(errors[i]);
      try {
        std::rethrow_exception(errors[i]);
      } catch (const Error& e) {
        out.failures.emplace_back(e.what());
      }
    } else {
      out.frames += loaded[i]->motion.num_frames;
      out.clips.push_back(std::move(*loaded[i]));
    }
  }
  if (out.clips.empty()) throw no_clip_loaded(out.failures, paths.size());
  control.stage(
      "loaded " + std::to_string(out.clips.size()) + " clips (" + format_count(out.frames) +
          " frames)" +
          (out.failures.empty() ? std::string()
                                : ", " + std::to_string(out.failures.size()) + " skipped"),
      1.0, 1.0);
  return out;
}

Error no_clip_loaded(const std::vector<std::string>& failures, std::size_t paths) {
  return Error("no clip could be loaded (" + std::to_string(failures.size()) + " of " +
               std::to_string(paths) + " failed); the first: " +
               (failures.empty() ? std::string("(none recorded)") : failures.front()));
}

}  // namespace motionmap::io
