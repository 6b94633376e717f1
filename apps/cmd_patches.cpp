// `pcl_patchdict patches IN -o X.pds`: the height-map patch set of a surface (section 3.2 of the
// paper), in the input's unit-cube units, with an optional PNG contact sheet.
#include <pcl_patchdict/io/patch_set_io.h>
#include "cli.h"
#include "options.h"
#include "surface_patches.h"


#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>

namespace pcl {
namespace patchdict {
namespace cli {

namespace {

constexpr std::size_t kSheetPatches = 400;  // a contact sheet of every patch would be gigapixels

JsonObject normalisationJson(const SurfacePatches& surface)
{
  JsonObject json;
  json.add("center_x", surface.center.x()).add("center_y", surface.center.y());
  json.add("center_z", surface.center.z()).add("scale", surface.scale);
  return json;
}

}  // namespace

int runPatches(const std::vector<std::string>& raw)
{
  const Arguments args = readCommandLine(raw, commandSpec("patches"));
  const bool quiet = args.quiet();
  SurfacePatchOptions options;
  options.grid_size = static_cast<int>(args.getInt("grid"));
  options.quad_length = args.getDouble("quad-length");
  options.overlap = static_cast<int>(args.getInt("overlap"));
  options.placement = parseSeedPlacement(args.getWord("placement"));
  options.seed = static_cast<std::uint64_t>(args.getInt("seed"));
  const std::string input = args.positionals()[0], output = args.get("output"), png = args.get("png");
  checkOutputPath(output, input);
  checkOutputPath(png, input);
  if (!png.empty() && sameFile(png, output))
    throw UsageError("--png and -o name the same file");

  StageTimer timer(quiet);
  const SurfacePatches surface = surfacePatches(input, options, quiet, &timer);
  const PatchSet& patches = surface.patches;
  const bool is_cloud = surface.is_cloud;
  note(quiet, "  " + std::to_string(patches.numPatches()) + " patches of " + std::to_string(options.grid_size) + "×" +
                  std::to_string(options.grid_size) + " bins, " +
                  std::to_string(static_cast<int>(100.0 * patches.observedFraction() + 0.5)) + " % observed");
  timer.start("save");
  savePatchSet(output, patches);
  if (!png.empty())
    savePatchSetPNG(png, patches, 20, 4, kSheetPatches);
  timer.stop();

  if (args.has("json")) {
    JsonObject json;
    json.add("command", "patches").add("input", input).add("output", output);
    json.add("input_kind", is_cloud ? "cloud" : "mesh").add("vertices", surface.vertices);
    json.add("faces", surface.faces);
    if (is_cloud)
      json.add("poisson_depth", surface.poisson_depth).add("coarse_faces", surface.coarse_faces);
    json.add("patches", patches.numPatches()).add("grid_size", options.grid_size);
    json.add("quad_length", options.quad_length);
    json.add("radius", patches.radius).add("overlap", options.overlap).add("placement", args.getWord("placement"));
    json.add("observed_fraction", patches.observedFraction());
    json.add("units", "unit-cube").add("normalisation", normalisationJson(surface));
    if (!png.empty())
      json.add("png", png).add("png_patches", std::min(patches.numPatches(), kSheetPatches));
    json.add("seconds", timer.json());
    std::cout << json.str() << '\n';
  } else if (!quiet) {
    std::printf("%zu patches (%d×%d, side %.4g in unit-cube units, %.1f %% of bins observed) -> %s\n",
                patches.numPatches(), options.grid_size, options.grid_size, options.quad_length,
                100.0 * patches.observedFraction(), output.c_str());
  }
  return 0;
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
