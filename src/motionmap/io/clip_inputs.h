#pragma once
// Libraries of clips: the inputs of a map — clip files, folders of clips and list files
// (`@takes.txt`) — expanded into the paths of the clips they name, in a fixed order; and loading
// all of them, with progress in clips and frames and, on request, skipping the clips that fail.
//
//   motionmap::io::ExpandOptions expand;
//   expand.recursive = true;                                   // folders' subfolders too
//   const std::vector<std::string> inputs{"takes/", "@more.txt", "64_08.bvh"};
//   auto paths = motionmap::io::expand_clip_inputs(inputs, expand);
//   motionmap::io::LoadClipsOptions load;
//   load.keep_going = true;                                    // skip clips that fail to load
//   auto library = motionmap::io::load_clips(paths, load, control);
//   // library.clips: the clips loaded, in `paths` order; library.failures: what was skipped
//
// What an input is:
//  - `@FILE`: a list file, one path a line. A relative path is relative to the list file's folder;
//    leading and trailing blanks are ignored, and so are blank lines and lines whose first
//    non-blank character is '#' (a '#' after a path is part of the path). An entry may be a clip
//    or a folder (expanded as below), never another list. The list's order is kept.
//  - a folder: its .bvh and .amc files (any letter case), sorted by path (byte order); with
//    ExpandOptions::recursive, those of every subfolder too, all sorted together (links to
//    folders are not followed). .asf files are skeletons, not clips (an .amc finds its .asf as
//    load_clip() does); other files, and names starting with '.', are ignored.
//  - anything else: a clip path, taken as it is (load_clip() reports a wrong extension).
// Inputs are expanded in the order given; a clip named twice is loaded twice.
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "motionmap/core/control.h"
#include "motionmap/core/error.h"
#include "motionmap/io/load.h"
#include "motionmap/skeleton/skeleton.h"

namespace motionmap::io {

struct ExpandOptions {
  /// Folders contribute the clips of their subfolders too (at any depth); without it, only the
  /// files directly in the folder.
  bool recursive = false;
};

/// Whether `path` names a clip by its extension: .bvh or .amc, in any letter case.
bool is_clip_file(std::string_view path);

/// The clip files in `folder` (and, with options.recursive, its subfolders), sorted by path.
/// @throws Error "folder: error: no clip (.bvh or .amc file) in this folder …" when there is
///         none, or naming the folder and the system's reason when it cannot be read.
std::vector<std::string> clip_files_in_folder(const std::string& folder,
                                              const ExpandOptions& options = {});

/// The entries of list-file text, each resolved against the list file's folder (`list_path`'s)
/// and expanded if it is a folder (see the top of this file). `list_path` is also used in
/// messages.
/// @throws ParseError "list.txt:LINE:COL: error: no such file or folder: 'x.bvh' (…)" for an
///         entry that does not exist; Error "list.txt: error: the list names no clip" when it
///         holds no entry; Error from clip_files_in_folder() for a folder entry with no clip.
std::vector<std::string> parse_clip_list(std::string_view text, const std::string& list_path,
                                         const ExpandOptions& options = {});

/// Reads and parses a list file. @throws Error if unreadable, otherwise as parse_clip_list().
std::vector<std::string> read_clip_list(const std::string& list_path,
                                        const ExpandOptions& options = {});

/// The clip paths of `inputs` (clips, folders, `@list` files), in order.
/// @throws Error "x: error: no such file or folder" for a missing input, and as
///         clip_files_in_folder() and read_clip_list().
std::vector<std::string> expand_clip_inputs(std::span<const std::string> inputs,
                                            const ExpandOptions& options = {});

struct LoadClipsOptions {
  LoadOptions load;  ///< for every clip (.asf of .amc files, fps)
  /// Skip a clip that fails to load (recording why in LoadedClips::failures) and go on; without
  /// it the first failure is thrown.
  bool keep_going = false;
};

struct LoadedClips {
  std::vector<Clip> clips;            ///< the clips loaded, in the order of the paths
  std::vector<std::string> failures;  ///< keep_going only: why each skipped clip failed (what())
  long long frames = 0;               ///< frames of the loaded clips together
};

/// Loads every path with load_clip(). Progress goes to `control` as one stage per clip, named
/// "loading 12/40 clips (183 000 frames)" (clips started of all, frames loaded so far), with the
/// fraction of clips done; cancellation is polled between clips.
/// @throws what load_clip() throws for the first clip that fails (without keep_going);
///         no_clip_loaded() when every clip fails (keep_going); ParameterError for no path;
///         Cancelled.
LoadedClips load_clips(std::span<const std::string> paths, const LoadClipsOptions& options = {},
                       const Control& control = {});

/// The error when none of `paths` clips loaded with keep_going, `failures` their what()s in
/// order: "no clip could be loaded (3 of 3 failed); the first: …".
Error no_clip_loaded(const std::vector<std::string>& failures, std::size_t paths);

}  // namespace motionmap::io
