#pragma once
/// Finding the clips of a batch: a folder (recursive) or a manifest (YAML or CSV).
///
/// Folder: every regular file whose extension is .bvh or .c3d (any case), recursively, sorted by
/// path; the output name is the path relative to the folder without its extension
/// ("walks/Walk01.BVH" -> "walks/Walk01"), so sub-folders are kept in the output folder. Folder
/// symlinks are not followed; a file symlink resolving outside the folder is rejected unless
/// `allow_outside`.
///
/// YAML manifest (.yaml/.yml; every key is checked, errors name file:line and the key path):
///
///   clips:
///     - walks/walk01.bvh                 # a plain path
///     - path: walks/walk02.bvh           # or a map; only `path` is required
///       output: walk02_slow              # output name (default: the path relative to the
///                                        # manifest's folder without extension, "walks/walk02")
///       source_units: cm                 # per-clip overrides of the convert flags
///       source_fps: 60
///       time_scale: 1.5
///       up_axis: y
///       profile: profiles/studio.yaml    # --skeleton-profile / --marker-map
///
/// CSV manifest (.csv): a header row naming the columns (any order; `path` required; the others
/// are `output`, `source_units`, `source_fps`, `time_scale`, `up_axis`, `profile`), then one row
/// per clip. Empty cells mean "no override". Fields may be double-quoted (RFC 4180, "" inside
/// quotes is a quote). Blank lines and lines starting with '#' are skipped. Errors name
/// `file:line` and the column.
///
/// Relative paths in a manifest resolve against the manifest's folder. The input root is the
/// folder (folder input) or the manifest's folder; a clip path that resolves outside it (after
/// symlinks) is an InputError unless `allow_outside`. Output names must be relative, without
/// "." or ".." components, backslashes or control characters, and unique; "summary" and
/// "summary-shard-*" are reserved for the batch's own files. Missing clip files are not an error
/// here: the worker reports them as that clip's bad input, and the batch goes on.

#include <string>
#include <vector>

#include "retarget/batch/batch_clip.hpp"

namespace rt {

struct ClipDiscoveryOptions {
  bool allow_outside = false;  ///< accept clip paths outside the input root (--allow-outside)
};

/// True for a path whose extension is .bvh or .c3d, case-insensitive.
bool is_motion_file(const std::string& path);

/// True when `input` names a manifest (.yaml, .yml or .csv, case-insensitive).
bool is_manifest_path(const std::string& input);

/// Clips of a folder, a YAML manifest or a CSV manifest, in listing order (folder: sorted by
/// relative path). InputError when the input does not exist, is neither a folder nor a manifest,
/// lists no clip, or breaks the rules above.
std::vector<BatchClip> discover_clips(const std::string& input, const ClipDiscoveryOptions& options = {});

/// Parses manifest text as if read from `manifest_path` (its folder is the base of relative paths
/// and the input root). `csv` picks the format. Same checks as discover_clips.
std::vector<BatchClip> parse_manifest(const std::string& text, const std::string& manifest_path, bool csv,
                                      const ClipDiscoveryOptions& options = {});

/// Checks one output name (rules above); `where` locates it in errors.
void check_output_name(const std::string& name, const std::string& where);

/// Rejects duplicate output names (InputError naming both clips' origins).
void check_unique_output_names(const std::vector<BatchClip>& clips);

}  // namespace rt
