// Mesh I/O: exact round trips in every format, hand-written fixtures for the corners of each format,
// one-line errors for bad input, and atomic writes.

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

// Values that defeat fixed-precision printing: tiny, huge, subnormal, negative zero, many digits.
TriangleMesh awkwardMesh()
{
  TriangleMesh mesh;
  mesh.vertices = {{0.1, -0.0, 1e-300},
                   {1e300, 4.9e-324, 123456789.123456789},
                   {-2.0 / 3.0, std::nextafter(1.0, 2.0), 1.0 / 3.0},
                   {3.0, 5e-8, -7.25}};
  mesh.faces = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

void expectIdentical(const TriangleMesh& expected, const TriangleMesh& actual, bool compare_normals)
{
  ASSERT_EQ(expected.vertices.size(), actual.vertices.size());
  ASSERT_EQ(expected.faces.size(), actual.faces.size());
  for (std::size_t i = 0; i < expected.vertices.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      ASSERT_EQ(expected.vertices[i][k], actual.vertices[i][k]) << "vertex " << i << " coordinate " << k;
      ASSERT_EQ(std::signbit(expected.vertices[i][k]), std::signbit(actual.vertices[i][k])) << "vertex " << i;
    }
  for (std::size_t f = 0; f < expected.faces.size(); ++f)
    ASSERT_EQ(expected.faces[f], actual.faces[f]) << "face " << f;
  if (compare_normals) {
    ASSERT_TRUE(actual.hasNormals());
    for (std::size_t i = 0; i < expected.normals.size(); ++i)
      ASSERT_EQ(expected.normals[i], actual.normals[i]) << "normal " << i;
  }
}

// STL keeps no vertex list: vertices come back in order of first use by the faces.
TriangleMesh renumberByFirstUse(const TriangleMesh& mesh)
{
  TriangleMesh out;
  std::unordered_map<std::int32_t, std::int32_t> new_index;
  for (const Face& face : mesh.faces) {
    Face renumbered;
    for (int c = 0; c < 3; ++c) {
      auto it = new_index.find(face[c]);
      if (it == new_index.end()) {
        it = new_index.emplace(face[c], static_cast<std::int32_t>(out.vertices.size())).first;
        out.vertices.push_back(mesh.vertices[face[c]]);
      }
      renumbered[c] = it->second;
    }
    out.faces.push_back(renumbered);
  }
  return out;
}

TriangleMesh roundTrip(const TriangleMesh& mesh, const std::string& name, const WriteOptions& options = {},
                       ReadInfo* info = nullptr)
{
  TempDir dir;
  writeMesh(dir.file(name), mesh, options);
  TriangleMesh back;
  readMesh(dir.file(name), back, info);
  return back;
}

TriangleMesh readFixture(const TempDir& dir, const std::string& name, const std::string& text,
                         ReadInfo* info = nullptr)
{
  writeFile(dir.file(name), text);
  TriangleMesh mesh;
  readMesh(dir.file(name), mesh, info);
  return mesh;
}

}  // namespace

// ---------------------------------------------------------------- formats and the bundled mesh

TEST(MeshIOFormat, ExtensionsAndNames)
{
  EXPECT_EQ(pcl::patchdict::formatFromPath("a/b/mesh.PLY"), MeshFormat::PLY);
  EXPECT_EQ(pcl::patchdict::formatFromPath("x.obj"), MeshFormat::OBJ);
  EXPECT_EQ(pcl::patchdict::formatFromPath("x.Off"), MeshFormat::OFF);
  EXPECT_EQ(pcl::patchdict::formatFromPath("x.stl"), MeshFormat::STL);
  EXPECT_EQ(pcl::patchdict::formatFromPath("cloud.pcd"), MeshFormat::PCD);
  EXPECT_EQ(pcl::patchdict::formatFromPath("x.xyz"), MeshFormat::Unknown);
  EXPECT_EQ(pcl::patchdict::formatFromPath("ply"), MeshFormat::Unknown);
  EXPECT_EQ(pcl::patchdict::formatName(MeshFormat::OFF), "off");
  EXPECT_EQ(pcl::patchdict::formatName(MeshFormat::PCD), "pcd");
}

