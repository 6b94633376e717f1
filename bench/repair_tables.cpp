// repair_tables: the issue-7 tables in one command. For each mesh (unit-cube normalised), seeded
// cases on the protocol of DESIGN.md — 20 % and 50 % of the vertices missing, 12 holes of radius
// 0.035, Gaussian noise of 0.5 × mean edge along the normals — repaired with the geometric base
// alone and with patches, scored with the library's metrics, printed as Markdown.
//
// usage: repair_tables MESH... [--dict D.pdd] [--seed S]
//   --dict: also run holes and missing vertices with this (global) dictionary; without it the
//   patches use a self-similar dictionary learned from the intact part of each damaged mesh.
// The cases are this program's own (mesh_damage.h), not the harness's: figures differ from
// ../shared/harness/BASELINES.md by the draw of the damage, not by the protocol.
#include <pcl_patchdict/mesh_damage.h>
#include <pcl_patchdict/mesh_io.h>
#include <pcl_patchdict/metrics.h>
#include <pcl_patchdict/normalization.h>
#include <pcl_patchdict/sparse_patch_inpainter.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

using namespace pcl::patchdict;

namespace {

double now()
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

struct Result {
  double error = 0.0, second = 0.0, seconds = 0.0;
};

Result missingCase(const TriangleMesh& truth, const std::vector<int>& missing, bool patches,
                   const PatchDictionary::ConstPtr& dictionary)
{
  TriangleMesh damaged = truth;
  for (int v : missing)
    damaged.vertices[static_cast<std::size_t>(v)] = Eigen::Vector3d::Zero();
  SparsePatchInpainter inpainter;
  inpainter.setMode(SparsePatchInpainter::Mode::MissingVertices);
  inpainter.setParameters(SparsePatchInpainter::defaultParameters(SparsePatchInpainter::Mode::MissingVertices));
  inpainter.setInputMesh(damaged);
  inpainter.setMissingVertices(missing);
  inpainter.setUsePatches(patches);
  inpainter.setDictionary(dictionary);
  TriangleMesh out;
  const double start = now();
  inpainter.process(out);
  return {1e3 * vertexRMSE(truth, out, missing), 0.0, now() - start};
}

Result holesCase(const TriangleMesh& truth, const HoledMesh& holed, bool patches,
                 const PatchDictionary::ConstPtr& dictionary)
{
  SparsePatchInpainter inpainter;
  inpainter.setMode(SparsePatchInpainter::Mode::Holes);
  inpainter.setInputMesh(holed.mesh);
  HoleFilling filling;
  filling.setMaxHoleDiameter(0.15);  // the scans' own openings stay open, as in the harness protocol
  inpainter.setHoleFilling(filling);
  inpainter.setParameters(SparsePatchInpainter::defaultParameters(SparsePatchInpainter::Mode::Holes));
  inpainter.setUsePatches(patches);
  inpainter.setDictionary(dictionary);
  TriangleMesh out;
  const double start = now();
  inpainter.process(out);
  const double seconds = now() - start;
  const HoleFillScore score = scoreHoleFill(truth, holed, out);
  return {1e3 * score.removed_to_output, 1e3 * score.new_to_truth, seconds};
}

Result denoiseCase(const TriangleMesh& truth, const TriangleMesh& noisy, bool patches)
{
  SparsePatchInpainter inpainter;
  inpainter.setMode(SparsePatchInpainter::Mode::Denoise);
  inpainter.setInputMesh(noisy);
  inpainter.setParameters(SparsePatchInpainter::defaultParameters(SparsePatchInpainter::Mode::Denoise));
  inpainter.setUsePatches(patches);
  TriangleMesh out;
  const double start = now();
  inpainter.process(out);
  return {1e3 * vertexRMSE(truth, out), 0.0, now() - start};
}

}  // namespace

