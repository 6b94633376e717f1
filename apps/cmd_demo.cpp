// `pcl_patchdict demo`: the main job on the bundled Stanford bunny, with no arguments. It damages a
// clean copy with a fixed seed — 20 % of the vertices dropped, 6 holes punched, Gaussian noise
// along the normals — and a generated relief with 6 holes, repairs each with the geometric base
// alone and with patches, prints a table of errors and times, and writes the meshes and shaded
// pictures (and a close-up of one relief hole beside its truth, coloured by error) to a folder it
// names.
#include "cli.h"
#include "options.h"
#include "repair_report.h"

#include <pcl_patchdict/geometry/hole_filling.h>
#include <pcl_patchdict_eval/mesh_damage.h>
#include <pcl_patchdict_eval/repair_figure.h>
#include <pcl_patchdict/geometry/mesh_hygiene.h>
#include <pcl_patchdict/geometry/metrics.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict_eval/shapes.h>
#include <pcl_patchdict/repair/patch_repairs.h>

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
  std::string decision{};  ///< a measured patch decision, "applied" or "declined" (--json key_decision)
};

double secondsOf(const std::function<void()>& work)
{
  const auto start = std::chrono::steady_clock::now();
  work();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/** The demo's run: its folder, the clean truth, and the table's rows. */
struct Demo {
  std::string folder;
  bool pictures = true;
  std::uint64_t seed = 1;
  std::string path;  ///< the bundled bunny
  TriangleMesh truth;
  double mean_edge = 0.0;
  std::vector<Row> rows;
  std::vector<int> missing;
  HoledMesh holed;

  std::string file(const std::string& name) const { return (std::filesystem::path(folder) / name).string(); }
};

/** One repair (`run`: options, report), the geometric base alone or with self-similar patches, at
  * the repair's defaults; timed into `row`. */
template <class Options, class Report, class Run>
Report timedRepair(bool patches, Row& row, Run run)
{
  Options options;
  if (!patches)
    options.decision.mode = PatchDecision::Never;
  Report report;
  row.seconds = secondsOf([&] { run(options, report); });
  return report;
}

// 0. The truth: the bunny cleaned, in the unit cube, its scan's own openings closed.
void loadTruth(Demo& demo, bool quiet)
{
  demo.path = findBundledMesh("bunny.obj");
  TriangleMesh truth = loadMesh(demo.path, quiet);
  const MeshCleanupResult cleanup = cleanMesh(truth);
  note(quiet, "  " + cleanup.summary());
  UnitCubeNormalization::fromMesh(truth).apply(truth);
  // The scan's own openings (the bunny has 5, under its base) closed first, so that the truth is
  // watertight and every hole the demo fills is one it punched.
  HoleFilling closing;
  closing.setInputMesh(std::make_shared<const TriangleMesh>(truth));
  closing.setOuterBoundaryFraction(std::numeric_limits<double>::infinity());
  closing.process(demo.truth);
  demo.mean_edge = demo.truth.meanEdgeLength();
}

// 1. Missing vertices: 20 % dropped; their stored positions are garbage (the origin).
void demoMissingVertices(Demo& demo)
{
  demo.missing = pickMissingVertices(demo.truth, 0.2, demo.seed);
  TriangleMesh damaged = demo.truth;
  for (int v : demo.missing)
    damaged.vertices[static_cast<std::size_t>(v)] = Eigen::Vector3d::Zero();
  for (bool patches : {false, true}) {
    TriangleMesh repaired;
    Row row{"missing 20 %", patches ? "bi-Laplacian + patches" : "bi-Laplacian"};
    timedRepair<MissingVerticesOptions, MissingVerticesReport>(patches, row, [&](const auto& options, auto& report) {
      fillMissingVertices(damaged, demo.missing, repaired, options, &report);
    });
    row.error = 1e3 * vertexRMSE(demo.truth, repaired, demo.missing);
    row.key = patches ? "missing_patches" : "missing_bilaplacian";
    demo.rows.push_back(row);
    writeMesh(demo.file(patches ? "missing_patches.ply" : "missing_bilaplacian.ply"), repaired);
  }
}

// 2. Holes, Liepa alone and with patches, scored on the protocol's two measures; the outputs kept
//    for the close-up.
std::vector<TriangleMesh> demoFillHoles(Demo& demo, const std::string& task, const std::string& name,
                                        const std::string& key, const TriangleMesh& clean, const HoledMesh& holed)
{
  writeMesh(demo.file(name + "_input.ply"), holed.mesh);
  if (demo.pictures)
    writeFillPicture(demo.file(name + "_input.png"), holed.mesh, holed.mesh.numFaces(), 600);
  std::vector<TriangleMesh> outputs;
  for (bool patches : {false, true}) {
    TriangleMesh filled;
    Row row{task, patches ? "Liepa + patches" : "Liepa"};
    const HoleRepairReport report = timedRepair<HoleRepairOptions, HoleRepairReport>(
        patches, row, [&](const auto& options, auto& r) { fillHolesWithPatches(holed.mesh, filled, options, &r); });
    if (patches)
      row.method += report.relief ? " (relief found)" : " (smooth)";
    const HoleFillScore score = scoreHoleFill(clean, holed, filled);
    row.error = 1e3 * score.removed_to_output;
    row.second_error = 1e3 * score.new_to_truth;
    row.key = key + (patches ? "_patches" : "_liepa");
    demo.rows.push_back(row);
    const std::string output = name + (patches ? "_patches" : "_liepa");
    writeMesh(demo.file(output + ".ply"), filled);
    if (demo.pictures)
      writeFillPicture(demo.file(output + ".png"), filled, holed.mesh.numFaces(), 600);
    outputs.push_back(std::move(filled));
  }
  return outputs;
}

// The relief's first hole up close: truth | Liepa | Liepa + patches shaded, and the input and both
// fills coloured by their distance to the truth (one scale, one camera).
void demoCloseUp(const Demo& demo, const TriangleMesh& truth, const HoledMesh& holed,
                 const std::vector<TriangleMesh>& outputs, double hole_radius)
{
  if (!demo.pictures || holed.centres.empty() || outputs.size() != 2)
    return;
  const CloseUpWindow window = windowAround(truth, holed.centres.front(), 2.0 * hole_radius);
  const RGBImage figure = comparisonFigure(truth, {"input", &holed.mesh},
                                           {{"Liepa", &outputs[0]}, {"Liepa + patches", &outputs[1]}}, window, 0.0, 360);
  writeImagePNG(demo.file("relief_holes_closeup.png"), figure);
}

// 3. Noise: σ = 0.5 × mean edge along the normals.
void demoDenoise(Demo& demo)
{
  const TriangleMesh noisy = addNormalNoise(demo.truth, 0.5 * demo.mean_edge, demo.seed + 2);
  writeMesh(demo.file("noise_input.ply"), noisy);
  demo.rows.push_back(Row{"noise 0.5 edge", "noisy input", 1e3 * vertexRMSE(demo.truth, noisy), -1.0, 0.0, "noisy"});
  for (bool patches : {false, true}) {
    TriangleMesh denoised;
    Row row{"noise 0.5 edge", patches ? "Taubin + patches" : "Taubin (discrepancy)"};
    const DenoiseReport report = timedRepair<DenoiseOptions, DenoiseReport>(
        patches, row, [&](const auto& options, auto& report) { denoiseWithPatches(noisy, denoised, options, &report); });
    if (patches) {  // the patches go in only when measured to help: the row says what was decided
      row.decision = report.outcome == PatchOutcome::NotRun ? "" : toString(report.outcome);
      row.method += " (" + row.decision + ")";
    }
    row.error = 1e3 * vertexRMSE(demo.truth, denoised);
    row.key = patches ? "denoise_patches" : "denoise_taubin";
    demo.rows.push_back(row);
    writeMesh(demo.file(patches ? "denoise_patches.ply" : "denoise_taubin.ply"), denoised);
  }
}

// 4. The table (or --json).
void printDemo(const Demo& demo, bool json_output, const StageTimer& timer)
{
  if (json_output) {
    JsonObject json;
    json.add("command", "demo").add("input", demo.path).add("vertices", demo.truth.numVertices());
    json.add("faces", demo.truth.numFaces()).add("mean_edge", demo.mean_edge).add("folder", demo.folder);
    json.add("missing_vertices", demo.missing.size()).add("holes", demo.holed.centres.size());
    json.add("removed_vertices", demo.holed.removed.size());
    for (const Row& row : demo.rows) {
      json.add(row.key + "_error", row.error);
      if (row.second_error >= 0.0)
        json.add(row.key + "_new_vertices_error", row.second_error);
      if (!row.decision.empty())
        json.add(row.key + "_decision", row.decision);
    }
    JsonObject seconds = timer.json();
    for (const Row& row : demo.rows)
      seconds.add(row.key, row.seconds);
    json.add("seconds", seconds);
    std::cout << json.str() << '\n';
    return;
  }
  std::printf("pcl_patchdict demo: %s (%zu vertices, mean edge %.4g in the unit cube), seed %llu\n",
              demo.path.c_str(), demo.truth.numVertices(), demo.mean_edge, static_cast<unsigned long long>(demo.seed));
  std::printf("errors x1e-3 of the unit cube: missing = RMSE of the %zu dropped vertices; holes = mean distance of\n"
              "the %zu removed true vertices to the output (new vertices to the truth); noise = vertex RMSE\n\n",
              demo.missing.size(), demo.holed.removed.size());
  std::printf("  %-16s %-34s %10s %12s %9s\n", "task", "method", "error", "(new verts)", "seconds");
  for (const Row& row : demo.rows) {
    char second[32] = "";
    if (row.second_error >= 0.0)
      std::snprintf(second, sizeof second, "%.4f", row.second_error);
    std::printf("  %-16s %-34s %10.4f %12s %9.2f\n", row.task.c_str(), row.method.c_str(), row.error, second,
                row.seconds);
  }
  std::printf("\nmeshes%s in %s/\n", demo.pictures ? " and pictures" : "", demo.folder.c_str());
}

}  // namespace