TEST(MeshIOBunny, LoadsWithExactCounts)
{
  const std::string path = test_support::dataDir() + "/bunny.obj";
  const std::string before = readFile(path);
  TriangleMesh mesh;
  ReadInfo info;
  const auto start = std::chrono::steady_clock::now();
  readMesh(path, mesh, &info);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "[ timing   ] bunny.obj loaded in " << seconds * 1000.0 << " ms\n";
  RecordProperty("bunny_load_ms", static_cast<int>(seconds * 1000.0));
  EXPECT_EQ(mesh.numVertices(), 35947u);
  EXPECT_EQ(mesh.numFaces(), 69451u);
  EXPECT_EQ(info.format, MeshFormat::OBJ);
  EXPECT_FALSE(info.binary);
  EXPECT_EQ(info.polygons_triangulated, 0u);
  EXPECT_FALSE(mesh.hasNormals());
  EXPECT_EQ(mesh.vertices[0], Eigen::Vector3d(-0.037830, 0.127940, 0.004475));
  EXPECT_EQ(readFile(path), before);  // reading never touches the input
}

// ---------------------------------------------------------------- round trips

TEST(MeshIOPly, BinaryRoundTripIsExactForDoubles)
{
  const TriangleMesh mesh = doubleMesh();
  TempDir dir;
  writeMesh(dir.file("m.ply"), mesh);
  const std::string bytes = readFile(dir.file("m.ply"));
  EXPECT_NE(bytes.find("format binary_little_endian 1.0"), std::string::npos);
  EXPECT_NE(bytes.find("property double x"), std::string::npos);
  TriangleMesh back;
  ReadInfo info;
  readMesh(dir.file("m.ply"), back, &info);
  EXPECT_EQ(info.format, MeshFormat::PLY);
  EXPECT_TRUE(info.binary);
  expectIdentical(mesh, back, true);
  expectIdentical(awkwardMesh(), roundTrip(awkwardMesh(), "a.ply"), false);
}

TEST(MeshIOPly, BinaryRoundTripOfFloatDataUsesFloat32)
{
  const TriangleMesh mesh = throughFloat(doubleMesh());
  TempDir dir;
  writeMesh(dir.file("m.ply"), mesh);
  const std::string bytes = readFile(dir.file("m.ply"));
  EXPECT_NE(bytes.find("property float x"), std::string::npos);
  EXPECT_NE(bytes.find("property float nx"), std::string::npos);
  const std::size_t header_end = bytes.find("end_header\n") + 11;
  EXPECT_EQ(bytes.size() - header_end, mesh.numVertices() * 24 + mesh.numFaces() * 13);
  TriangleMesh back;
  readMesh(dir.file("m.ply"), back);
  expectIdentical(mesh, back, true);
}

TEST(MeshIOPly, AsciiRoundTripIsExact)
{
  WriteOptions ascii;
  ascii.binary = false;
  ReadInfo info;
  expectIdentical(doubleMesh(), roundTrip(doubleMesh(), "m.ply", ascii, &info), true);
  EXPECT_FALSE(info.binary);
  const TriangleMesh floats = throughFloat(doubleMesh());
  expectIdentical(floats, roundTrip(floats, "f.ply", ascii), true);
  expectIdentical(awkwardMesh(), roundTrip(awkwardMesh(), "a.ply", ascii), false);
}

TEST(MeshIOPly, NormalsAreOptional)
{
  WriteOptions no_normals;
  no_normals.write_normals = false;
  const TriangleMesh back = roundTrip(doubleMesh(), "m.ply", no_normals);
  EXPECT_FALSE(back.hasNormals());
  EXPECT_EQ(back.numVertices(), doubleMesh().numVertices());
}

TEST(MeshIOPly, CloudWithoutFacesRoundTrips)
{
  TriangleMesh cloud = doubleMesh();
  cloud.faces.clear();
  const TriangleMesh back = roundTrip(cloud, "cloud.ply");
  expectIdentical(cloud, back, true);
}

TEST(MeshIOObj, RoundTripIsExactWithNormals)
{
  expectIdentical(doubleMesh(), roundTrip(doubleMesh(), "m.obj"), true);
  expectIdentical(awkwardMesh(), roundTrip(awkwardMesh(), "a.obj"), false);
  TriangleMesh cloud = doubleMesh();
  cloud.faces.clear();
  expectIdentical(cloud, roundTrip(cloud, "cloud.obj"), true);
}

