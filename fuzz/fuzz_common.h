// Shared by the fuzz targets: what every accepted input must satisfy. A reader may reject any input
// with pcl::patchdict::Error; anything else (another exception, a crash, a sanitizer report, or an
// accepted result that breaks these checks) is a finding.
#pragma once

#include <pcl_patchdict/core/checksum.h>
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict/coding/patch_dictionary.h>
#include <pcl_patchdict/core/triangle_mesh.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace fuzz {

[[noreturn]] inline void fail(const char* what)
{
  std::fprintf(stderr, "fuzz invariant broken: %s\n", what);
  std::abort();
}

/** A mesh a reader accepted: at least one vertex, all finite, faces in range, normals (if any)
  * one per vertex. */
inline void checkMesh(const pcl::patchdict::TriangleMesh& mesh)
{
  if (mesh.vertices.empty())
    fail("a mesh was accepted without vertices");
  for (const auto& v : mesh.vertices)
    if (!v.allFinite())
      fail("a vertex coordinate is not finite");
  for (const auto& f : mesh.faces)
    for (int k = 0; k < 3; ++k)
      if (f[k] < 0 || static_cast<std::size_t>(f[k]) >= mesh.vertices.size())
        fail("a face index is out of range");
  if (!mesh.normals.empty() && mesh.normals.size() != mesh.vertices.size())
    fail("normals are not one per vertex");
}

inline std::string bytesOf(const std::uint8_t* data, std::size_t size)
{
  return std::string(reinterpret_cast<const char*>(data), size);
}

/** Our binary formats end in an FNV-1a 64 checksum of everything before it, which a mutated input
  * would fail at once: it is recomputed, so that the fuzzer reaches the parsing behind it (the
  * checksum test itself is one comparison, covered by the unit tests). */
inline std::string withValidChecksum(const std::uint8_t* data, std::size_t size)
{
  std::string bytes = bytesOf(data, size);
  if (size > 8) {
    const std::uint64_t sum = pcl::patchdict::fnv1a64(bytes.data(), size - 8);
    for (int k = 0; k < 8; ++k)
      bytes[size - 8 + static_cast<std::size_t>(k)] = static_cast<char>((sum >> (8 * k)) & 0xffu);
  }
  return bytes;
}

/** One input through readMeshFromMemory in `format`: rejected cleanly, or a valid mesh. */
inline int fuzzMeshReader(const std::uint8_t* data, std::size_t size, pcl::patchdict::MeshFormat format)
{
  pcl::patchdict::TriangleMesh mesh;
  try {
    pcl::patchdict::readMeshFromMemory(bytesOf(data, size), format, mesh);
  }
  catch (const pcl::patchdict::Error&) {
    return 0;
  }
  checkMesh(mesh);
  return 0;
}

}  // namespace fuzz
