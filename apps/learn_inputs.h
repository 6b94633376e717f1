// The inputs of `learn`: files, directories, glob patterns and @list files expanded into one
// ordered list of patch sets (.pds) and surfaces (meshes, clouds), with a fingerprint for resuming.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace pcl {
namespace patchdict {
namespace cli {

struct LearnInputs {
  std::vector<std::string> paths;  ///< in streaming order
  std::size_t ignored = 0;         ///< directory entries that are neither .pds nor a surface format
  bool expanded = false;           ///< a directory, glob or list was given (a "many inputs" job)
};

/** True for a .pds name (case-insensitive). */
bool isPatchSetPath(const std::string& path);

/** Expands learn's positional arguments, in order:
  *  - `@LIST`: one entry per line, blank lines and lines starting with '#' skipped, surrounding
  *    white space trimmed, relative entries relative to the list's folder; entries may be files,
  *    directories or globs (not other lists);
  *  - a directory: its regular files named *.pds or with a surface extension (PLY, OBJ, OFF, STL,
  *    PCD), sorted by name, not recursive (a dataset's folders often hold derived versions — the
  *    list file says which);
  *  - a name with *, ? or [ that is not an existing file: glob(3), matches sorted by name (byte
  *    order, not the locale's), as a shell that left the pattern alone would have expanded it;
  *  - anything else: a file, checked when it is read.
  * Throws Error (one line) for an unreadable list, an empty directory, or a pattern without match. */
LearnInputs expandLearnInputs(const std::vector<std::string>& arguments);

/** FNV-1a 64 of the absolute paths and file sizes, in order: resuming refuses another list. */
std::uint64_t fingerprintInputs(const std::vector<std::string>& paths);

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