TEST(MeshIOOff, RoundTripIsExact)
{
  TriangleMesh mesh = doubleMesh();
  mesh.normals.clear();
  ReadInfo info;
  expectIdentical(mesh, roundTrip(mesh, "m.off", {}, &info), false);
  EXPECT_EQ(info.format, MeshFormat::OFF);
  expectIdentical(awkwardMesh(), roundTrip(awkwardMesh(), "a.off"), false);
}

TEST(MeshIOStl, BinaryRoundTripIsExactForFloatData)
{
  TriangleMesh mesh = throughFloat(pcl::patchdict::makeTorus(24, 12));
  ReadInfo info;
  const TriangleMesh back = roundTrip(mesh, "m.stl", {}, &info);
  EXPECT_TRUE(info.binary);
  EXPECT_EQ(back.numVertices(), mesh.numVertices());  // shared corners merged back
  expectIdentical(renumberByFirstUse(mesh), back, false);
}

TEST(MeshIOStl, AsciiRoundTripIsExactForDoubles)
{
  WriteOptions ascii;
  ascii.binary = false;
  const TriangleMesh mesh = pcl::patchdict::makeTorus(24, 12);
  ReadInfo info;
  const TriangleMesh back = roundTrip(mesh, "m.stl", ascii, &info);
  EXPECT_FALSE(info.binary);
  expectIdentical(renumberByFirstUse(mesh), back, false);
}

TEST(MeshIOPcd, BinaryAndAsciiRoundTripsAreExactForFloatData)
{
  const TriangleMesh mesh = throughFloat(doubleMesh());
  TriangleMesh cloud = mesh;
  cloud.faces.clear();  // PCD keeps points only
  for (const bool binary : {true, false}) {
    WriteOptions options;
    options.binary = binary;
    ReadInfo info;
    const TriangleMesh back = roundTrip(mesh, "m.pcd", options, &info);
    EXPECT_EQ(info.format, MeshFormat::PCD);
    EXPECT_EQ(info.binary, binary);
    EXPECT_EQ(info.points_dropped, 0u);
    expectIdentical(cloud, back, true);
  }
}

TEST(MeshIOPcd, StoresFloat32AndDropsNaNPoints)
{
  TempDir dir;
  const std::string text =
      "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 4\nHEIGHT 1\n"
      "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\nDATA ascii\n1 2 3\nnan nan nan\n4 5 6\n7 nan 9\n";
  ReadInfo info;
  const TriangleMesh cloud = readFixture(dir, "c.pcd", text, &info);
  ASSERT_EQ(cloud.numVertices(), 2u);
  EXPECT_EQ(info.points_dropped, 2u);
  EXPECT_FALSE(info.binary);
  EXPECT_EQ(cloud.vertices[1], Eigen::Vector3d(4, 5, 6));
  // A double coordinate comes back rounded to float32 (documented: PCD is float32).
  TriangleMesh point;
  point.vertices = {{0.1, 0.2, 0.3}};
  const TriangleMesh back = roundTrip(point, "p.pcd");
  EXPECT_EQ(back.vertices[0], roundToFloat(point.vertices[0]));
}

// ---------------------------------------------------------------- hand-written fixtures

