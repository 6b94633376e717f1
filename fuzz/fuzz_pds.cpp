// libFuzzer target: the .pds patch-set reader (parsePatchSet).
#include "fuzz_common.h"

#include <pcl_patchdict/patches/patch_set.h>
#include <pcl_patchdict/io/patch_set_io.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  pcl::patchdict::PatchSet set;
  try {
    set = pcl::patchdict::parsePatchSet(fuzz::withValidChecksum(data, size));
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
