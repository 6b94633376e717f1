// hole_size_sweep: the error of a hole fill against the hole's size (the paper's Fig. 8a), Liepa
// beside the patches. For each mesh (unit-cube normalised) and hole radius, 6 seeded holes are
// punched (mesh_damage.h) and filled by Liepa alone and with patches (the defaults: the relief
// check decides the settings); printed as CSV on stdout.
//
// With --quad-length L the patch side is fixed (patch_scale × L, --patch-scale F, default 1) for
// every radius, as in the paper's Fig. 8a (side 0.062); without it the side follows the holes.
//
// usage: hole_size_sweep MESH... [--radii 0.01,0.02,...] [--seed S] [--quad-length L [--patch-scale F]]
// columns: mesh, radius, removed vertices, relief (0/1), prediction gain, patch side, hole
// diameter / patch side, Liepa removed→out, patches removed→out, Liepa new→GT, patches new→GT,
// ratio removed→out (patches / Liepa).
#include <pcl_patchdict_eval/mesh_damage.h>
#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/repair/patch_repairs.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

using namespace pcl::patchdict;

int main(int argc, char** argv)
{
  std::vector<std::string> meshes;
  std::vector<double> radii{0.01, 0.02, 0.035, 0.05, 0.07};
  std::uint64_t seed = 1;
  double quad_length = 0.0, patch_scale = 1.0;
  const char* usage = "usage: hole_size_sweep MESH... [--radii R1,R2,...] [--seed S] [--quad-length L [--patch-scale F]]\n";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--radii" && i + 1 < argc) {
      radii.clear();
      std::stringstream list(argv[++i]);
      for (std::string item; std::getline(list, item, ',');)
        radii.push_back(std::atof(item.c_str()));
    } else if (a == "--seed" && i + 1 < argc) {
      seed = std::strtoull(argv[++i], nullptr, 10);
    } else if (a == "--quad-length" && i + 1 < argc) {
      quad_length = std::atof(argv[++i]);
    } else if (a == "--patch-scale" && i + 1 < argc) {
      patch_scale = std::atof(argv[++i]);
    } else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "%s", usage);
      return 2;
    } else {
      meshes.push_back(a);
    }
  }
  if (meshes.empty() || radii.empty() || !(quad_length >= 0.0) || !(patch_scale > 0.0)) {
    std::fprintf(stderr, "%s", usage);
    return 2;
  }
  try {
    std::printf("mesh,radius,removed,relief,gain,patch_side,diameter_over_side,liepa_removed,patch_removed,"
                "liepa_new,patch_new,ratio_removed\n");
    for (const std::string& path : meshes) {
      TriangleMesh truth;
      readMesh(path, truth);
      UnitCubeNormalization::fromMesh(truth).apply(truth);
      const std::string name = std::filesystem::path(path).stem().string();
      for (double radius : radii) {
        const HoledMesh holed = punchHoles(truth, 6, radius, seed);
        double error[2] = {0.0, 0.0}, added_error[2] = {0.0, 0.0};
        HoleRepairReport report;
        for (int patches = 0; patches < 2; ++patches) {
          HoleRepairOptions options;
          options.filling.setMaxHoleDiameter(6.0 * radius);  // the punched holes, not the scan's own openings
          options.quad_length = quad_length;
          if (quad_length > 0.0)
            options.patch_scale = patch_scale;
          options.decision.mode = patches == 1 ? PatchDecision::Auto : PatchDecision::Never;
          TriangleMesh out;
          fillHolesWithPatches(holed.mesh, out, options, &report);
          const HoleFillScore score = scoreHoleFill(truth, holed, out);
          error[patches] = score.removed_to_output;
          added_error[patches] = score.new_to_truth;
        }
        const double side = report.patches.patch_side;
        std::printf("%s,%.3f,%zu,%d,%.3f,%.4f,%.3f,%.6g,%.6g,%.6g,%.6g,%.4f\n", name.c_str(), radius,
                    holed.removed.size(), report.relief ? 1 : 0, report.relief_gain, side,
                    side > 0.0 ? 2.0 * radius / side : 0.0, error[0], error[1], added_error[0], added_error[1],
                    error[0] > 0.0 ? error[1] / error[0] : 0.0);
        std::fflush(stdout);
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hole_size_sweep: %s\n", e.what());
    return 1;
  }
  return 0;
}
