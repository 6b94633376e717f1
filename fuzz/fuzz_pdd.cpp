// libFuzzer target: the .pdd dictionary reader (parsePatchDictionary).
#include "fuzz_common.h"

#include <pcl_patchdict/coding/patch_dictionary.h>
#include <pcl_patchdict/io/patch_dictionary_io.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  pcl::patchdict::PatchDictionary::Ptr dictionary;
  try {
    dictionary = pcl::patchdict::parsePatchDictionary(fuzz::withValidChecksum(data, size));
  }
  catch (const pcl::patchdict::Error&) {
    return 0;
  }
  const int grid = dictionary->gridSize();
  if (grid < 1 || dictionary->atoms().rows() != grid * grid || dictionary->atoms().cols() < 1 ||
      !dictionary->atoms().allFinite())
    fuzz::fail("an accepted dictionary is inconsistent");
  return 0;
}
