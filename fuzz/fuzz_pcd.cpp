// libFuzzer target: the PCD reader (our header checks, then PCL's parser, which reads from a path:
// each input goes through one temporary file per process).
#include "fuzz_common.h"

#include <pcl_patchdict/io/mesh_io.h>

#include <unistd.h>

#include <fstream>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  static const std::string path = "/tmp/pcl_patchdict_fuzz_" + std::to_string(::getpid()) + ".pcd";
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  pcl::patchdict::TriangleMesh mesh;
  try {
    pcl::patchdict::readMesh(path, mesh);
  }
  catch (const pcl::patchdict::Error&) {
    return 0;
  }
  fuzz::checkMesh(mesh);
  if (!mesh.faces.empty())
    fuzz::fail("a PCD file gave faces");
  return 0;
}
