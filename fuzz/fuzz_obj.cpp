// libFuzzer target: the OBJ reader (readMeshFromMemory, MeshFormat::OBJ).
#include "fuzz_common.h"

#include <pcl_patchdict/mesh_io.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  pcl::patchdict::TriangleMesh mesh;
  try {
    pcl::patchdict::readMeshFromMemory(fuzz::bytesOf(data, size), pcl::patchdict::MeshFormat::OBJ, mesh);
  }
  catch (const pcl::patchdict::Error&) {
    return 0;
  }
  fuzz::checkMesh(mesh);
  return 0;
}
