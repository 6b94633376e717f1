// The .pdd dictionary file: the atoms in float64, the mean option and how they were learned,
// checksummed; and the atoms drawn as a PNG contact sheet (like Fig. 5, left, of the paper).
#pragma once

#include <pcl_patchdict/coding/patch_dictionary.h>

#include <string>

namespace pcl {
namespace patchdict {

/** The bytes of a .pdd file (little-endian): magic, version, N, K, flags (bit 0: the mean removed),
  * method, sparsity, iterations, seed, training patches, the atoms column-major, then an FNV-1a 64
  * checksum of everything before it. Throws Error for a dictionary without atoms. */
std::string formatPatchDictionary(const PatchDictionary& dictionary);

/** A dictionary from the bytes of a .pdd file; with expected_grid_size > 0, one of another grid is
  * an error. Truncated, corrupted (checksum) or implausible bytes are rejected with one clear line
  * (Error); `name` is what error messages call them. */
PatchDictionary::Ptr parsePatchDictionary(const std::string& bytes, int expected_grid_size = 0,
                                          const std::string& name = "<memory>");

/** formatPatchDictionary written atomically (core/atomic_file.h). */
void savePatchDictionary(const std::string& path, const PatchDictionary& dictionary);

/** parsePatchDictionary of the file's bytes. */
PatchDictionary::Ptr loadPatchDictionary(const std::string& path, int expected_grid_size = 0);

/** The atoms as a PNG contact sheet, `columns` tiles per row. */
void saveDictionaryAtomsPNG(const std::string& path, const PatchDictionary& dictionary, int columns = 20,
                            int pixels_per_bin = 4);

}  // namespace patchdict
}  // namespace pcl
