// Mesh I/O on bad input and failing writes: one-line errors naming the file (and line), every prefix of
// every format failing cleanly or reading, and atomic writes that leave nothing half-written.

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict_eval/shapes.h>

#include "test_support.h"

#include "mesh_io_test_helpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <limits>
#include <set>
#include <unordered_map>

using namespace mesh_io_test;

namespace {

std::set<std::string> listDirectory(const std::string& path)
{
  std::set<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(path))
    names.insert(entry.path().filename().string());
  return names;
}

}  // namespace

TEST(MeshIOErrors, MissingEmptyDirectoryAndUnknownExtension)
{
  TempDir dir;
  expectReadError(dir.file("missing.ply"), "no such file");
  std::filesystem::create_directory(dir.file("folder.obj"));
  expectReadError(dir.file("folder.obj"), "directory");
  for (const char* name : {"e.ply", "e.obj", "e.off", "e.stl", "e.pcd"})
    expectFixtureError(dir, name, "", "empty");
  expectFixtureError(dir, "mesh.xyz", "v 0 0 0\n", "extension");
  expectFixtureError(dir, "nothing.obj", "# only a comment\n", "no vertices");
}

TEST(MeshIOErrors, TruncatedAndHugeDeclaredCounts)
{
  TempDir dir;
  const TriangleMesh mesh = doubleMesh();
  writeMesh(dir.file("good.ply"), mesh);
  const std::string bytes = readFile(dir.file("good.ply"));
  expectFixtureError(dir, "t1.ply", bytes.substr(0, bytes.size() - 1), "truncated");
  expectFixtureError(dir, "t2.ply", bytes.substr(0, bytes.size() / 2), "truncated");

  const auto start = std::chrono::steady_clock::now();
  const std::string body(30, '\0');
  for (const char* count : {"1000000000000", "100000000", "2000000000"}) {
    const std::string header = std::string("ply\nformat binary_little_endian 1.0\nelement vertex ") + count +
                               "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
    expectFixtureError(dir, "huge.ply", header + body);
    expectFixtureError(dir, "huge_ascii.ply",
                       std::string("ply\nformat ascii 1.0\nelement vertex ") + count +
                           "\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n");
  }
  expectFixtureError(dir, "huge_faces.ply",
                     "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
                     "property float z\nelement face 900000000\nproperty list uchar int vertex_indices\nend_header\n" +
                         body,
                     "truncated");
  expectFixtureError(dir, "huge.off", "OFF\n100000000 100000000 0\n0 0 0\n", "truncated");
  Bytes stl(false);
  stl.text(std::string(80, ' ')).put<std::uint32_t>(4000000000u).text(std::string(50, '\0'));
  expectFixtureError(dir, "huge.stl", stl.data, "truncated");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 2.0);  // rejected from the header, without allocating or scanning
}

