// make_scale_cases: one scan at four sizes for the speed and memory measurements of issue 9 — the
// scan decimated to a quarter (VTK quadric decimation through PCL), as it is, and midpoint-subdivided
// once and twice — each with 12 holes of radius 0.035 in unit-cube units (seeded; the subdivided
// sizes subdivide the holed scan, so they have its holes exactly). Writes binary PLY:
//   OUT/<stem>_<faces>.ply        the intact mesh      OUT/<stem>_<faces>_holes.ply   with holes
// usage: make_scale_cases MESH OUT [--seed S] [--levels N]   (N sizes, 1–4, smallest first; default 4)
#include <pcl_patchdict_eval/mesh_damage.h>
#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict/geometry/mesh_hygiene.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict_eval/shapes.h>
#include <pcl_patchdict/pcl/conversions.h>

#include <pcl/surface/vtk_smoothing/vtk_mesh_quadric_decimation.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

using namespace pcl::patchdict;

namespace {

TriangleMesh decimate(const TriangleMesh& mesh, double reduction)
{
  pcl::PolygonMesh::Ptr in(new pcl::PolygonMesh);
  toPolygonMesh(mesh, *in);
  pcl::MeshQuadricDecimationVTK decimation;
  decimation.setInputMesh(in);
  decimation.setTargetReductionFactor(static_cast<float>(reduction));
  pcl::PolygonMesh out;
  decimation.process(out);
  TriangleMesh result;
  fromPolygonMesh(out, result);
  return result;
}

void write(const TriangleMesh& mesh, const std::filesystem::path& path)
{
  WriteOptions options;
  options.binary = true;
  options.write_normals = false;
  writeMesh(path.string(), mesh, options);
  std::printf("%s: %zu vertices, %zu faces\n", path.c_str(), mesh.numVertices(), mesh.numFaces());
}

}  // namespace

int main(int argc, char** argv)
{
  if (argc < 3) {
    std::fprintf(stderr, "usage: make_scale_cases MESH OUT [--seed S] [--levels N]\n");
    return 2;
  }
  const std::string input = argv[1];
  const std::filesystem::path out = argv[2];
  std::uint64_t seed = 1;
  int levels = 4;
  for (int i = 3; i + 1 < argc; i += 2)
    if (std::string(argv[i]) == "--seed")
      seed = std::strtoull(argv[i + 1], nullptr, 10);
    else if (std::string(argv[i]) == "--levels")
      levels = std::max(1, std::min(4, std::atoi(argv[i + 1])));
  try {
    std::filesystem::create_directories(out);
    TriangleMesh mesh;
    readMesh(input, mesh);
    mesh.normals.clear();
    cleanMesh(mesh);
    const std::string stem = std::filesystem::path(input).stem().string();
    const double radius = UnitCubeNormalization::fromMesh(mesh).invertLength(0.035);
    const auto name = [&](const TriangleMesh& m) {
      return stem + "_" + std::to_string((m.numFaces() + 500) / 1000) + "k";
    };
    const TriangleMesh quarter = decimate(mesh, 0.75);
    write(quarter, out / (name(quarter) + ".ply"));
    write(punchHoles(quarter, 12, radius, seed).mesh, out / (name(quarter) + "_holes.ply"));
    TriangleMesh level = mesh, holes = punchHoles(mesh, 12, radius, seed).mesh;
    for (int i = 0; i + 1 < levels; ++i) {
      write(level, out / (name(level) + ".ply"));
      write(holes, out / (name(level) + "_holes.ply"));
      if (i + 2 < levels) {
        level = subdivideMidpoint(level);
        holes = subdivideMidpoint(holes);
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_scale_cases: %s\n", e.what());
    return 1;
  }
  return 0;
}
