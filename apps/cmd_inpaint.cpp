// `pcl_patchdict inpaint IN --missing IDX.txt [--dict DICT.pdd | --no-patches] -o OUT`: recovers
// the positions of missing vertices (connectivity known) — bi-Laplacian base + patch correction.
#include "cli.h"

#include <pcl_patchdict/index_io.h>
#include <pcl_patchdict/patch_dictionary.h>
#include <pcl_patchdict/sparse_patch_inpainter.h>

#include <cstdio>
#include <iostream>

namespace pcl {
namespace patchdict {
namespace cli {

namespace {

const char* const kUsage =
    "pcl_patchdict inpaint IN --missing IDX.txt [--dict DICT.pdd | --no-patches] -o OUT [--quad-length L] "
    "[--quad-factor C] [--sparsity S] [--mu M] [--overlap K] [--atoms K] [--grid N] [--json]";

}  // namespace

int runInpaint(const std::vector<std::string>& raw)
{
  auto value_options = commonValueOptions();
  value_options.insert({"output", "missing", "dict", "quad-length", "quad-factor", "sparsity", "mu", "overlap",
                        "atoms", "grid", "patch-scale", "centre-sigma", "observed-power", "fit-scale",
                        "agreement-scale", "min-observed"});
  auto flag_options = commonFlagOptions();
  flag_options.insert("no-patches");
  const Arguments args(raw, value_options, flag_options);
  args.expectPositionals(1, 1, kUsage);
  if (!args.has("output") || !args.has("missing"))
    throw UsageError("usage: " + std::string(kUsage));
  if (args.has("dict") && args.has("no-patches"))
    throw UsageError("--dict and --no-patches exclude each other");
  applyCommonOptions(args);
  const bool quiet = args.has("quiet") || args.has("json");
  const std::string in_path = args.positionals()[0], out_path = args.get("output");
  refuseOverwritingInput(out_path, in_path);
  if (formatFromPath(out_path) == MeshFormat::Unknown || formatFromPath(out_path) == MeshFormat::PCD ||
      formatFromPath(out_path) == MeshFormat::STL)
    throw Error("output '" + out_path + "' must be a mesh file that keeps vertex order (.ply, .obj, .off)");

  SparsePatchInpainter::Parameters parameters;
  parameters.quad_length = args.getDouble("quad-length", 0.0, 0.0, 0.5);
  parameters.quad_length_factor = args.getDouble("quad-factor", parameters.quad_length_factor, 0.1, 1000.0);
  parameters.sparsity = static_cast<int>(args.getInt("sparsity", parameters.sparsity, 1, 1024));
  parameters.constraint_weight = args.getDouble("mu", parameters.constraint_weight, 0.0, 1e12);
  parameters.overlap = static_cast<int>(args.getInt("overlap", parameters.overlap, 0, 8));
  parameters.self_similar_atoms = static_cast<int>(args.getInt("atoms", parameters.self_similar_atoms, 1, 65536));
  parameters.grid_size = static_cast<int>(args.getInt("grid", 0, 0, 256));
  parameters.patch_scale = args.getDouble("patch-scale", parameters.patch_scale, 0.05, 20.0);
  parameters.centre_sigma = args.getDouble("centre-sigma", parameters.centre_sigma, 0.0, 100.0);
  parameters.observed_power = args.getDouble("observed-power", parameters.observed_power, 0.0, 100.0);
  parameters.fit_scale = args.getDouble("fit-scale", parameters.fit_scale, 0.0, 1e6);
  parameters.agreement_scale = args.getDouble("agreement-scale", parameters.agreement_scale, 0.0, 1e6);
  parameters.min_observed_fraction = args.getDouble("min-observed", parameters.min_observed_fraction, 0.0, 1.0);
  parameters.seed = static_cast<std::uint64_t>(args.getInt("seed", 0, 0, (1LL << 62)));

  StageTimer timer(quiet);
  timer.start("load");
  const TriangleMesh mesh = loadMesh(in_path, quiet);
  const std::vector<int> missing = readIndexFile(args.get("missing"), mesh.numVertices());
  PatchDictionary::ConstPtr dictionary;
  if (args.has("dict"))
    dictionary = PatchDictionary::load(args.get("dict"));

  timer.start("inpaint");
  SparsePatchInpainter inpainter;
  inpainter.setInputMesh(mesh);
  inpainter.setMissingVertices(missing);
  inpainter.setDictionary(dictionary);
  inpainter.setUsePatches(!args.has("no-patches"));
  inpainter.setParameters(parameters);
  TriangleMesh repaired;
  SparsePatchInpainter::Report report;
  inpainter.process(repaired, &report);

  timer.start("write");
  writeMesh(out_path, repaired);
  timer.stop();

  const std::string dictionary_kind =
      args.has("no-patches") ? "none" : (args.has("dict") ? "given" : "self-similar");
  if (report.used_patches)
    note(quiet, "  L = " + std::to_string(report.quad_length) + " (" +
                    std::to_string(report.quad_length / std::max(report.mean_edge_length, 1e-300)) +
                    " × mean edge), " + std::to_string(report.patches_used) + " of " +
                    std::to_string(report.patches) + " patches used, " + std::to_string(report.constraints) +
                    " constraints on " + std::to_string(report.constrained_vertices) + " vertices");
  if (args.has("json")) {
    JsonObject json;
    json.add("command", "inpaint").add("input", in_path).add("output", out_path);
    json.add("vertices", mesh.numVertices()).add("faces", mesh.numFaces());
    json.add("missing_vertices", report.missing_vertices).add("isolated_missing", report.isolated_missing);
    json.add("patches", report.used_patches).add("dictionary", dictionary_kind);
    if (report.used_patches) {
      json.add("mean_edge_length", report.mean_edge_length).add("quad_length", report.quad_length);
      json.add("quad_length_over_mean_edge", report.quad_length / std::max(report.mean_edge_length, 1e-300));
      json.add("patch_side", report.patch_side).add("grid_size", report.grid_size).add("atoms", report.atoms);
      json.add("sparsity", parameters.sparsity).add("mu", parameters.constraint_weight);
      json.add("patch_count", report.patches).add("patches_used", report.patches_used);
      json.add("observed_fraction", report.observed_fraction).add("constraints", report.constraints);
      json.add("constrained_vertices", report.constrained_vertices);
      json.add("mean_correction", report.mean_correction);
    }
    JsonObject stages;
    stages.add("first_guess", report.seconds_first_guess).add("layout", report.seconds_layout);
    stages.add("patches", report.seconds_patches).add("dictionary", report.seconds_dictionary);
    stages.add("coding", report.seconds_coding).add("solve", report.seconds_solve);
    json.add("inpaint_stages", stages).add("seconds", timer.json());
    std::cout << json.str() << '\n';
  } else if (!quiet) {
    std::printf("recovered %zu missing vertices (%s) -> %s\n", report.missing_vertices,
                report.used_patches ? (dictionary_kind + " dictionary").c_str() : "bi-Laplacian", out_path.c_str());
  }
  return 0;
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