int runDemo(const std::vector<std::string>& raw)
{
  const Arguments args = readCommandLine(raw, commandSpec("demo"));
  const bool quiet = args.quiet();
  Demo demo;
  demo.seed = static_cast<std::uint64_t>(args.getInt("seed"));
  demo.folder = args.get("output");
  demo.pictures = !args.has("no-pictures");

  StageTimer timer(quiet);
  timer.start("load");
  loadTruth(demo, quiet);
  makeFolder(demo.folder, "demo");
  writeMesh(demo.file("truth.ply"), demo.truth);

  timer.start("missing_vertices");
  demoMissingVertices(demo);
  timer.start("holes");  // 6 of radius 0.035 (the protocol's largest)
  demo.holed = punchHoles(demo.truth, 6, 0.035, demo.seed + 1);
  demoFillHoles(demo, "holes r 0.035", "holes", "holes", demo.truth, demo.holed);
  // The same on a relief, where a smooth fill has nothing to go on and patches copy the pattern: a
  // sinusoidal relief (period 0.1, amplitude 0.02) with 6 holes of radius 0.04.
  timer.start("relief_holes");
  const TriangleMesh relief = makeSinusoidalRelief(100, 100, 0.02, 0.1);
  writeMesh(demo.file("relief_truth.ply"), relief);
  const HoledMesh relief_holed = punchHoles(relief, 6, 0.04, demo.seed + 3);
  demoCloseUp(demo, relief, relief_holed,
              demoFillHoles(demo, "relief holes", "relief_holes", "relief", relief, relief_holed), 0.04);
  timer.start("denoise");
  demoDenoise(demo);
  timer.stop();

  printDemo(demo, args.has("json"), timer);
  return 0;
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
