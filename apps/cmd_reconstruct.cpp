// `pcl_patchdict reconstruct IN -o OUT [--dict DICT.pdd]`: surface → patches → surface on the
// input's own connectivity (section 3.4 of the paper) — the identity round trip, or through a
// dictionary (sparse codes with --sparsity atoms, decoded) — scored against the input.
#include "cli.h"
#include "surface_patches.h"

#include <pcl_patchdict/patches/height_map_patch_extractor.h>
#include <pcl_patchdict/geometry/metrics.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/coding/patch_dictionary.h>
#include <pcl_patchdict/patches/patch_mesh_reconstruction.h>

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

}  // namespace

int runReconstruct(const std::vector<std::string>& raw)
{
  auto value_options = commonValueOptions();
  value_options.insert({"output", "dict", "rule", "sparsity", "grid", "quad-length", "overlap", "placement", "samples"});
  const Arguments args(raw, value_options, commonFlagOptions());
  const std::string usage =
      "pcl_patchdict reconstruct IN -o OUT [--dict DICT.pdd [--sparsity S]] [--rule bilinear|bin-centres] "
      "[--grid N] [--quad-length L] [--overlap K] [--placement quads|random] [--samples N] [--json]";
  args.expectPositionals(1, 1, usage);
  if (!args.has("output"))
    throw UsageError("usage: " + usage);
  const std::string rule_name = args.get("rule", "bilinear");
  if (rule_name != "bilinear" && rule_name != "bin-centres")
    throw UsageError("option --rule: '" + rule_name + "' is not bilinear or bin-centres");
  if (args.has("sparsity") && !args.has("dict"))
    throw UsageError("--sparsity needs --dict");
  applyCommonOptions(args);
  const bool quiet = args.has("quiet") || args.has("json");
  const int grid_size = static_cast<int>(args.getInt("grid", 16, 2, 64));
  const double quad_length = args.getDouble("quad-length", 0.03, 1e-3, 0.5);
  const int overlap = static_cast<int>(args.getInt("overlap", 1, 0, 16));
  const SeedPlacement placement = parseSeedPlacement(args.get("placement", "quads"));
  const int sparsity = static_cast<int>(args.getInt("sparsity", 20, 1, 1024));
  const auto samples = static_cast<std::size_t>(args.getInt("samples", 200000, 1000, 100000000));
  const auto seed = static_cast<std::uint64_t>(args.getInt("seed", 1, 0, (1LL << 62)));
  const std::string input = args.positionals()[0], output = args.get("output");
  checkOutputPath(output, input);
  if (formatFromPath(output) == MeshFormat::Unknown)
    throw Error("output '" + output + "' must be a mesh or cloud file (.ply, .obj, .off, .stl, .pcd)");
  if (args.has("dict") && sameFile(args.get("dict"), output))
    throw UsageError("--dict and -o name the same file");

  StageTimer timer(quiet);
  timer.start("load");
  TriangleMesh reference = loadMesh(input, quiet);
  PatchDictionary::Ptr dictionary;
  if (args.has("dict"))
    dictionary = PatchDictionary::load(args.get("dict"), grid_size);
  if (reference.faces.empty()) {
    // A cloud has no vertices to move: its output is the cloud of the patches' observed bins.
    if (placement != SeedPlacement::Quads)
      throw Error("a point cloud needs --placement quads (its seeds lie on its Poisson surface)");
    const UnitCubeNormalization normalization = UnitCubeNormalization::fromMesh(reference);
    normalization.apply(reference);
    timer.start("seeds");
    const SeedsAndFrames seeds = computeSeedsAndFrames(reference, quad_length, overlap, seed, placement);
    timer.start("extract");
    HeightMapPatchExtractor extractor;
    extractor.setInputCloud(std::make_shared<const TriangleMesh>(reference));
    extractor.setSeeds(seeds.seeds, seeds.frames);
    extractor.setRadius(quad_length / std::sqrt(2.0));
    extractor.setGridSize(grid_size);
    PatchSet patches;
    extractor.compute(patches);
    const double patch_rmse = dictionary ? codeThroughDictionary(*dictionary, sparsity, patches) : 0.0;
    timer.start("reconstruct");
    TriangleMesh result;
    result.vertices = patchSetToPoints(patches);
    timer.start("eval");
    const PointSetDistance to_input = pointsToPointsDistance(result.vertices, reference.vertices);
    const PointSetDistance from_input = pointsToPointsDistance(reference.vertices, result.vertices);
    timer.start("save");
    normalization.invert(result);
    writeMesh(output, result);
    timer.stop();
    if (args.has("json")) {
      JsonObject json;
      json.add("command", "reconstruct").add("input", input).add("output", output).add("input_kind", "cloud");
      if (dictionary)
        json.add("dictionary", args.get("dict")).add("sparsity", sparsity).add("patch_rmse", patch_rmse);
      else
        json.addNull("dictionary");
      json.add("points_in", reference.vertices.size()).add("points_out", result.vertices.size());
      json.add("patches", patches.numPatches()).add("grid_size", grid_size).add("quad_length", quad_length);
      json.add("observed_fraction", patches.observedFraction()).add("units", "unit-cube");
      json.add("output_to_input_mean", to_input.mean).add("output_to_input_rms", to_input.rms);
      json.add("input_to_output_mean", from_input.mean).add("input_to_output_max", from_input.max);
      json.add("seconds", timer.json());
      std::cout << json.str() << '\n';
    } else if (!quiet) {
      std::printf("cloud round trip: %zu points from %zu patches, mean distance to the input %.4g, of the input to "
                  "them %.4g (unit-cube units) -> %s\n",
                  result.vertices.size(), patches.numPatches(), to_input.mean, from_input.mean, output.c_str());
    }
    return 0;
  }
  // Vertices no face uses keep their place: they are left out of the scores.
  std::vector<int> referenced;
  {
    std::vector<char> used(reference.vertices.size(), 0);
    for (const Face& f : reference.faces)
      for (const auto v : f)
        used[static_cast<std::size_t>(v)] = 1;
    for (std::size_t v = 0; v < used.size(); ++v)
      if (used[v])
        referenced.push_back(static_cast<int>(v));
  }
  const UnitCubeNormalization normalization = UnitCubeNormalization::fromMesh(reference);
  normalization.apply(reference);

  timer.start("seeds");
  const SeedsAndFrames seeds = computeSeedsAndFrames(reference, quad_length, overlap, seed, placement);
  timer.start("extract");
  PatchSet patches = extractMeshPatches(reference, seeds, quad_length, grid_size);
  double patch_rmse = 0.0;
  if (dictionary) {
    timer.start("code");
    patch_rmse = codeThroughDictionary(*dictionary, sparsity, patches);
  }

  timer.start("reconstruct");
  PatchMeshReconstruction reconstruction;
  reconstruction.setPatches(std::make_shared<const PatchSet>(patches));
  reconstruction.setTargetMesh(std::make_shared<const TriangleMesh>(reference));
  reconstruction.setRule(rule_name == "bilinear" ? PatchMeshReconstruction::Rule::Bilinear
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
  const SurfaceDistance distance = surfaceDistance(reference, result, samples, seed);

  timer.start("save");
  normalization.invert(result);
  writeMesh(output, result);
  timer.stop();

  if (args.has("json")) {
    JsonObject json;
    json.add("command", "reconstruct").add("input", input).add("output", output).add("rule", rule_name);
    if (dictionary)
      json.add("dictionary", args.get("dict")).add("atoms", static_cast<long long>(dictionary->atoms().cols()))
          .add("sparsity", sparsity).add("patch_rmse", patch_rmse);
    else
      json.addNull("dictionary");
    json.add("vertices", reference.vertices.size()).add("faces", reference.faces.size());
    json.add("patches", patches.numPatches()).add("grid_size", grid_size).add("quad_length", quad_length);
    json.add("overlap", overlap).add("placement", args.get("placement", "quads")).add("observed_fraction", patches.observedFraction());
    json.add("vertices_covered", report.vertices_covered).add("vertices_from_ring", report.vertices_from_ring);
    json.add("vertices_unchanged", report.vertices_unchanged).add("mean_estimates", report.mean_estimates);
    json.add("units", "unit-cube").add("vertex_rmse", rmse);
    json.add("vertex_to_surface_mean", to_surface.mean).add("vertex_to_surface_max", to_surface.max);
    json.add("surface_mean", distance.mean).add("surface_rms", distance.rms).add("hausdorff", distance.hausdorff);
    json.add("psnr_db", distance.psnr).add("seconds", timer.json());
    std::cout << json.str() << '\n';
  } else if (!quiet) {
    std::printf("%s round trip (%s rule, %zu patches): vertex RMSE %.4g, PSNR %.2f dB, mean vertex-to-surface %.4g "
                "(unit-cube units) -> %s\n",
                dictionary ? "dictionary" : "identity", rule_name.c_str(), patches.numPatches(), rmse, distance.psnr,
                to_surface.mean, output.c_str());
  }
  return 0;
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
