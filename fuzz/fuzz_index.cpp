// libFuzzer target: vertex index files (parseIndexFile, the reader of --missing / --vertices).
#include "fuzz_common.h"

#include <pcl_patchdict/io/index_io.h>

#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  constexpr std::size_t kVertices = 1000;
  std::vector<int> indices;
  try {
    indices = pcl::patchdict::parseIndexFile(fuzz::bytesOf(data, size), kVertices);
  }
  catch (const pcl::patchdict::Error&) {
    return 0;
  }
  std::vector<char> seen(kVertices, 0);
  for (const int index : indices) {
    if (index < 0 || static_cast<std::size_t>(index) >= kVertices)
      fuzz::fail("an accepted index is out of range");
    if (seen[static_cast<std::size_t>(index)]++)
      fuzz::fail("an accepted index is listed twice");
  }
  return 0;
}
