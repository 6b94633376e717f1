// libFuzzer target: the .pds patch-set reader (PatchSet::fromBytes).
#include "fuzz_common.h"

#include <pcl_patchdict/patches/patch_set.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  pcl::patchdict::PatchSet set;
  try {
    set = pcl::patchdict::PatchSet::fromBytes(fuzz::withValidChecksum(data, size));
  }
  catch (const pcl::patchdict::Error&) {
    return 0;
  }
  try {
    set.check();
  }
  catch (const pcl::patchdict::Error&) {
    fuzz::fail("an accepted patch set fails its own check()");
  }
  return 0;
}