TEST(MeshIOObj, AllFaceFormsNegativeIndicesAndPolygons)
{
  TempDir dir;
  const std::string text =
      "# comment\nmtllib thing.mtl\no thing\n"
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 1.5 0 1\n"
      "vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n"
      "g group\nusemtl red\ns 1\n"
      "f 1 2 3\n"
      "f 1/1 3/3 4/2\n"
      "f 1//1 2//1 3//1\r\n"
      "f 1/1/1 2/2/1 3/3/1 # trailing comment\n"
      "f -5 -4 -3\n"
      "f 1 2 3 4\n"
      "\tf  1 2 3 5 4\n"
      "l 1 2\n";
  ReadInfo info;
  const TriangleMesh mesh = readFixture(dir, "fixture.obj", text, &info);
  ASSERT_EQ(mesh.numVertices(), 5u);
  ASSERT_EQ(mesh.numFaces(), 10u);
  EXPECT_EQ(info.polygons_triangulated, 2u);
  EXPECT_EQ(info.lines_ignored, 9u);  // mtllib o vt vt vt g usemtl s l
  EXPECT_EQ(mesh.faces[1], (Face{0, 2, 3}));
  EXPECT_EQ(mesh.faces[4], (Face{0, 1, 2}));  // negative indices
  EXPECT_EQ(mesh.faces[5], (Face{0, 1, 2}));
  EXPECT_EQ(mesh.faces[6], (Face{0, 2, 3}));
  EXPECT_EQ(mesh.faces[9], (Face{0, 4, 3}));
  EXPECT_EQ(mesh.vertices[4], Eigen::Vector3d(0.5, 1.5, 0));
  EXPECT_FALSE(mesh.hasNormals());  // only 3 of 5 vertices have one: no partial normals
}

TEST(MeshIOObj, PerCornerNormalsBecomeVertexNormals)
{
  TempDir dir;
  const std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 -1\nvn 0 0 1\nf 1//2 2//2 3//1\n";
  const TriangleMesh mesh = readFixture(dir, "n.obj", text);
  ASSERT_TRUE(mesh.hasNormals());
  EXPECT_EQ(mesh.normals[0], Eigen::Vector3d(0, 0, 1));
  EXPECT_EQ(mesh.normals[2], Eigen::Vector3d(0, 0, -1));
}

TEST(MeshIOPly, BigEndianWithExtraPropertiesAndElements)
{
  Bytes ply(true);
  ply.text("ply\nformat binary_big_endian 1.0\ncomment made by hand\nobj_info nothing\n"
           "element material 2\nproperty list ushort float stuff\nproperty uchar flag\n"
           "element vertex 4\nproperty double x\nproperty float y\nproperty int z\nproperty uchar red\n"
           "element face 2\nproperty uchar flags\nproperty list uchar int vertex_indices\n"
           "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n");
  ply.put<std::uint16_t>(2).put<float>(1.5f).put<float>(2.5f).put<std::uint8_t>(7);
  ply.put<std::uint16_t>(0).put<std::uint8_t>(9);
  const double xs[4] = {0.1, 1.0, 1.0, 0.0};
  const float ys[4] = {0.0f, 0.0f, 1.0f, 1.0f};
  for (int i = 0; i < 4; ++i)
    ply.put<double>(xs[i]).put<float>(ys[i]).put<std::int32_t>(-i).put<std::uint8_t>(255);
  ply.put<std::uint8_t>(1).put<std::uint8_t>(3).put<std::int32_t>(0).put<std::int32_t>(1).put<std::int32_t>(2);
  ply.put<std::uint8_t>(0).put<std::uint8_t>(4);
  for (const std::int32_t v : {0, 1, 2, 3})
    ply.put<std::int32_t>(v);
  ply.put<std::int32_t>(0).put<std::int32_t>(1);

  TempDir dir;
  writeFile(dir.file("be.ply"), ply.data);
  TriangleMesh mesh;
  ReadInfo info;
  readMesh(dir.file("be.ply"), mesh, &info);
  EXPECT_TRUE(info.binary);
  ASSERT_EQ(mesh.numVertices(), 4u);
  ASSERT_EQ(mesh.numFaces(), 3u);
  EXPECT_EQ(info.polygons_triangulated, 1u);
  EXPECT_EQ(mesh.vertices[0], Eigen::Vector3d(0.1, 0.0, 0.0));
  EXPECT_EQ(mesh.vertices[3], Eigen::Vector3d(0.0, 1.0, -3.0));
  EXPECT_EQ(mesh.faces[0], (Face{0, 1, 2}));
  EXPECT_EQ(mesh.faces[2], (Face{0, 2, 3}));
  // The same file cut short anywhere must fail cleanly.
  for (std::size_t length = 1; length < ply.data.size(); ++length) {
    writeFile(dir.file("cut.ply"), ply.data.substr(0, length));
    TriangleMesh cut;
    EXPECT_THROW(readMesh(dir.file("cut.ply"), cut), Error) << "length " << length;
  }
}

