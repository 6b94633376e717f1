// pcl_patchdict — one tool, many subcommands (see `pcl_patchdict help`). Every failure is one line
// on stderr and a non-zero exit: 1 for bad input or a failed run, 2 for a malformed command line.
#include "cli.h"

#include <pcl_patchdict/io/atomic_file.h>

#include <cstdio>
#include <exception>
#include <functional>
#include <iostream>
#include <map>
#include <new>

namespace cli = pcl::patchdict::cli;

namespace {

struct Subcommand {
  std::function<int(const std::vector<std::string>&)> run;
  const char* synopsis;
  const char* what;
};

const std::vector<std::pair<std::string, Subcommand>>& subcommands()
{
  static const std::vector<std::pair<std::string, Subcommand>> table{
      {"demo", {cli::runDemo, "demo [--out DIR] [--seed X] [--no-pictures] [--json]",
                "the main job: the bundled bunny and a generated relief damaged, repaired with and without patches"}},
      {"info", {cli::runInfo, "info IN [--json]", "statistics and hygiene report of a mesh or cloud"}},
      {"eval", {cli::runEval, "eval REF OUT [--vertices IDX.txt] [--samples N] [--absolute] [--json]",
                "vertex RMSE, symmetric surface distance, Hausdorff and PSNR of OUT against REF"}},
      {"quads", {cli::runQuads,
                 "quads IN -o QUADS.obj [--quad-length L] [--overlap K] [--frames FRAMES.ply] [--coarse COARSE.ply] "
                 "[--json]",
                 "coarse shape, field-aligned quad mesh, and the seeds with their frames"}},
      {"patches", {cli::runPatches,
                   "patches IN -o PATCHES.pds [--png SHEET.png] [--grid N] [--quad-length L] [--overlap K] [--json]",
                   "height-map patch set (unit-cube units)"}},
      {"learn", {cli::runLearn,
                 "learn INPUT... -o DICT.pdd [--method ksvd|online] [--atoms K] [--sparsity S] [--iterations T] "
                 "[--batch B] [--buffer N] [--grid N] [--quad-length L] [--overlap K] [--skip-bad] "
                 "[--checkpoint FILE.pdk [--checkpoint-every N] [--stop-after N]] [--resume FILE.pdk] "
                 "[--remove-mean] [--png ATOMS.png] [--json]",
                 "learn a patch dictionary from .pds files, meshes, clouds, folders, globs or @lists (one input: "
                 "K-SVD, local; several: online, streamed, resumable)"}},
      {"reconstruct", {cli::runReconstruct,
                       "reconstruct IN -o OUT [--dict DICT.pdd [--sparsity S]] [--rule bilinear|bin-centres] [--json]",
                       "surface -> patches -> surface round trip (identity, or through a dictionary), scored"}},
      {"compress", {cli::runCompress,
                    "compress IN --dict DICT.pdd -o OUT.pdc [--quad-length L] [--patch-scale F] [--coefficients S] "
                    "[--coefficient-bits B] [--position-bits B] [--overlap K] [--subdivision N] [--smooth-iterations T] "
                    "[--keep-connectivity [--location-bits B]] [--no-projection] [--samples N] [--no-eval] [--json]",
                    "compress as quad mesh + sparse codes (.pdc); reports bytes per part and PSNR"}},
      {"decompress", {cli::runDecompress, "decompress IN.pdc --dict DICT.pdd -o OUT [--ref REF [--samples N]] [--json]",
                      "decode a .pdc file (with the dictionary it was encoded with)"}},
      {"denoise", {cli::runDenoise, "denoise IN [--dict DICT.pdd | --self-similar | --no-patches] -o OUT [--noise S] [--report DIR [--ref REF]] [--json]",
                   "denoise: Taubin smoothing (iterations by the discrepancy principle); with --dict or --self-similar, corrected by patches"}},
      {"inpaint", {cli::runInpaint, "inpaint IN --missing IDX.txt [--dict DICT.pdd | --no-patches] -o OUT [--quad-length L] [--report DIR [--ref REF]] [--json]",
                   "recover missing vertices"}},
      {"fill-holes", {cli::runFillHoles, "fill-holes IN [--dict DICT.pdd | --no-patches] -o OUT [--surface auto|smooth|relief] [--max-hole-edges E] [--max-hole-diameter D] [--absolute] [--report DIR [--ref REF]] [--json]",
                      "fill holes: Liepa's triangulate-refine-fair, new vertices corrected by patches"}},
  };
  return table;
}

}  // namespace

int cli::runHelp(const std::vector<std::string>&)
{
  std::cout << "pcl_patchdict — repair and compress 3D surfaces with learned dictionaries of height-map patches\n\n"
               "usage: pcl_patchdict COMMAND [ARGS] [OPTIONS]\n\ncommands:\n";
  for (const auto& [name, command] : subcommands())
    std::printf("  %s\n      %s\n", command.synopsis, command.what);
  std::cout << "  help\n      this text\n\n"
               "common options: --threads T, --seed X, --json (one JSON object on stdout), --quiet (no progress on stderr)\n"
               "formats: PLY (ascii/binary), OBJ, OFF, STL meshes; PCD and face-less PLY clouds\n";
  return 0;
}

int main(int argc, char** argv)
{
  pcl::patchdict::removeTemporaryFilesOnInterrupt();
  const std::vector<std::string> all(argv + 1, argv + argc);
  if (all.empty() || all[0] == "help" || all[0] == "--help" || all[0] == "-h")
    return cli::runHelp({});
  const std::string name = all[0];
  const std::vector<std::string> args(all.begin() + 1, all.end());
  try {
    for (const auto& [command_name, command] : subcommands()) {
      if (command_name != name)
        continue;
      return command.run(args);
    }
    std::cerr << "pcl_patchdict: unknown command '" << name << "' (see 'pcl_patchdict help')\n";
    return 2;
  } catch (const cli::UsageError& e) {
    std::cerr << "pcl_patchdict " << name << ": " << e.what() << '\n';
    return 2;
  } catch (const std::bad_alloc&) {
    std::cerr << "pcl_patchdict " << name << ": error: out of memory\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "pcl_patchdict " << name << ": error: " << e.what() << '\n';
    return 1;
  }
}
