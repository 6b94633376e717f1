// `pcl_patchdict fill-holes IN [--dict DICT.pdd | --no-patches] -o OUT`: Liepa's
// triangulate–refine–fair, then the new vertices corrected by patches (fillHolesWithPatches).
// The output keeps the input vertices first, bit-identical and in order, then the new ones.
#include "cli.h"
#include "options.h"
#include "repair_options.h"

#include <pcl_patchdict/geometry/hole_filling.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/repair/patch_repairs.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <map>

namespace pcl {
namespace patchdict {
namespace cli {

int runCloudFillHoles(const std::vector<std::string>& raw);

namespace {

/** --json of a mesh fill. */
JsonObject fillHolesJson(const Arguments& args, const RepairCommandLine& line,
                         const HoleRepairOptions& parameters, const TriangleMesh& mesh,
                         const TriangleMesh& filled, const HoleRepairReport& repair,
                         const std::map<std::string, std::size_t>& reasons, const StageTimer& timer,
                         const JsonObject& report_json)
{
  const HoleFilling::Report& report = repair.holes;
  const std::string& in_path = line.in_path;
  const std::string& out_path = line.out_path;
  JsonObject json;
  json.add("command", "fill-holes").add("input", in_path).add("output", out_path).add("method", "liepa");
  json.add("input_vertices", mesh.vertices.size()).add("input_faces", mesh.faces.size());
  json.add("output_vertices", filled.vertices.size()).add("output_faces", filled.faces.size());
  json.add("holes_found", report.holes_found).add("holes_filled", report.holes_filled);
  json.add("holes_skipped", report.holes_skipped);
  JsonObject skipped;
  for (const auto& [reason, count] : reasons)
    skipped.add(reason, count);
  json.add("skipped_reasons", skipped);
  json.add("new_vertices", report.new_vertices).add("new_faces", report.new_faces);
  json.add("fairing_solved", report.fairing_solved);
  JsonObject holes;
  for (std::size_t h = 0; h < report.holes.size(); ++h) {
    const auto& hole = report.holes[h];
    JsonObject entry;
    entry.add("edges", hole.boundary.size()).add("length", hole.length).add("diameter", hole.diameter);
    entry.add("status", toString(hole.skipped));
    entry.add("new_vertices", hole.new_vertices.size()).add("new_faces", hole.new_faces.size());
    holes.add(std::to_string(h), entry);
  }
  json.add("holes", holes);
  if (repair.used_patches) {
    json.add("surface", repair.relief ? "relief" : "smooth").add("prediction_gain", repair.relief_gain);
    json.add("patch_stage", patchStageJson(repair.patches));
    json.add("sparsity", parameters.sparsity).add("mu", parameters.constraint_weight);
    json.add("mean_correction", repair.mean_correction);
  }
  json.add("repair_stages", repairStagesJson(repair));
  JsonObject seconds = timer.json();
  seconds.add("triangulation", report.seconds_triangulation)
      .add("refinement", report.seconds_refinement)
      .add("fairing", report.seconds_fairing);
  json.add("seconds", seconds);
  if (args.has("report"))
    json.add("report", report_json);
  return json;
}

}  // namespace


int runFillHoles(const std::vector<std::string>& raw)
{
  if (takesCloudPath(raw, "fill-holes"))
    return runCloudFillHoles(raw);
  const RepairCommandLine line = parseRepairCommand(raw, commandSpec("fill-holes"), false);
  const Arguments& args = line.args;
  args.needs("absolute", "max-hole-diameter", "it is the one length given in the input's units");
  const auto max_edges = static_cast<std::size_t>(args.getInt("max-hole-edges"));
  const double max_diameter = args.getDouble("max-hole-diameter", std::numeric_limits<double>::infinity());
  const bool quiet = line.quiet;
  const std::string& in_path = line.in_path;
  const std::string& out_path = line.out_path;
  HoleRepairOptions parameters;
  readRepairOptions(args, parameters);
  parameters.constraint_weight = args.getDouble("mu");
  parameters.decision.quad_factor = args.getDouble("hole-factor");
  const std::string surface = args.getWord("surface");
  parameters.hole_settings = surface == "smooth"   ? HoleSettings::Smooth
                             : surface == "relief" ? HoleSettings::Relief
                                                   : HoleSettings::Auto;
  StageTimer timer(quiet);
  const RepairInputs inputs = loadRepairInputs(line, parameters.grid_size, "fill-holes", timer);
  const TriangleMesh& mesh = inputs.mesh;

  timer.start("fill");
  HoleFilling filler;
  filler.setInputMesh(std::make_shared<const TriangleMesh>(mesh));
  filler.setMaxHoleEdges(max_edges);
  double diameter_limit = max_diameter;
  if (std::isfinite(max_diameter) && !args.has("absolute"))
    diameter_limit = UnitCubeNormalization::fromMesh(mesh).invertLength(max_diameter);
  filler.setMaxHoleDiameter(diameter_limit > 0.0 ? diameter_limit : std::numeric_limits<double>::min());
  parameters.filling = filler;
  setPatchSource(parameters, inputs.dictionary, !args.has("no-patches"));
  TriangleMesh filled;
  HoleRepairReport repair;
  fillHolesWithPatches(mesh, filled, parameters, &repair);
  const HoleFilling::Report& report = repair.holes;
  if (repair.used_patches) {
    char line[200];
    std::snprintf(line, sizeof line, "  surface: %s (prediction gain %.2f over a biharmonic fill%s)",
                  repair.relief ? "relief" : "smooth", repair.relief_gain,
                  repair.relief_gain > 0.0 ? "" : ": not measured");
    note(quiet, line);
    note(quiet, patchStageSummary(repair.patches));
  }

  timer.start("write");
  writeMesh(out_path, filled);
  timer.stop();
  const JsonObject report_json = reportIfAsked(inputs.report, mesh, filled, mesh.numFaces(), quiet);

  std::map<std::string, std::size_t> reasons;
  for (const auto& hole : report.holes)
    if (!hole.filled())
      ++reasons[toString(hole.skipped)];

  if (args.has("json")) {
    std::cout << fillHolesJson(args, line, parameters, mesh, filled, repair, reasons, timer, report_json).str() << '\n';
    return 0;
  }
  if (!args.has("quiet")) {
    std::printf("fill-holes %s -> %s: %zu holes found, %zu filled, %zu skipped", in_path.c_str(), out_path.c_str(),
                report.holes_found, report.holes_filled, report.holes_skipped);
    const char* separator = " (";
    for (const auto& [reason, count] : reasons) {
      std::printf("%s%zu %s", separator, count, reason.c_str());
      separator = ", ";
    }
    std::printf("%s; %zu new vertices, %zu new faces%s\n", reasons.empty() ? "" : ")", report.new_vertices,
                report.new_faces, report.fairing_solved ? "" : " (fairing failed: fill left unfaired)");
  }
  return 0;
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