TEST(MeshIOPly, AsciiWithVertexIndexNameAndNormals)
{
  TempDir dir;
  const std::string text = "ply\r\nformat ascii 1.0\r\ncomment hi\r\nelement vertex 3\r\nproperty float x\r\n"
                           "property float y\r\nproperty float z\r\nproperty float nx\r\nproperty float ny\r\n"
                           "property float nz\r\nelement face 1\r\nproperty list uint8 uint32 vertex_index\r\n"
                           "end_header\r\n0.1 0 0 0 0 1\r\n1 0 0 0 0 1\r\n0 1e0 +0 0 0 1\r\n3 0 1 2\r\n";
  ReadInfo info;
  const TriangleMesh mesh = readFixture(dir, "vi.ply", text, &info);
  EXPECT_FALSE(info.binary);
  ASSERT_EQ(mesh.numFaces(), 1u);
  EXPECT_EQ(mesh.faces[0], (Face{0, 1, 2}));
  // A float property holds the float nearest to the decimal text.
  EXPECT_EQ(mesh.vertices[0].x(), static_cast<double>(0.1f));
  ASSERT_TRUE(mesh.hasNormals());
  EXPECT_EQ(mesh.normals[2], Eigen::Vector3d(0, 0, 1));
}

TEST(MeshIOOff, CommentsQuadsColoursAndNormals)
{
  TempDir dir;
  const std::string text = "OFF\n# a comment\n\n4 1 0   # counts\n0 0 0\n1 0 0 # corner\n1 1 0\n0 1 0\n"
                           "4 0 1 2 3 255 0 0\n";
  ReadInfo info;
  TriangleMesh mesh = readFixture(dir, "q.off", text, &info);
  ASSERT_EQ(mesh.numFaces(), 2u);
  EXPECT_EQ(info.polygons_triangulated, 1u);
  EXPECT_EQ(mesh.faces[1], (Face{0, 2, 3}));

  mesh = readFixture(dir, "c.off", "COFF 3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n3 0 1 2\n");
  EXPECT_EQ(mesh.numVertices(), 3u);
  EXPECT_EQ(mesh.vertices[1], Eigen::Vector3d(1, 0, 0));

  mesh = readFixture(dir, "n.off", "NOFF\n3 1 3\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n");
  ASSERT_TRUE(mesh.hasNormals());
  EXPECT_EQ(mesh.normals[1], Eigen::Vector3d(0, 0, 1));
}

TEST(MeshIOStl, AsciiFixtureMergesSharedCorners)
{
  TempDir dir;
  const std::string text = "solid square\n"
                           " facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 1 1 0\n"
                           "  endloop\n endfacet\n"
                           " facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 1 0\n   vertex 0 1 0\n"
                           "  endloop\n endfacet\nendsolid square\n";
  ReadInfo info;
  const TriangleMesh mesh = readFixture(dir, "s.stl", text, &info);
  EXPECT_FALSE(info.binary);
  ASSERT_EQ(mesh.numVertices(), 4u);
  ASSERT_EQ(mesh.numFaces(), 2u);
  EXPECT_EQ(mesh.faces[1], (Face{0, 2, 3}));
}

TEST(MeshIOStl, BinaryFixtureWhoseHeaderStartsWithSolid)
{
  Bytes stl(false);
  std::string header = "solid but binary facet";
  header.resize(80, ' ');
  stl.text(header).put<std::uint32_t>(2);
  const float triangles[2][9] = {{0, 0, 0, 1, 0, 0, 1, 1, 0}, {0, 0, 0, 1, 1, 0, 0, 1, 0}};
  for (const auto& triangle : triangles) {
    stl.put<float>(0).put<float>(0).put<float>(1);
    for (const float value : triangle)
      stl.put<float>(value);
    stl.put<std::uint16_t>(0);
  }
  TempDir dir;
  ReadInfo info;
  const TriangleMesh mesh = readFixture(dir, "b.stl", stl.data, &info);
  EXPECT_TRUE(info.binary);
  ASSERT_EQ(mesh.numVertices(), 4u);
  EXPECT_EQ(mesh.faces[1], (Face{0, 2, 3}));
  expectFixtureError(dir, "short.stl", stl.data.substr(0, stl.data.size() - 1), "truncated");
}

// ---------------------------------------------------------------- bad input
