// How `learn` reads its inputs as patches: a .pds as it is, a surface through the `patches`
// stages, and the cache that lets later passes read a surface's patches back instead.
#pragma once

#include "surface_patches.h"

#include <pcl_patchdict/patches/patch_set.h>
#include <pcl_patchdict/io/patch_set_io.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace pcl {
namespace patchdict {
namespace cli {

/** True for an input read as a .pds: a .pds, or a file that is no surface either (whose reader
  * then says what is wrong with it); false for a surface, which goes through the `patches` stages. */
bool readsAsPatchSet(const std::string& path);

/** Reads one input as patches: a .pds as it is, a surface through the `patches` stages. A grid
  * size > 0 is imposed on surfaces and required of .pds files (Error otherwise). */
PatchSet loadInputPatches(const std::string& path, SurfacePatchOptions options, int grid_size);

/** Patches of surface inputs kept on disk after the pass that made them (.pds files in a folder of
  * the system's temporary directory, removed when the run ends): later passes read them back
  * instead of running the quad and patch stages again. float64 throughout, so the same patches bit
  * for bit and the same dictionary. A cache that cannot be written is given up, never the job. */
class PatchCache {
public:
  PatchCache(bool enabled, std::size_t inputs) : enabled_(enabled), stored_(inputs, false) {}
  PatchCache(const PatchCache&) = delete;
  PatchCache& operator=(const PatchCache&) = delete;
  ~PatchCache();
  bool has(std::size_t input) const { return stored_[input]; }
  PatchSet load(std::size_t input) const { return loadPatchSet(file(input)); }
  void store(std::size_t input, const PatchSet& patches, bool quiet);
  std::uintmax_t bytes() const { return bytes_; }

private:
  std::string file(std::size_t input) const { return (folder_ / (std::to_string(input) + ".pds")).string(); }
  bool enabled_;
  std::vector<bool> stored_;
  std::filesystem::path folder_;
  std::uintmax_t bytes_ = 0;
};

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