TEST(MeshIOErrors, GarbageHeadersAndLinesNameTheLine)
{
  TempDir dir;
  expectFixtureError(dir, "g1.obj", "v 0 0 0\nv 1 0 0\nv 1 2\nf 1 2 3\n", "line 3");
  expectFixtureError(dir, "g2.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 x 3\n", "line 4");
  expectFixtureError(dir, "g3.obj", "v 0 0 0\nv1 1 0 0\n", "line 2");
  expectFixtureError(dir, "g4.obj", "v 0 0 0\n1 2 3\n", "line 2");
  expectFixtureError(dir, "g5.obj", "v 0 0 0\nv 1 0 abc\n", "line 2");
  expectFixtureError(dir, "g6.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/2/3/4 2 3\n", "line 4");
  expectFixtureError(dir, "g1.ply", "ply\nformat ascii 1.0\nelement vertex 1\nbogus line\nend_header\n0 0 0\n",
                     "line 4");
  expectFixtureError(dir, "g2.ply", "PLY?\nformat ascii 1.0\n", "not a PLY");
  expectFixtureError(dir, "g3.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n", "end_header");
  expectFixtureError(dir, "g4.ply",
                     "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                     "property float z\nend_header\n0 zero 0\n",
                     "line 8");
  expectFixtureError(dir, "g5.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n",
                     "'y'");
  expectFixtureError(dir, "g1.off", "OFX\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "not an OFF");
  expectFixtureError(dir, "g2.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1\n3 0 1 2\n", "line 5");
  expectFixtureError(dir, "g1.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n", "truncated");
  expectFixtureError(dir, "g2.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvortex 1 0 0\n", "line 5");
  expectFixtureError(dir, "g1.pcd", "# .PCD v0.7\nFIELDS x y z\nthis is not a pcd\n", "line 3");
  expectFixtureError(dir, "g2.pcd", "garbage\n");  // crashes PCL's reader if handed over unchecked
  const std::string pcd_head = "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
                               "WIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n";
  expectFixtureError(dir, "g3.pcd", pcd_head + "1 2 3\n4 abc 6\n", "line 13");  // PCL alone reads 0
  expectFixtureError(dir, "g4.pcd", pcd_head + "1 2 3\n4 5\n", "line 13");
  expectFixtureError(dir, "g5.pcd", pcd_head + "1 2 3\n", "truncated");
}

TEST(MeshIOErrors, FaceIndicesOutOfRange)
{
  TempDir dir;
  const std::string three = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  expectFixtureError(dir, "zero.obj", three + "f 0 1 2\n", "line 4");
  expectFixtureError(dir, "large.obj", three + "f 1 2 4\n", "out of range");
  expectFixtureError(dir, "negative.obj", three + "f -1 -2 -4\n", "line 4");
  expectFixtureError(dir, "normal.obj", three + "vn 0 0 1\nf 1//1 2//2 3//1\n", "normal");
  const std::string ply_head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                               "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                               "end_header\n0 0 0\n1 0 0\n0 1 0\n";
  expectFixtureError(dir, "large.ply", ply_head + "3 0 1 3\n", "out of range");
  expectFixtureError(dir, "negative.ply", ply_head + "3 0 -1 2\n", "out of range");
  Bytes binary(false);
  binary.text("ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
              "property float z\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n");
  for (int i = 0; i < 9; ++i)
    binary.put<float>(0.0f);
  binary.put<std::uint8_t>(3).put<std::uint32_t>(0).put<std::uint32_t>(1).put<std::uint32_t>(4000000000u);
  expectFixtureError(dir, "large_binary.ply", binary.data, "out of range");
  expectFixtureError(dir, "large.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "line 6");
}

TEST(MeshIOErrors, NonFiniteCoordinatesAndShortFaces)
{
  TempDir dir;
  expectFixtureError(dir, "nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\n", "vertex 1 has a non-finite");
  expectFixtureError(dir, "inf.off", "OFF\n3 0 0\n0 0 0\n1 inf 0\n0 1 0\n", "non-finite");
  expectFixtureError(dir, "nan.ply",
                     "ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\nproperty double y\n"
                     "property double z\nend_header\n0 0 0\n1 NaN 0\n",
                     "vertex 1 has a non-finite");
  Bytes binary(false);
  binary.text("ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
              "property float z\nend_header\n");
  binary.put<float>(0.0f).put<float>(std::numeric_limits<float>::quiet_NaN()).put<float>(0.0f);
  expectFixtureError(dir, "nan_binary.ply", binary.data, "non-finite");
  expectFixtureError(dir, "nan.stl",
                     "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex nan 0 0\nvertex 0 1 0\n"
                     "endloop\nendfacet\nendsolid\n",
                     "non-finite");
  expectFixtureError(dir, "two.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", "2 vertices");
  expectFixtureError(dir, "two.ply",
                     "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                     "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                     "0 0 0\n1 0 0\n2 0 1\n",
                     "2 vertices");
  expectFixtureError(dir, "two.off", "OFF\n2 1 0\n0 0 0\n1 0 0\n2 0 1\n", "2 vertices");
}

TEST(MeshIOErrors, EveryPrefixOfEveryFormatFailsCleanlyOrReads)
{
  // Text formats may legitimately end at a line break; what matters is: an Error or a mesh, never a crash.
  const TriangleMesh mesh = throughFloat(pcl::patchdict::makeIcosphere(0));
  TempDir dir;
  for (const char* name : {"m.ply", "m.obj", "m.off", "m.stl", "m.pcd", "a.ply", "a.stl", "a.pcd"}) {
    WriteOptions options;
    options.binary = name[0] == 'm';
    writeMesh(dir.file(name), mesh, options);
    const std::string bytes = readFile(dir.file(name));
    for (std::size_t length = 0; length < bytes.size(); ++length) {
      writeFile(dir.file(std::string("cut_") + name), bytes.substr(0, length));
      TriangleMesh cut;
      try {
        readMesh(dir.file(std::string("cut_") + name), cut);
        EXPECT_LE(cut.numVertices(), mesh.numVertices()) << name << " " << length;
      }
      catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
      }
    }
  }
}

// ---------------------------------------------------------------- writing

TEST(MeshIOWrite, FailuresLeaveNothingBehind)
{
  TempDir dir;
  auto expectWriteError = [&](const std::string& path, const TriangleMesh& mesh, const std::string& mention) {
    EXPECT_THROW(writeMesh(path, mesh), Error) << path;
    try {
      writeMesh(path, mesh);
    }
    catch (const Error& e) {
      expectOneLineMessage(e.what(), path);
      EXPECT_NE(std::string(e.what()).find(mention), std::string::npos) << e.what();
    }
    EXPECT_TRUE(listDirectory(dir.path()).empty()) << path;
  };
  const TriangleMesh mesh = doubleMesh();
  TempDir other;
  std::filesystem::create_directory(other.file("is_a_directory.ply"));
  // Fails only at the final rename, after the temporary file was written: it must be removed.
  EXPECT_THROW(writeMesh(other.file("is_a_directory.ply"), mesh), Error);
  EXPECT_EQ(listDirectory(other.path()), std::set<std::string>{"is_a_directory.ply"});
  expectWriteError(dir.file("mesh.xyz"), mesh, "extension");
  expectWriteError(dir.file("no/such/dir/mesh.ply"), mesh, "does not exist");
  TriangleMesh bad = mesh;
  bad.vertices[3].y() = std::numeric_limits<double>::quiet_NaN();
  expectWriteError(dir.file("nan.obj"), bad, "non-finite");
  bad = mesh;
  bad.faces[2][1] = static_cast<std::int32_t>(mesh.numVertices());
  expectWriteError(dir.file("index.off"), bad, "out of range");
  TriangleMesh cloud = mesh;
  cloud.faces.clear();
  expectWriteError(dir.file("cloud.stl"), cloud, "no faces");
  expectWriteError(dir.file("empty.pcd"), TriangleMesh(), "empty");
  expectWriteError(dir.file("empty.ply"), TriangleMesh(), "empty");
  TriangleMesh huge = mesh;
  huge.vertices[0].x() = 1e300;
  expectWriteError(dir.file("huge.stl"), huge, "float32");
}

TEST(MeshIOWrite, ReplacesWholeAndLeavesOnlyTheTarget)
{
  TempDir dir;
  const TriangleMesh mesh = throughFloat(doubleMesh());
  for (const char* name : {"m.ply", "m.obj", "m.off", "m.stl", "m.pcd"}) {
    const std::string path = dir.file(name);
    writeFile(path, std::string(1 << 20, 'x'));  // an older, larger file
    writeMesh(path, mesh);
    TriangleMesh back;
    readMesh(path, back);
    EXPECT_EQ(back.numVertices(), mesh.numVertices()) << name;
    EXPECT_EQ(listDirectory(dir.path()), std::set<std::string>{name});
    TempDir fresh;
    writeMesh(fresh.file(name), mesh);
    if (std::string(name) != "m.pcd") {  // PCL's writer is not ours to pin down byte for byte
      EXPECT_EQ(readFile(path), readFile(fresh.file(name))) << name;
    }
    std::filesystem::remove(path);
  }
}
