// Whole-or-nothing file output: bytes go to a temporary file beside the target, which is renamed
// into place only once everything was written, so an interrupted run never leaves a partial file.
#pragma once

#include <functional>
#include <string>

namespace pcl {
namespace patchdict {

/** Writes `bytes` to `path` atomically (temporary file in the same directory, fsync, rename).
  * Throws Error (one line) if the directory does not exist, the target is a directory, or a
  * write fails; no temporary file is left behind in any case. */
void writeFileAtomically(const std::string& path, const std::string& bytes);

/** The same for writers that need a file name (e.g. PCL's): `write_temporary` must create and fill
  * the file at the path it is given, or throw. */
void writeFileAtomically(const std::string& path, const std::function<void(const std::string&)>& write_temporary);

/** Throws Error (one line, "cannot write 'path': …") unless `path` names a file that could be written:
  * its directory exists and it is not itself a directory. writeFileAtomically checks this first; a
  * command can call it before its work, so that a bad output path fails at once. */
void checkWritableFile(const std::string& path);

/** Installs handlers for SIGINT, SIGTERM and SIGHUP that delete the temporary files of writes in
  * progress and then let the signal end the process as it would have (a tool calls this once, at
  * start): an interrupted run leaves neither a partial target nor a stray temporary file. SIGKILL
  * cannot be caught; its temporary file ("." + name + ".tmp.<pid>.<n>") is all it can leave. */
void removeTemporaryFilesOnInterrupt();

/** Whole file into memory. Throws Error ("cannot read 'path': reason") for a missing file, a
  * directory, something that is not a regular file, or a read failure. */
std::string readWholeFile(const std::string& path);

}  // namespace patchdict
}  // namespace pcl
