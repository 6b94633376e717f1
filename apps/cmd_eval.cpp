// `pcl_patchdict eval REF OUT`: how far OUT is from REF, in the metrics of the paper's protocol.
// Lengths are in REF's unit-cube units (largest bbox side = 1) unless --absolute.
#include "cli.h"
#include "options.h"

#include <pcl_patchdict/io/index_io.h>
#include <pcl_patchdict/geometry/metrics.h>
#include <pcl_patchdict/core/normalization.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <numeric>

namespace pcl {
namespace patchdict {
namespace cli {

namespace {

/** The text report of `eval`. */
void printEval(bool absolute, const std::string& ref_path, const std::string& out_path, double rmse,
               std::size_t vertex_count, bool symmetric, const SurfaceDistance& distance)
{
  const char* unit = absolute ? "input units" : "unit-cube units";
  std::printf("eval %s vs %s (%s)\n", out_path.c_str(), ref_path.c_str(), unit);
  if (!std::isnan(rmse))
    std::printf("  vertex RMSE       %.6g over %zu vertices\n", rmse, vertex_count);
  if (symmetric) {
    std::printf("  surface distance  mean %.6g  rms %.6g  Hausdorff %.6g  (%zu samples per side)\n", distance.mean,
                distance.rms, distance.hausdorff, distance.samples_per_side);
    std::printf("  ref -> out        mean %.6g  max %.6g\n", distance.mean_ref_to_out, distance.max_ref_to_out);
  }
  std::printf("  out -> ref        mean %.6g  max %.6g\n", distance.mean_out_to_ref, distance.max_out_to_ref);
  if (symmetric)
    std::printf("  PSNR              %.2f dB (peak = bbox diagonal %.6g)\n", distance.psnr, distance.bbox_diagonal);
}

}  // namespace

int runEval(const std::vector<std::string>& raw)
{
  const Arguments args = readCommandLine(raw, commandSpec("eval"));
  const bool quiet = args.quiet();
  const auto samples = static_cast<std::size_t>(args.getInt("samples"));
  const auto seed = static_cast<std::uint64_t>(args.getInt("seed"));

  StageTimer timer(quiet);
  timer.start("load");
  const std::string ref_path = args.positionals()[0], out_path = args.positionals()[1];
  TriangleMesh ref = loadMesh(ref_path, quiet);
  TriangleMesh out = loadMesh(out_path, quiet);
  if (ref.faces.empty())
    throw Error("reference '" + ref_path + "' has no faces: eval needs a reference surface");
  std::vector<int> indices;
  if (args.has("vertices")) {
    if (out.vertices.size() != ref.vertices.size())
      throw Error("--vertices needs REF and OUT with the same vertex count (" + std::to_string(ref.vertices.size()) +
                  " vs " + std::to_string(out.vertices.size()) + ")");
    indices = readIndexFile(args.get("vertices"), ref.vertices.size());
    if (indices.empty())
      throw Error("index file '" + args.get("vertices") + "' lists no vertices");
  }

  const UnitCubeNormalization normalization = UnitCubeNormalization::fromMesh(ref);
  for (const auto& v : out.vertices)
    if (!v.allFinite())
      throw Error("'" + out_path + "' has a vertex with a non-finite coordinate");
  if (!args.has("absolute")) {
    normalization.apply(ref);
    normalization.apply(out);
  }

  JsonObject json;
  json.add("command", "eval").add("reference", ref_path).add("output", out_path);
  json.add("units", args.has("absolute") ? "input" : "unit-cube");
  json.add("reference_vertices", ref.vertices.size()).add("reference_faces", ref.faces.size());
  json.add("output_vertices", out.vertices.size()).add("output_faces", out.faces.size());

  timer.start("vertex_rmse");
  double rmse = std::nan("");
  if (out.vertices.size() == ref.vertices.size()) {
    rmse = vertexRMSE(ref, out, indices);
    json.add("vertex_rmse", rmse).add("vertex_count", indices.empty() ? ref.vertices.size() : indices.size());
  } else {
    json.addNull("vertex_rmse");
  }

  timer.start("surface_distance");
  SurfaceDistance distance;
  const bool symmetric = !out.faces.empty();
  if (symmetric) {
    distance = surfaceDistance(ref, out, samples, seed);
  } else {
    // A cloud output: the one-way distance of its points to the reference surface.
    const PointSetDistance to_ref = pointsToSurfaceDistance(out.vertices, ref);
    distance.mean_out_to_ref = to_ref.mean;
    distance.rms_out_to_ref = to_ref.rms;
    distance.max_out_to_ref = to_ref.max;
    distance.bbox_diagonal = ref.boundingBoxDiagonal();
  }
  timer.stop();

  JsonObject surface;
  if (symmetric) {
    surface.add("mean", distance.mean).add("rms", distance.rms).add("hausdorff", distance.hausdorff);
    surface.add("mean_ref_to_out", distance.mean_ref_to_out).add("rms_ref_to_out", distance.rms_ref_to_out)
        .add("max_ref_to_out", distance.max_ref_to_out);
  }
  surface.add("mean_out_to_ref", distance.mean_out_to_ref).add("rms_out_to_ref", distance.rms_out_to_ref)
      .add("max_out_to_ref", distance.max_out_to_ref);
  if (symmetric)
    surface.add("samples_per_side", distance.samples_per_side);
  json.add("surface", surface);
  json.add("bbox_diagonal", distance.bbox_diagonal);
  if (symmetric)
    json.add("psnr_db", distance.psnr);
  else
    json.addNull("psnr_db");
  json.add("seconds", timer.json());

  if (args.has("json")) {
    std::cout << json.str() << '\n';
    return 0;
  }
  printEval(args.has("absolute"), ref_path, out_path, rmse, indices.empty() ? ref.vertices.size() : indices.size(), symmetric, distance);
  return 0;
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
