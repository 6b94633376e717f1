// `pcl_patchdict demo`: the main job on the bundled Stanford bunny, with no arguments. It damages a
// clean copy with a fixed seed — 20 % of the vertices dropped, 6 holes punched, Gaussian noise
// along the normals — and a generated relief with 6 holes, repairs each with the geometric base
// alone and with patches, prints a table of errors and times, and writes the meshes and pictures
// to a folder it names.
#include "cli.h"
#include "repair_report.h"

#include <pcl_patchdict/geometry/hole_filling.h>
#include <pcl_patchdict/eval/mesh_damage.h>
#include <pcl_patchdict/geometry/mesh_hygiene.h>
#include <pcl_patchdict/geometry/metrics.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/eval/shapes.h>
#include <pcl_patchdict/repair/sparse_patch_inpainter.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <limits>

namespace pcl {
namespace patchdict {
namespace cli {

namespace {

// The bundled data: $PCL_PATCHDICT_DATA, the source tree, the install prefix, or beside the binary.
std::string findBundledMesh(const std::string& name)
{
  namespace fs = std::filesystem;
  std::vector<fs::path> candidates;
  if (const char* env = std::getenv("PCL_PATCHDICT_DATA"))
    candidates.emplace_back(env);
  candidates.emplace_back(PCL_PATCHDICT_DATA_DIR);
  candidates.emplace_back(PCL_PATCHDICT_INSTALLED_DATA_DIR);
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (!ec)
    candidates.push_back(self.parent_path().parent_path() / "share" / "pcl_patchdict");
  for (const auto& directory : candidates)
    if (fs::exists(directory / name, ec))
      return (directory / name).string();
  throw Error("bundled mesh '" + name + "' not found (set PCL_PATCHDICT_DATA to the project's data/ directory)");
}

/** One row of the demo's table. */
struct Row {
  std::string task, method;
  double error = 0.0, second_error = -1.0;  // ×1e-3 of the unit cube
  double seconds = 0.0;
  std::string key{};  ///< name in --json (key_error, key_new_vertices_error, seconds.key)
};

double secondsOf(const std::function<void()>& work)
{
  const auto start = std::chrono::steady_clock::now();
  work();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int runDemo(const std::vector<std::string>& raw)
{
  auto value_options = commonValueOptions();
  value_options.insert("out");
  auto flag_options = commonFlagOptions();
  flag_options.insert("no-pictures");
  const Arguments args(raw, value_options, flag_options);
  args.expectPositionals(0, 0, "pcl_patchdict demo [--out DIR] [--seed X] [--no-pictures] [--json]");
  applyCommonOptions(args);
  const bool quiet = args.has("quiet") || args.has("json");
  const auto seed = static_cast<std::uint64_t>(args.getInt("seed", 1, 0, (1LL << 62)));
  const std::string out_dir = args.get("out", "pcl_patchdict_demo");
  const bool pictures = !args.has("no-pictures");

  StageTimer timer(quiet);
  timer.start("load");
  const std::string path = findBundledMesh("bunny.obj");
  TriangleMesh truth = loadMesh(path, quiet);
  const MeshCleanupResult cleanup = cleanMesh(truth);
  note(quiet, "  " + cleanup.summary());
  UnitCubeNormalization::fromMesh(truth).apply(truth);
  {
    // The scan's own openings (the bunny has 5, under its base) closed first, so that the truth is
    // watertight and every hole the demo fills is one it punched.
    HoleFilling closing;
    closing.setInputMesh(std::make_shared<const TriangleMesh>(truth));
    closing.setOuterBoundaryFraction(std::numeric_limits<double>::infinity());
    TriangleMesh closed;
    closing.process(closed);
    truth = std::move(closed);
  }
  const double mean_edge = truth.meanEdgeLength();
  makeFolder(out_dir, "demo");
  const auto file = [&](const std::string& name) { return (std::filesystem::path(out_dir) / name).string(); };
  writeMesh(file("truth.ply"), truth);
  std::vector<Row> rows;

  // Each repair twice: the geometric base alone, then with patches (self-similar, mode defaults).
  const auto repair = [](SparsePatchInpainter::Mode mode, const TriangleMesh& input, bool patches,
                         const std::vector<int>& missing, TriangleMesh& out, Row& row) {
    SparsePatchInpainter inpainter(mode);
    inpainter.setInputMesh(std::make_shared<const TriangleMesh>(input));
    if (!missing.empty())
      inpainter.setMissingVertices(missing);
    inpainter.setUsePatches(patches);
    inpainter.setParameters(SparsePatchInpainter::defaultParameters(mode));
    SparsePatchInpainter::Report report;
    row.seconds = secondsOf([&] { inpainter.process(out, &report); });
    return report;
  };

  // 1. Missing vertices: 20 % dropped; their stored positions are garbage (the origin).
  timer.start("missing_vertices");
  const std::vector<int> missing = pickMissingVertices(truth, 0.2, seed);
  TriangleMesh damaged = truth;
  for (int v : missing)
    damaged.vertices[static_cast<std::size_t>(v)] = Eigen::Vector3d::Zero();
  for (bool patches : {false, true}) {
    TriangleMesh repaired;
    Row row{"missing 20 %", patches ? "bi-Laplacian + patches" : "bi-Laplacian"};
    repair(SparsePatchInpainter::Mode::MissingVertices, damaged, patches, missing, repaired, row);
    row.error = 1e3 * vertexRMSE(truth, repaired, missing);
    row.key = patches ? "missing_patches" : "missing_bilaplacian";
    rows.push_back(row);
    writeMesh(file(patches ? "missing_patches.ply" : "missing_bilaplacian.ply"), repaired);
  }

  // 2. Holes, Liepa alone and with patches, scored on the protocol's two measures.
  const auto fill_holes = [&](const std::string& task, const std::string& name, const std::string& key,
                              const TriangleMesh& clean, const HoledMesh& holed) {
    writeMesh(file(name + "_input.ply"), holed.mesh);
    if (pictures)
      writeFillPicture(file(name + "_input.png"), holed.mesh, holed.mesh.numFaces(), 600);
    for (bool patches : {false, true}) {
      TriangleMesh filled;
      Row row{task, patches ? "Liepa + patches" : "Liepa"};
      const SparsePatchInpainter::Report report =
          repair(SparsePatchInpainter::Mode::Holes, holed.mesh, patches, {}, filled, row);
      if (patches)
        row.method += report.relief ? " (relief found)" : " (smooth)";
      const HoleFillScore score = scoreHoleFill(clean, holed, filled);
      row.error = 1e3 * score.removed_to_output;
      row.second_error = 1e3 * score.new_to_truth;
      row.key = key + (patches ? "_patches" : "_liepa");
      rows.push_back(row);
      const std::string output = name + (patches ? "_patches" : "_liepa");
      writeMesh(file(output + ".ply"), filled);
      if (pictures)
        writeFillPicture(file(output + ".png"), filled, holed.mesh.numFaces(), 600);
    }
  };
  timer.start("holes");  // 6 of radius 0.035 (the protocol's largest)
  const HoledMesh holed = punchHoles(truth, 6, 0.035, seed + 1);
  fill_holes("holes r 0.035", "holes", "holes", truth, holed);
  // The same on a relief, where a smooth fill has nothing to go on and patches copy the pattern: a
  // sinusoidal relief (period 0.1, amplitude 0.02) with 6 holes of radius 0.04.
  timer.start("relief_holes");
  const TriangleMesh relief = makeSinusoidalRelief(100, 100, 0.02, 0.1);
  writeMesh(file("relief_truth.ply"), relief);
  fill_holes("relief holes", "relief_holes", "relief", relief, punchHoles(relief, 6, 0.04, seed + 3));

  // 3. Noise: σ = 0.5 × mean edge along the normals.
  timer.start("denoise");
  const TriangleMesh noisy = addNormalNoise(truth, 0.5 * mean_edge, seed + 2);
  writeMesh(file("noise_input.ply"), noisy);
  rows.push_back(Row{"noise 0.5 edge", "noisy input", 1e3 * vertexRMSE(truth, noisy), -1.0, 0.0, "noisy"});
  for (bool patches : {false, true}) {
    TriangleMesh denoised;
    Row row{"noise 0.5 edge", patches ? "Taubin + self-similar patches" : "Taubin (discrepancy)"};
    repair(SparsePatchInpainter::Mode::Denoise, noisy, patches, {}, denoised, row);
    row.error = 1e3 * vertexRMSE(truth, denoised);
    row.key = patches ? "denoise_patches" : "denoise_taubin";
    rows.push_back(row);
    writeMesh(file(patches ? "denoise_patches.ply" : "denoise_taubin.ply"), denoised);
  }
  timer.stop();

  if (args.has("json")) {
    JsonObject json;
    json.add("command", "demo").add("input", path).add("vertices", truth.numVertices());
    json.add("faces", truth.numFaces()).add("mean_edge", mean_edge).add("folder", out_dir);
    json.add("missing_vertices", missing.size()).add("holes", holed.centres.size());
    json.add("removed_vertices", holed.removed.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const std::string& key = rows[i].key;
      json.add(key + "_error", rows[i].error);
      if (rows[i].second_error >= 0.0)
        json.add(key + "_new_vertices_error", rows[i].second_error);
    }
    JsonObject seconds = timer.json();
    for (std::size_t i = 0; i < rows.size(); ++i)
      seconds.add(rows[i].key, rows[i].seconds);
    json.add("seconds", seconds);
    std::cout << json.str() << '\n';
    return 0;
  }
  std::printf("pcl_patchdict demo: %s (%zu vertices, mean edge %.4g in the unit cube), seed %llu\n",
              path.c_str(), truth.numVertices(), mean_edge, static_cast<unsigned long long>(seed));
  std::printf("errors x1e-3 of the unit cube: missing = RMSE of the %zu dropped vertices; holes = mean distance of\n"
              "the %zu removed true vertices to the output (new vertices to the truth); noise = vertex RMSE\n\n",
              missing.size(), holed.removed.size());
  std::printf("  %-16s %-34s %10s %12s %9s\n", "task", "method", "error", "(new verts)", "seconds");
  for (const Row& row : rows) {
    char second[32] = "";
    if (row.second_error >= 0.0)
      std::snprintf(second, sizeof second, "%.4f", row.second_error);
    std::printf("  %-16s %-34s %10.4f %12s %9.2f\n", row.task.c_str(), row.method.c_str(), row.error, second,
                row.seconds);
  }
  std::printf("\nmeshes%s in %s/\n", pictures ? " and pictures" : "", out_dir.c_str());
  return 0;
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
