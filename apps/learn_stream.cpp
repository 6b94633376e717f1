// How `learn` reads its inputs as patches, and the patch cache of later passes (learn_stream.h).
#include "learn_stream.h"
#include "cli.h"
#include "learn_inputs.h"

#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict/io/patch_set_io.h>

#include <chrono>
#include <system_error>

#include <unistd.h>

namespace pcl {
namespace patchdict {
namespace cli {

bool readsAsPatchSet(const std::string& path)
{
  return isPatchSetPath(path) || formatFromPath(path) == MeshFormat::Unknown;
}

PatchSet loadInputPatches(const std::string& path, SurfacePatchOptions options, int grid_size)
{
  PatchSet patches;
  if (readsAsPatchSet(path)) {
    patches = loadPatchSet(path);
  } else {
    if (grid_size > 0)
      options.grid_size = grid_size;
    patches = surfacePatches(path, options, true).patches;
  }
  if (grid_size > 0 && patches.numPatches() > 0 && patches.grid_size != grid_size)
    throw Error("'" + path + "' has " + std::to_string(patches.grid_size) + "×" + std::to_string(patches.grid_size) +
                " patches, the inputs before it (or --grid) " + std::to_string(grid_size) + "×" +
                std::to_string(grid_size));
  return patches;
}

PatchCache::~PatchCache()
{
  std::error_code ignored;
  if (!folder_.empty())
    std::filesystem::remove_all(folder_, ignored);
}

void PatchCache::store(std::size_t input, const PatchSet& patches, bool quiet)
{
  if (!enabled_)
    return;
  try {
    if (folder_.empty()) {
      folder_ = std::filesystem::temp_directory_path() /
                ("pcl_patchdict_learn_" + std::to_string(::getpid()) + "_" +
                 std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
      std::filesystem::create_directories(folder_);
    }
    savePatchSet(file(input), patches);
    stored_[input] = true;
    bytes_ += std::filesystem::file_size(file(input));
  } catch (const std::exception& error) {  // a full disk, say: the patches are made again instead
    enabled_ = false;
    note(quiet, std::string("  patch cache given up (") + error.what() + "): later passes make the patches again");
  }
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
