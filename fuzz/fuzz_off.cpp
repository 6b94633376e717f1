// libFuzzer target: the OFF reader (readMeshFromMemory, MeshFormat::OFF).
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  return fuzz::fuzzMeshReader(data, size, pcl::patchdict::MeshFormat::OFF);
}
