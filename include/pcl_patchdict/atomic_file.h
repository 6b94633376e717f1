// Whole-or-nothing file output: bytes go to a temporary file beside the target, which is renamed
// into place only once everything was written, so an interrupted run never leaves a partial file.
#pragma once

#include <string>

namespace pcl {
namespace patchdict {

/** Writes `bytes` to `path` atomically. Throws Error (one line) if the directory does not exist,
  * is not writable, or the write fails; no temporary file is left behind in any case. */
void writeFileAtomically(const std::string& path, const std::string& bytes);

/** Whole file into memory. Throws Error for a missing file, a directory, or a read failure. */
std::string readWholeFile(const std::string& path);

}  // namespace patchdict
}  // namespace pcl
