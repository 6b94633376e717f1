// `pcl_patchdict denoise IN [--dict DICT.pdd | --self-similar | --no-patches] -o OUT`: the
// geometric base (TaubinSmoother, iterations by the discrepancy principle), then, with a
// dictionary, every patch replaced by its sparse approximation to an error target matched to the
// noise (denoiseWithPatches). Vertex count, order and faces kept.
// Without --dict no patches are used unless --self-similar asks for a dictionary learned from the
// noisy input itself. Either way the patches go into the result only when Stein's risk estimate
// says they lower the error (--patch-decision always applies them regardless, to measure them).
#include "cli.h"
#include "options.h"
#include "repair_options.h"

#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/repair/patch_repairs.h>

#include <cstdio>
#include <iostream>

namespace pcl {
namespace patchdict {
namespace cli {

int runCloudDenoise(const std::vector<std::string>& raw);

int runDenoise(const std::vector<std::string>& raw)
{
  if (takesCloudPath(raw, "denoise"))
    return runCloudDenoise(raw);
  const RepairCommandLine line = parseRepairCommand(raw, commandSpec("denoise"), true);
  const Arguments& args = line.args;
  if (args.has("self-similar") && (args.has("dict") || args.has("no-patches")))
    throw UsageError("--self-similar excludes --dict and --no-patches");
  if (args.has("noise") && args.has("noise-edges"))
    throw UsageError("--noise and --noise-edges exclude each other");
  if (args.has("mu"))
    throw UsageError("--mu weighs the patch constraints of fill-missing and fill-holes; denoise's is --fidelity");
  if (!args.has("dict") && !args.has("self-similar"))
    refusePatchOptions(args, "denoise runs only with --dict or --self-similar");
  const bool quiet = line.quiet;
  const std::string& in_path = line.in_path;
  const std::string& out_path = line.out_path;
  DenoiseOptions parameters;
  readRepairOptions(args, parameters);
  parameters.noise_sigma = args.getDouble("noise");
  const double noise_edges = args.getDouble("noise-edges", 0.0);  // read only when given
  const bool use_patches = args.has("dict") || args.has("self-similar");
  const std::string dictionary_kind = args.has("dict") ? "given" : (use_patches ? "self-similar" : "none");
  parameters.error_factor = args.getDouble("error-factor");
  parameters.fidelity = args.getDouble("fidelity");
  parameters.base_iterations = static_cast<int>(args.getInt("base-iterations"));
  parameters.discrepancy = args.getDouble("discrepancy");
  parameters.decision.mode = args.getWord("patch-decision") == "always" ? PatchDecision::Always : PatchDecision::Auto;
  StageTimer timer(quiet);
  const RepairInputs inputs = loadRepairInputs(line, parameters.grid_size, "denoise", timer);
  const TriangleMesh& mesh = inputs.mesh;
  if (args.has("noise-edges"))  // σ in mean edge lengths, in the unit-cube units of the other lengths
    parameters.noise_sigma = noise_edges * UnitCubeNormalization::fromMesh(mesh).applyLength(mesh.meanEdgeLength());

  timer.start("denoise");
  setPatchSource(parameters, inputs.dictionary, use_patches);
  TriangleMesh denoised;
  DenoiseReport report;
  denoiseWithPatches(mesh, denoised, parameters, &report);
  char sigma_line[160];
  std::snprintf(sigma_line, sizeof sigma_line, "  noise sigma %.4g (%s, %.3f x mean edge)", report.noise_sigma,
                report.noise_estimated ? "estimated" : "given",
                report.noise_sigma / std::max(report.mean_edge_length, 1e-300));
  note(quiet, sigma_line);
  note(quiet, "  base: Taubin smoothing, " + std::to_string(report.base_iterations) + " iterations");
  const bool patch_stage_ran = report.outcome != PatchOutcome::NotRun;
  if (patch_stage_ran)
    note(quiet, patchStageSummary(report.patches));
  if (report.base_error >= 0.0) {  // measured, not forced
    char decision[200];
    std::snprintf(decision, sizeof decision, "  patches %s: estimated error %.4g with them, %.4g without (Stein)",
                  toString(report.outcome), report.patch_error, report.base_error);
    note(quiet, decision);
  }

  timer.start("write");
  writeMesh(out_path, denoised);
  timer.stop();
  const JsonObject report_json = reportIfAsked(inputs.report, mesh, denoised, denoised.numFaces(), quiet);

  if (args.has("json")) {
    JsonObject json;
    json.add("command", "denoise").add("input", in_path).add("output", out_path);
    json.add("vertices", mesh.numVertices()).add("faces", mesh.numFaces());
    json.add("patches", report.used_patches).add("dictionary", dictionary_kind);
    json.add("noise_sigma", report.noise_sigma).add("noise_estimated", report.noise_estimated);
    json.add("base_iterations", report.base_iterations);
    json.add("noise_sigma_over_mean_edge", report.noise_sigma / std::max(report.mean_edge_length, 1e-300));
    if (patch_stage_ran) {
      json.add("patch_decision", toString(report.outcome));
      if (report.base_error >= 0.0)
        json.add("estimated_error", JsonObject()
                                        .add("base", report.base_error)
                                        .add("patches", report.patch_error)
                                        .add("seconds", report.seconds_decision));
      json.add("patch_stage", patchStageJson(report.patches));
      json.add("sparsity", parameters.sparsity).add("error_factor", parameters.error_factor);
      json.add("fidelity", parameters.fidelity).add("mean_correction", report.mean_correction);
    }
    json.add("repair_stages", repairStagesJson(report)).add("seconds", timer.json());
    if (args.has("report"))
      json.add("report", report_json);
    std::cout << json.str() << '\n';
  } else if (!quiet) {
    std::printf("denoised %zu vertices (%s) -> %s\n", mesh.numVertices(),
                report.used_patches ? (dictionary_kind + " dictionary").c_str()
                : report.outcome == PatchOutcome::Declined ? "Taubin base: the patches were measured not to help"
                                                       : "Taubin base alone",
                out_path.c_str());
  }
  return 0;
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
