// `pcl_patchdict reconstruct IN -o OUT [--dict DICT.pdd]`: surface → patches → surface on the
// input's own connectivity (section 3.4 of the paper) — the identity round trip, or through a
// dictionary (sparse codes with --sparsity atoms, decoded) — scored against the input.
#include "cli.h"
#include "patch_seeds.h"

#include <pcl_patchdict/metrics.h>
#include <pcl_patchdict/normalization.h>
#include <pcl_patchdict/patch_dictionary.h>
#include <pcl_patchdict/patch_mesh_reconstruction.h>

#include <cmath>
#include <cstdio>
#include <iostream>

namespace pcl {
namespace patchdict {
namespace cli {

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
  refuseOverwritingInput(output, input);
  if (args.has("dict") && sameFile(args.get("dict"), output))
    throw UsageError("--dict and -o name the same file");

  StageTimer timer(quiet);
  timer.start("load");
  TriangleMesh reference = loadMesh(input, quiet);
  if (reference.faces.empty())
    throw Error("'" + input + "' has no faces: reconstruct needs a mesh (point-cloud output is not in this version yet)");
  PatchDictionary::Ptr dictionary;
  if (args.has("dict"))
    dictionary = PatchDictionary::load(args.get("dict"), grid_size);
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
    const PatchCodes codes = dictionary->encodeMasked(patches.heights, patches.observed, {sparsity, 0.0});
    const Eigen::MatrixXd decoded = dictionary->decode(codes);
    double squared = 0.0;
    std::size_t count = 0;
    for (Eigen::Index i = 0; i < decoded.size(); ++i)
      if (patches.observed.data()[i]) {
        squared += std::pow(decoded.data()[i] - patches.heights.data()[i], 2);
        ++count;
      }
    patch_rmse = count ? std::sqrt(squared / static_cast<double>(count)) : 0.0;
    // Unobserved bins stay unobserved: the decoded values there are extrapolation, not surface.
    patches.heights = decoded;
  }

  timer.start("reconstruct");
  PatchMeshReconstruction reconstruction;
  reconstruction.setPatches(patches);
  reconstruction.setTargetMesh(reference);
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
