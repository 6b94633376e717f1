// Helpers of the mesh I/O tests (test_mesh_io.cpp, test_mesh_io_errors.cpp): meshes whose
// coordinates are genuine doubles or float-rounded, and the checks of one-line read errors.
#pragma once

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/triangle_mesh.h>
#include <pcl_patchdict_eval/shapes.h>
#include <pcl_patchdict/io/mesh_io.h>

#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>

namespace mesh_io_test {

using pcl::patchdict::Error;
using pcl::patchdict::Face;
using pcl::patchdict::MeshFormat;
using pcl::patchdict::ReadInfo;
using pcl::patchdict::TriangleMesh;
using pcl::patchdict::WriteOptions;
using pcl::patchdict::readMesh;
using pcl::patchdict::writeMesh;
using test_support::TempDir;
using test_support::readFile;
using test_support::writeFile;

// An icosphere whose normals are its (unit) positions: coordinates are genuine doubles.
inline TriangleMesh doubleMesh()
{
  TriangleMesh mesh = pcl::patchdict::makeIcosphere(2, 1.0);
  mesh.normals = mesh.vertices;
  return mesh;
}

// Through a volatile float on purpose: GCC 12.2 at -O2/-O3 (SLP vectoriser) folds the pair
// `a = (double)(float)x; b = (double)(float)y;` into a plain copy, leaving x and y unrounded.
inline Eigen::Vector3d roundToFloat(const Eigen::Vector3d& p)
{
  Eigen::Vector3d out;
  for (int k = 0; k < 3; ++k) {
    volatile float narrow = static_cast<float>(p[k]);
    out[k] = narrow;
  }
  return out;
}

inline TriangleMesh throughFloat(TriangleMesh mesh)
{
  for (auto* points : {&mesh.vertices, &mesh.normals})
    for (Eigen::Vector3d& p : *points)
      p = roundToFloat(p);
  return mesh;
}

inline void expectOneLineMessage(const std::string& message, const std::string& path)
{
  EXPECT_FALSE(message.empty());
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_NE(message.find(path), std::string::npos) << "message does not name the file: " << message;
}

// Reads `path`, which must fail with a one-line Error naming the file (and `mention`, if given).
inline void expectReadError(const std::string& path, const std::string& mention = "")
{
  TriangleMesh mesh;
  EXPECT_THROW(readMesh(path, mesh), Error) << path;
  try {
    readMesh(path, mesh);
  }
  catch (const Error& e) {
    expectOneLineMessage(e.what(), path);
    EXPECT_NE(std::string(e.what()).find(mention), std::string::npos)
        << "expected '" << mention << "' in: " << e.what();
  }
}

// Writes `text` as a file called `name` in `dir` and expects reading it to fail.
inline void expectFixtureError(const TempDir& dir, const std::string& name, const std::string& text,
                        const std::string& mention = "")
{
  writeFile(dir.file(name), text);
  SCOPED_TRACE(name + ":\n" + text.substr(0, 300));
  expectReadError(dir.file(name), mention);
}

// Binary fixture builder with a chosen byte order.
class Bytes {
public:
  explicit Bytes(bool big_endian) : big_endian_(big_endian) {}
  Bytes& text(const std::string& s) { data += s; return *this; }
  template <typename T>
  Bytes& put(T value)
  {
    unsigned char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    const std::uint16_t probe = 1;
    const bool host_little = *reinterpret_cast<const unsigned char*>(&probe) == 1;
    if (host_little == big_endian_)
      std::reverse(raw, raw + sizeof(T));
    data.append(reinterpret_cast<const char*>(raw), sizeof(T));
    return *this;
  }
  std::string data;

private:
  bool big_endian_;
};

}  // namespace mesh_io_test