int main(int argc, char** argv)
{
  std::vector<std::string> meshes;
  std::string dictionary_path;
  std::uint64_t seed = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--dict" && i + 1 < argc)
      dictionary_path = argv[++i];
    else if (a == "--seed" && i + 1 < argc)
      seed = std::strtoull(argv[++i], nullptr, 10);
    else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "usage: repair_tables MESH... [--dict D.pdd] [--seed S]\n");
      return 2;
    } else
      meshes.push_back(a);
  }
  if (meshes.empty()) {
    std::fprintf(stderr, "usage: repair_tables MESH... [--dict D.pdd] [--seed S]\n");
    return 2;
  }
  try {
    PatchDictionary::ConstPtr global;
    if (!dictionary_path.empty())
      global = PatchDictionary::load(dictionary_path);
    const std::string dict_columns = global ? " | global dictionary" : "";
    std::printf("Errors ×1e-3 of the unit cube; seconds in parentheses. Seed %llu.\n\n",
                static_cast<unsigned long long>(seed));
    std::string missing_table = "| mesh | missing | bi-Laplacian | + self-similar patches" + dict_columns +
                                " |\n|---|---|---|---|" + (global ? "---|" : "") + "\n";
    std::string holes_table = "| mesh | removed V | Liepa: removed→out / new→GT | + self-similar patches" +
                              dict_columns + " |\n|---|---|---|---|" + (global ? "---|" : "") + "\n";
    std::string noise_table = "| mesh | noisy | Taubin base | + self-similar patches |\n|---|---|---|---|\n";
    char cell[160];
    for (const std::string& path : meshes) {
      TriangleMesh truth;
      readMesh(path, truth);
      UnitCubeNormalization::fromMesh(truth).apply(truth);
      const std::string name = std::filesystem::path(path).stem().string();
      std::fprintf(stderr, "%s: %zu vertices\n", name.c_str(), truth.numVertices());
      for (double fraction : {0.2, 0.5}) {
        const std::vector<int> missing = pickMissingVertices(truth, fraction, seed);
        const Result base = missingCase(truth, missing, false, nullptr);
        const Result self = missingCase(truth, missing, true, nullptr);
        std::snprintf(cell, sizeof cell, "| %s | %.0f %% | %.4f (%.2f) | %.4f (%.1f) |", name.c_str(), 100 * fraction,
                      base.error, base.seconds, self.error, self.seconds);
        missing_table += cell;
        if (global) {
          const Result g = missingCase(truth, missing, true, global);
          std::snprintf(cell, sizeof cell, " %.4f (%.1f) |", g.error, g.seconds);
          missing_table += cell;
        }
        missing_table += "\n";
      }
      const HoledMesh holed = punchHoles(truth, 12, 0.035, seed + 1);
      const Result liepa = holesCase(truth, holed, false, nullptr);
      const Result self = holesCase(truth, holed, true, nullptr);
      std::snprintf(cell, sizeof cell, "| %s | %zu | %.3f / %.3f (%.2f) | %.3f / %.3f (%.1f) |", name.c_str(),
                    holed.removed.size(), liepa.error, liepa.second, liepa.seconds, self.error, self.second,
                    self.seconds);
      holes_table += cell;
      if (global) {
        const Result g = holesCase(truth, holed, true, global);
        std::snprintf(cell, sizeof cell, " %.3f / %.3f (%.1f) |", g.error, g.second, g.seconds);
        holes_table += cell;
      }
      holes_table += "\n";
      const TriangleMesh noisy = addNormalNoise(truth, 0.5 * truth.meanEdgeLength(), seed + 2);
      const Result taubin = denoiseCase(truth, noisy, false);
      const Result patched = denoiseCase(truth, noisy, true);
      std::snprintf(cell, sizeof cell, "| %s | %.3f | %.3f (%.2f) | %.3f (%.1f) |\n", name.c_str(),
                    1e3 * vertexRMSE(truth, noisy), taubin.error, taubin.seconds, patched.error, patched.seconds);
      noise_table += cell;
    }
    std::printf("Missing vertices (RMSE over the missing ones):\n\n%s\n", missing_table.c_str());
    std::printf("Holes, 12 of radius 0.035 (mean distances):\n\n%s\n", holes_table.c_str());
    std::printf("Noise 0.5 × mean edge along the normals (vertex RMSE):\n\n%s", noise_table.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "repair_tables: %s\n", e.what());
    return 1;
  }
  return 0;
}
