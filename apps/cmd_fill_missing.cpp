// `pcl_patchdict fill-missing IN --missing IDX.txt [--dict DICT.pdd | --no-patches] -o OUT`: recovers
// the positions of missing vertices (connectivity known) — bi-Laplacian base + patch correction.
#include "cli.h"
#include "options.h"
#include "repair_options.h"

#include <pcl_patchdict/io/index_io.h>
#include <pcl_patchdict/coding/patch_dictionary.h>
#include <pcl_patchdict/repair/patch_repairs.h>

#include <cstdio>
#include <iostream>

namespace pcl {
namespace patchdict {
namespace cli {

int runFillMissing(const std::vector<std::string>& raw)
{
  const RepairCommandLine line = parseRepairCommand(raw, commandSpec("fill-missing"), true);
  const Arguments& args = line.args;
  const bool quiet = line.quiet;
  const std::string& in_path = line.in_path;
  const std::string& out_path = line.out_path;
  MissingVerticesOptions parameters;
  readRepairOptions(args, parameters);
  parameters.constraint_weight = args.getDouble("mu");
  StageTimer timer(quiet);
  const RepairInputs inputs = loadRepairInputs(line, parameters.grid_size, "fill-missing", timer);
  const TriangleMesh& mesh = inputs.mesh;
  const std::vector<int> missing = readIndexFile(args.get("missing"), mesh.numVertices());

  timer.start("fill");
  setPatchSource(parameters, inputs.dictionary, !args.has("no-patches"));
  TriangleMesh repaired;
  MissingVerticesReport report;
  fillMissingVertices(mesh, missing, repaired, parameters, &report);

  timer.start("write");
  writeMesh(out_path, repaired);
  timer.stop();
  const JsonObject report_json = reportIfAsked(inputs.report, mesh, repaired, repaired.numFaces(), quiet);

  const std::string dictionary_kind = dictionaryKind(args);
  if (report.used_patches)
    note(quiet, patchStageSummary(report.patches));
  if (args.has("json")) {
    JsonObject json;
    json.add("command", "fill-missing").add("input", in_path).add("output", out_path);
    json.add("vertices", mesh.numVertices()).add("faces", mesh.numFaces());
    json.add("missing_vertices", report.missing_vertices).add("isolated_missing", report.isolated_missing);
    json.add("patches", report.used_patches).add("dictionary", dictionary_kind);
    if (report.used_patches) {
      json.add("patch_stage", patchStageJson(report.patches));
      json.add("sparsity", parameters.sparsity).add("mu", parameters.constraint_weight);
      json.add("mean_correction", report.mean_correction);
    }
    json.add("repair_stages", repairStagesJson(report)).add("seconds", timer.json());
    if (args.has("report"))
      json.add("report", report_json);
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
