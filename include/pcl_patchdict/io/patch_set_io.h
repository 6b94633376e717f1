// The .pds patch-set file: every patch's seed, frame, heights and observed bins, checksummed; and the
// patches drawn as a PNG contact sheet.
#pragma once

#include <pcl_patchdict/patches/patch_set.h>

#include <cstddef>
#include <string>

namespace pcl {
namespace patchdict {

/** The bytes of a .pds file (little-endian): magic, version, N, r, P, then seeds, rotations, heights,
  * mask, sources, and an FNV-1a 64 checksum of everything before it. Throws Error if the set does not
  * pass PatchSet::check(). */
std::string formatPatchSet(const PatchSet& set);

/** A .pds file from its bytes; `name` is what error messages call it. Truncated, corrupted
  * (checksum), mismatched (magic, version) or implausible bytes are rejected with one clear line
  * (Error), before any allocation larger than the bytes themselves. */
PatchSet parsePatchSet(const std::string& bytes, const std::string& name = "<memory>");

/** formatPatchSet written atomically (core/atomic_file.h). */
void savePatchSet(const std::string& path, const PatchSet& set);

/** parsePatchSet of the file's bytes. */
PatchSet loadPatchSet(const std::string& path);

/** Contact sheet of the patches (the first `max_patches` of them when > 0), unobserved bins drawn as a
  * checker, `columns` tiles per row; Error for an empty set. */
void savePatchSetPNG(const std::string& path, const PatchSet& set, int columns = 20, int pixels_per_bin = 4,
                     std::size_t max_patches = 0);

}  // namespace patchdict
}  // namespace pcl
