// Shared options and reporting of the repair subcommands (see repair_options.h).
#include <pcl_patchdict/io/patch_dictionary_io.h>
#include "repair_options.h"
#include "cloud_input.h"
#include "repair_report.h"

#include <algorithm>
#include <cstdio>

namespace pcl {
namespace patchdict {
namespace cli {

const std::vector<std::string>& patchStageOptionNames()
{
  static const std::vector<std::string> names = {
      "quad-length",  "quad-factor",    "sparsity",  "mu",         "overlap",         "atoms",
      "grid",         "patch-scale",    "centre-sigma", "observed-power", "fit-scale", "agreement-scale",
      "min-observed", "smoothing-iterations", "surface", "hole-factor", "error-factor", "fidelity",
      "patch-decision"};
  return names;
}

void refusePatchOptions(const Arguments& args, const std::string& why)
{
  for (const std::string& name : patchStageOptionNames())
    args.refuse(name, "tunes the patch stage, which " + why);
}

bool takesCloudPath(const std::vector<std::string>& raw, const std::string& command)
{
  const Arguments probe(raw, {&commandSpec(command), &commandSpec(command, "cloud")});
  return probe.positionals().size() == 1 && isCloudFile(probe.positionals()[0]);
}

RepairCommandLine parseRepairCommand(const std::vector<std::string>& raw, const CommandSpec& spec,
                                     bool keeps_vertex_order)
{
  RepairCommandLine line{readCommandLine(raw, spec), false, "", ""};
  line.quiet = line.args.quiet();
  line.in_path = line.args.positionals()[0];
  line.out_path = line.args.get("output");
  checkRepairOutput(line.out_path, line.in_path, keeps_vertex_order);
  return line;
}

void checkRepairOutput(const std::string& out_path, const std::string& in_path, bool keeps_vertex_order)
{
  checkOutputPath(out_path, in_path);
  const MeshFormat format = formatFromPath(out_path);
  if (keeps_vertex_order && (format == MeshFormat::Unknown || format == MeshFormat::PCD || format == MeshFormat::STL))
    throw Error("output '" + out_path + "' must be a mesh file that keeps vertex order (.ply, .obj, .off)");
  if (format == MeshFormat::Unknown || format == MeshFormat::PCD)
    throw Error("output '" + out_path + "' must be a mesh file (.ply, .obj, .off, .stl)");
}

TriangleMesh loadRepairMesh(const std::string& path, bool quiet, const std::string& command)
{
  TriangleMesh mesh = loadMesh(path, quiet);
  if (mesh.faces.empty())
    throw Error("'" + path + "' has no faces: " + command + " needs a triangle mesh");
  return mesh;
}

void readRepairOptions(const Arguments& args, PatchRepairCommon& options)
{
  if (args.has("dict") && args.has("no-patches"))
    throw UsageError("--dict and --no-patches exclude each other");
  if (args.has("ref") && !args.has("report"))
    throw UsageError("--ref is the reference of --report DIR");
  args.needs("error-scale", "ref", "it scales the report's error colouring, which needs a reference");
  if (args.has("no-patches"))
    refusePatchOptions(args, "--no-patches turns off");
  if (args.has("dict"))
    args.refuse("atoms", "sizes a self-similar dictionary; --dict brings its own atoms");
  options.quad_length = args.getDouble("quad-length");
  options.quad_length_factor = args.getDouble("quad-factor");
  options.sparsity = static_cast<int>(args.getInt("sparsity"));
  options.overlap = static_cast<int>(args.getInt("overlap"));
  options.smoothing_iterations = static_cast<int>(args.getInt("smoothing-iterations"));
  options.self_similar_atoms = static_cast<int>(args.getInt("atoms"));
  options.grid_size = static_cast<int>(args.getInt("grid", options.grid_size));  // 0: the dictionary's
  options.patch_scale = args.getDouble("patch-scale");
  options.centre_sigma = args.getDouble("centre-sigma");
  options.observed_power = args.getDouble("observed-power");
  options.fit_scale = args.getDouble("fit-scale");
  options.agreement_scale = args.getDouble("agreement-scale");
  options.min_observed_fraction = args.getDouble("min-observed");
  options.seed = static_cast<std::uint64_t>(args.getInt("seed"));
}

void setPatchSource(PatchRepairCommon& options, const PatchDictionary::ConstPtr& dictionary, bool use_patches)
{
  if (!use_patches)
    options.decision.mode = PatchDecision::Never;
  options.dictionary = use_patches ? dictionary : nullptr;
}

RepairInputs loadRepairInputs(const RepairCommandLine& line, int grid_size, const std::string& command,
                              StageTimer& timer)
{
  RepairInputs inputs;
  inputs.report = prepareReport(line.args);
  timer.start("load");
  inputs.mesh = loadRepairMesh(line.in_path, line.quiet, command);
  if (line.args.has("dict"))
    inputs.dictionary = loadPatchDictionary(line.args.get("dict"), grid_size);
  return inputs;
}

ReportRequest prepareReport(const Arguments& args)
{
  ReportRequest request;
  if (!args.has("report"))
    return request;
  request.error_scale = args.getDouble("error-scale");
  if (args.has("ref")) {
    request.reference = loadMesh(args.get("ref"), true);
    if (request.reference.faces.empty())
      throw Error("--ref '" + args.get("ref") + "' has no faces: the error colouring needs a surface");
    request.has_reference = true;
  }
  makeFolder(args.get("report"), "report");
  request.folder = args.get("report");
  return request;
}

JsonObject reportIfAsked(const ReportRequest& request, const TriangleMesh& before, const TriangleMesh& after,
                         std::size_t first_new_face, bool quiet)
{
  if (request.folder.empty())
    return JsonObject();
  note(quiet, "report -> " + request.folder);
  return writeRepairReport(request.folder, before, after, first_new_face,
                           request.has_reference ? &request.reference : nullptr, request.error_scale);
}

std::string dictionaryKind(const Arguments& args)
{
  return args.has("no-patches") ? "none" : (args.has("dict") ? "given" : "self-similar");
}

std::string patchStageSummary(const PatchCorrectionReport& report)
{
  char text[320];
  std::snprintf(text, sizeof text,
                "  L = %.4g (%.2f x mean edge), %zu of %zu patches used, %.1f atoms per code, %zu constraints on %zu "
                "vertices",
                report.quad_length, report.quad_length / std::max(report.mean_edge_length, 1e-300),
                report.patches_used, report.patches, report.mean_atoms, report.constraints,
                report.constrained_vertices);
  return text;
}

JsonObject patchStageJson(const PatchCorrectionReport& report)
{
  JsonObject json;
  json.add("mean_edge_length", report.mean_edge_length).add("quad_length", report.quad_length);
  json.add("quad_length_over_mean_edge", report.quad_length / std::max(report.mean_edge_length, 1e-300));
  json.add("patch_side", report.patch_side).add("grid_size", report.grid_size).add("atoms", report.atoms);
  json.add("self_similar", report.self_similar);
  json.add("patch_count", report.patches).add("patches_used", report.patches_used);
  json.add("observed_fraction", report.observed_fraction).add("mean_atoms_per_code", report.mean_atoms);
  json.add("constraints", report.constraints).add("constrained_vertices", report.constrained_vertices);
  return json;
}

namespace {

/** The stages' seconds; `check`: the relief check's (zeros for the repairs without one). */
JsonObject stagesJson(const PatchRepairReport& report, const HoleRepairReport& check)
{
  JsonObject json;
  json.add("base", report.seconds_base).add("surface_check", check.seconds_check);
  json.add("check_layout", check.seconds_check_layout).add("check_patches", check.seconds_check_patches);
  json.add("check_prediction", check.seconds_check_prediction);
  json.add("patch_stage", report.seconds_patch_stage);
  json.add("layout", report.patches.seconds_layout).add("patches", report.patches.seconds_patches);
  json.add("dictionary", report.patches.seconds_dictionary).add("coding", report.patches.seconds_coding);
  json.add("constraints", report.patches.seconds_constraints).add("solve", report.seconds_solve);
  return json;
}

}  // namespace

JsonObject repairStagesJson(const PatchRepairReport& report) { return stagesJson(report, HoleRepairReport()); }
JsonObject repairStagesJson(const HoleRepairReport& report) { return stagesJson(report, report); }

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
