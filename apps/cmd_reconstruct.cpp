// `pcl_patchdict reconstruct IN -o OUT [--dict DICT.pdd]`: surface → patches → surface on the
// input's own connectivity (section 3.4 of the paper) — the identity round trip, or through a
// dictionary (sparse codes with --sparsity atoms, decoded) — scored against the input.
#include "cli.h"
#include "options.h"
#include "surface_patches.h"

#include <pcl_patchdict/patches/height_maps.h>
#include <pcl_patchdict/geometry/metrics.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/coding/patch_dictionary.h>
#include <pcl_patchdict/patches/patch_mesh_reconstruction.h>
#include <pcl_patchdict/io/patch_dictionary_io.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <utility>

namespace pcl {
namespace patchdict {
namespace cli {

namespace {

/** Encodes the observed bins with `sparsity` atoms and decodes every patch in place; returns the
  * RMS error over the observed bins. Unobserved bins stay unobserved: decoded values there are
  * extrapolation, not surface. */
double codeThroughDictionary(const PatchDictionary& dictionary, int sparsity, PatchSet& patches)
{
  const PatchCodes codes = dictionary.encodeMasked(patches.heights, patches.observed, {sparsity, 0.0});
  Eigen::MatrixXd decoded = dictionary.decode(codes);
  const double rmse = observedRMSE(decoded, patches.heights, patches.observed);
  patches.heights = std::move(decoded);
  return rmse;
}

/** The command line of `reconstruct`, read and checked before any work (defaults: the table's). */
struct ReconstructLine {
  bool quiet = false;
  std::string input, output, rule_name;
  int grid_size = 0, overlap = 0, sparsity = 0;
  double quad_length = 0.0;
  SeedPlacement placement = SeedPlacement::Quads;
  std::size_t samples = 0;
  std::uint64_t seed = 0;
};

/** The layout the line asks for (seeds as `patches` lays them). */
PatchLayoutParameters layoutOf(const ReconstructLine& line)
{
  PatchLayoutParameters parameters;
  parameters.quad_length = line.quad_length;
  parameters.overlap = line.overlap;
  parameters.seed = line.seed;
  return parameters;
}

// 1. The command line.
ReconstructLine readReconstructLine(const Arguments& args)
{
  ReconstructLine line;
  line.rule_name = args.getWord("rule");
  if (args.has("sparsity") && !args.has("dict"))
    throw UsageError("--sparsity needs --dict");
  line.quiet = args.quiet();
  line.grid_size = static_cast<int>(args.getInt("grid"));
  line.quad_length = args.getDouble("quad-length");
  line.overlap = static_cast<int>(args.getInt("overlap"));
  line.placement = parseSeedPlacement(args.getWord("placement"));
  line.sparsity = static_cast<int>(args.getInt("sparsity"));
  line.samples = static_cast<std::size_t>(args.getInt("samples"));
  line.seed = static_cast<std::uint64_t>(args.getInt("seed"));
  line.input = args.positionals()[0];
  line.output = args.get("output");
  checkOutputPath(line.output, line.input);
  if (formatFromPath(line.output) == MeshFormat::Unknown)
    throw Error("output '" + line.output + "' must be a mesh or cloud file (.ply, .obj, .off, .stl, .pcd)");
  if (args.has("dict") && sameFile(args.get("dict"), line.output))
    throw UsageError("--dict and -o name the same file");
  return line;
}

/** The result back in the input's units, written to -o (the timer's "save" stage). */
void saveResult(const ReconstructLine& line, const UnitCubeNormalization& normalization, TriangleMesh& result,
                StageTimer& timer)
{
  timer.start("save");
  normalization.invert(result);
  writeMesh(line.output, result);
  timer.stop();
}

/** The input moved into its unit cube, and its patches: seeds laid by layPatches, heights extracted (the
  * timer's "seeds" and "extract" stages). */
PatchSet unitCubePatches(const ReconstructLine& line, TriangleMesh& reference, UnitCubeNormalization& normalization,
                         StageTimer& timer)
{
  normalization = UnitCubeNormalization::fromMesh(reference);
  normalization.apply(reference);
  timer.start("seeds");
  const PatchLayout layout = layPatches(reference, layoutOf(line), line.placement);
  timer.start("extract");
  return extractSurfacePatches(reference, layout, line.grid_size);
}

// 2. A cloud has no vertices to move: its output is the cloud of the patches' observed bins.
int reconstructCloud(const Arguments& args, const ReconstructLine& line, TriangleMesh reference,
                     const PatchDictionary::Ptr& dictionary, StageTimer& timer)
{
  if (line.placement != SeedPlacement::Quads)
    throw Error("a point cloud needs --placement quads (its seeds lie on its Poisson surface)");
  args.refuse("rule", "reads patches at a mesh's vertices; a cloud's output is the patches' points");
  args.refuse("samples", "samples a mesh's score; a cloud is scored point to point");
  UnitCubeNormalization normalization;
  PatchSet patches = unitCubePatches(line, reference, normalization, timer);
  const double patch_rmse = dictionary ? codeThroughDictionary(*dictionary, line.sparsity, patches) : 0.0;
  timer.start("reconstruct");
  TriangleMesh result;
  result.vertices = patchSetToPoints(patches);
  timer.start("eval");
  const PointSetDistance to_input = pointsToPointsDistance(result.vertices, reference.vertices);
  const PointSetDistance from_input = pointsToPointsDistance(reference.vertices, result.vertices);
  saveResult(line, normalization, result, timer);
  if (args.has("json")) {
    JsonObject json;
    json.add("command", "reconstruct").add("input", line.input).add("output", line.output).add("input_kind", "cloud");
    if (dictionary)
      json.add("dictionary", args.get("dict")).add("sparsity", line.sparsity).add("patch_rmse", patch_rmse);
    else
      json.addNull("dictionary");
    json.add("points_in", reference.vertices.size()).add("points_out", result.vertices.size());
    json.add("patches", patches.numPatches()).add("grid_size", line.grid_size).add("quad_length", line.quad_length);
    json.add("observed_fraction", patches.observedFraction()).add("units", "unit-cube");
    json.add("output_to_input_mean", to_input.mean).add("output_to_input_rms", to_input.rms);
    json.add("input_to_output_mean", from_input.mean).add("input_to_output_max", from_input.max);
    json.add("seconds", timer.json());
    std::cout << json.str() << '\n';
  } else if (!line.quiet) {
    std::printf("cloud round trip: %zu points from %zu patches, mean distance to the input %.4g, of the input to "
                "them %.4g (unit-cube units) -> %s\n",
                result.vertices.size(), patches.numPatches(), to_input.mean, from_input.mean, line.output.c_str());
  }
  return 0;
}

/** The vertices some face uses (the others keep their place and are left out of the scores). */
std::vector<int> referencedVertices(const TriangleMesh& mesh)
{
  std::vector<int> referenced;
  std::vector<char> used(mesh.vertices.size(), 0);
  for (const Face& f : mesh.faces)
    for (const auto v : f)
      used[static_cast<std::size_t>(v)] = 1;
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v])
      referenced.push_back(static_cast<int>(v));
  return referenced;
}

// 3. A mesh: its patches read back at its own vertices, scored against it.
int reconstructMesh(const Arguments& args, const ReconstructLine& line, TriangleMesh reference,
                    const PatchDictionary::Ptr& dictionary, StageTimer& timer)
{
  const std::vector<int> referenced = referencedVertices(reference);
  UnitCubeNormalization normalization;
  PatchSet patches = unitCubePatches(line, reference, normalization, timer);
  double patch_rmse = 0.0;
  if (dictionary) {
    timer.start("code");
    patch_rmse = codeThroughDictionary(*dictionary, line.sparsity, patches);
  }

  timer.start("reconstruct");
  PatchMeshReconstruction reconstruction;
  reconstruction.setPatches(std::make_shared<const PatchSet>(patches));
  reconstruction.setTargetMesh(std::make_shared<const TriangleMesh>(reference));
  reconstruction.setRule(line.rule_name == "bilinear" ? PatchMeshReconstruction::Rule::Bilinear
                                                      : PatchMeshReconstruction::Rule::BinCentres);
  TriangleMesh result;
  PatchMeshReconstruction::Report report;
  reconstruction.compute(result, &report);

  timer.start("eval");
  const double rmse = vertexRMSE(reference, result, referenced);
  std::vector<Eigen::Vector3d> moved;
  moved.reserve(referenced.size());
  for (const int v : referenced)
    moved.push_back(result.vertices[static_cast<std::size_t>(v)]);
  const PointSetDistance to_surface = pointsToSurfaceDistance(moved, reference);
  const SurfaceDistance distance = surfaceDistance(reference, result, line.samples, line.seed);

  saveResult(line, normalization, result, timer);

  if (args.has("json")) {
    JsonObject json;
    json.add("command", "reconstruct").add("input", line.input).add("output", line.output).add("rule", line.rule_name);
    if (dictionary)
      json.add("dictionary", args.get("dict")).add("atoms", static_cast<long long>(dictionary->atoms().cols()))
          .add("sparsity", line.sparsity).add("patch_rmse", patch_rmse);
    else
      json.addNull("dictionary");
    json.add("vertices", reference.vertices.size()).add("faces", reference.faces.size());
    json.add("patches", patches.numPatches()).add("grid_size", line.grid_size).add("quad_length", line.quad_length);
    json.add("overlap", line.overlap).add("placement", args.getWord("placement"))
        .add("observed_fraction", patches.observedFraction());
    json.add("vertices_covered", report.vertices_covered).add("vertices_from_ring", report.vertices_from_ring);
    json.add("vertices_unchanged", report.vertices_unchanged).add("mean_estimates", report.mean_estimates);
    json.add("units", "unit-cube").add("vertex_rmse", rmse);
    json.add("vertex_to_surface_mean", to_surface.mean).add("vertex_to_surface_max", to_surface.max);
    json.add("surface_mean", distance.mean).add("surface_rms", distance.rms).add("hausdorff", distance.hausdorff);
    json.add("psnr_db", distance.psnr).add("seconds", timer.json());
    std::cout << json.str() << '\n';
  } else if (!line.quiet) {
    std::printf("%s round trip (%s rule, %zu patches): vertex RMSE %.4g, PSNR %.2f dB, mean vertex-to-surface %.4g "
                "(unit-cube units) -> %s\n",
                dictionary ? "dictionary" : "identity", line.rule_name.c_str(), patches.numPatches(), rmse,
                distance.psnr, to_surface.mean, line.output.c_str());
  }
  return 0;
}

}  // namespace

int runReconstruct(const std::vector<std::string>& raw)
{
  const Arguments args = readCommandLine(raw, commandSpec("reconstruct"));
  const ReconstructLine line = readReconstructLine(args);

  StageTimer timer(line.quiet);
  timer.start("load");
  TriangleMesh reference = loadMesh(line.input, line.quiet);
  PatchDictionary::Ptr dictionary;
  if (args.has("dict"))
    dictionary = loadPatchDictionary(args.get("dict"), line.grid_size);
  if (reference.faces.empty())
    return reconstructCloud(args, line, std::move(reference), dictionary, timer);
  return reconstructMesh(args, line, std::move(reference), dictionary, timer);
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
