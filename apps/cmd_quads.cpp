// `pcl_patchdict quads IN -o QUADS.obj`: the coarse shape, its field-aligned quad mesh and the
// seeds with their frames — where the patches of IN go.
#include "cli.h"
#include "options.h"

#include <pcl_patchdict/core/atomic_file.h>
#include <pcl_patchdict/geometry/mesh_hygiene.h>
#include <pcl_patchdict_eval/mesh_render.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/quads/patch_layout.h>
#include <pcl_patchdict/io/mesh_io.h>

#include <array>
#include <iostream>
#include <sstream>

namespace pcl {
namespace patchdict {
namespace cli {

namespace {

/** Seeds with their frames as an ASCII PLY point set: x y z, then the X, Y and Z axes, then the face. */
void writeFrames(const std::string& path, const UnitCubeNormalization& normalization, const PatchLayout& layout)
{
  std::ostringstream out;
  out.precision(9);
  out << "ply\nformat ascii 1.0\ncomment seeds and reference frames written by pcl_patchdict quads\n"
      << "element vertex " << layout.seeds.size() << "\nproperty double x\nproperty double y\nproperty double z\n";
  for (const char* axis : {"x_axis", "y_axis", "z_axis"})
    for (const char* c : {"x", "y", "z"})
      out << "property float " << axis << '_' << c << '\n';
  out << "property int quad\nend_header\n";
  for (std::size_t s = 0; s < layout.seeds.size(); ++s) {
    const Eigen::Vector3d p = normalization.invert(layout.seeds[s]);
    const Eigen::Matrix3d& f = layout.frames[s];
    out << p.x() << ' ' << p.y() << ' ' << p.z();
    for (int axis = 0; axis < 3; ++axis)  // rows X, Y, Z; floats, as the header says (exact: rounded)
      out << ' ' << static_cast<float>(f(axis, 0)) << ' ' << static_cast<float>(f(axis, 1)) << ' '
          << static_cast<float>(f(axis, 2));
    out << ' ' << layout.seed_faces[s] << '\n';
  }
  writeFileAtomically(path, out.str());
}

}  // namespace

int runQuads(const std::vector<std::string>& raw)
{
  const Arguments args = readCommandLine(raw, commandSpec("quads"));
  const std::string input = args.positionals()[0], output = args.get("output");
  const bool quiet = args.quiet();
  PatchLayoutParameters parameters;
  parameters.quad_length = args.getDouble("quad-length");
  parameters.overlap = static_cast<int>(args.getInt("overlap"));
  parameters.smoothing_iterations = static_cast<int>(args.getInt("smoothing-iterations"));
  parameters.smoothing = args.getWord("smoothing") == "taubin" ? CoarseMeshEstimation::Method::Taubin
                                                               : CoarseMeshEstimation::Method::Laplacian;
  parameters.seed = static_cast<std::uint64_t>(args.getInt("seed"));
  for (const std::string& path : {output, args.get("frames"), args.get("coarse"), args.get("png")})
    checkOutputPath(path, input);
  // Check the output's format before the work, not after.
  const MeshFormat format = formatFromPath(output);
  if (format != MeshFormat::OBJ && format != MeshFormat::PLY)
    throw Error("cannot write '" + output + "': a quad mesh is written as .obj or .ply");

  StageTimer timer(quiet);
  timer.start("read");
  TriangleMesh mesh = loadMesh(input, quiet);
  cleanInputMesh(mesh, input);
  const UnitCubeNormalization normalization = UnitCubeNormalization::fromMesh(mesh);
  normalization.apply(mesh);

  timer.start("layout");
  PatchLayout layout;
  computePatchLayout(mesh, parameters, layout);

  timer.start("write");
  QuadMesh quads = layout.quads;
  for (auto& v : quads.vertices)
    v = normalization.invert(v);
  writeQuadMesh(output, quads);
  if (args.has("frames"))
    writeFrames(args.get("frames"), normalization, layout);
  if (args.has("coarse")) {
    TriangleMesh coarse = layout.coarse;
    normalization.invert(coarse);
    writeMesh(args.get("coarse"), coarse);
  }
  if (args.has("png")) {
    // Quads light blue, triangles orange, larger faces red.
    std::vector<std::array<std::uint8_t, 3>> colours;
    for (const auto& face : quads.faces)
      colours.push_back(face.size() == 4   ? std::array<std::uint8_t, 3>{170, 200, 235}
                        : face.size() == 3 ? std::array<std::uint8_t, 3>{245, 170, 80}
                                           : std::array<std::uint8_t, 3>{230, 60, 60});
    RenderOptions options;
    options.draw_edges = true;  // the layout is the picture's point
    writePolygonsPNG(args.get("png"), quads.vertices, quads.faces, colours, options);
  }
  timer.stop();

  const QuadMeshStatistics stats = computeQuadMeshStatistics(layout.quads);
  if (args.has("json")) {
    JsonObject json;
    json.add("command", "quads").add("input", input).add("output", output);
    json.add("quad_length", parameters.quad_length).add("overlap", parameters.overlap);
    json.add("coarse_faces", layout.coarse.faces.size()).add("coarse_area_change", layout.coarse_report.area_change).add("refined_faces", layout.quad_report.refined_faces);
    json.add("vertices", stats.vertices).add("faces", stats.faces).add("quads", stats.quads);
    json.add("triangles", stats.triangles).add("other_faces", stats.other_faces);
    json.add("quad_fraction", stats.quad_fraction).add("interior_valence4_fraction", stats.interior_valence4_fraction);
    json.add("singularities", layout.quad_report.orientation_singularities);
    json.add("mean_edge_length", stats.mean_edge_length).add("mean_edge_length_input_units",
                                                             normalization.invertLength(stats.mean_edge_length));
    json.add("boundary_edges", stats.boundary_edges).add("nonmanifold_edges", stats.nonmanifold_edges);
    json.add("seeds", layout.seeds.size()).add("mean_seed_shift", layout.mean_seed_shift);
    JsonObject stages;
    stages.add("coarse", layout.seconds_coarse)
        .add("refine", layout.quad_report.seconds_refine)
        .add("hierarchy", layout.quad_report.seconds_hierarchy)
        .add("orientation_field", layout.quad_report.seconds_orientation)
        .add("position_field", layout.quad_report.seconds_position)
        .add("extraction", layout.quad_report.seconds_extraction)
        .add("frames", layout.seconds_frames);
    json.add("seconds_per_stage", stages).add("seconds", timer.json());
    std::cout << json.str() << '\n';
  } else {
    std::cout << "wrote " << output << ": " << stats.faces << " faces (" << stats.quads << " quads, "
              << stats.triangles << " triangles, " << stats.other_faces << " other), " << stats.vertices
              << " vertices, " << layout.quad_report.orientation_singularities << " singularities, mean edge "
              << normalization.invertLength(stats.mean_edge_length) << "; " << layout.seeds.size() << " seeds\n";
  }
  return 0;
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
