// `pcl_patchdict learn IN.pds... -o DICT.pdd`: a local (one input) or global (many) dictionary.
#include "cli.h"

#include <pcl_patchdict/patch_dictionary.h>
#include <pcl_patchdict/patch_set.h>

#include <cstdio>
#include <iostream>

namespace pcl {
namespace patchdict {
namespace cli {

int runLearn(const std::vector<std::string>& raw)
{
  auto value_options = commonValueOptions();
  value_options.insert({"output", "atoms", "sparsity", "iterations", "method", "batch", "png"});
  auto flag_options = commonFlagOptions();
  flag_options.insert("remove-mean");
  const Arguments args(raw, value_options, flag_options);
  const std::string usage =
      "pcl_patchdict learn IN.pds... -o DICT.pdd [--atoms K] [--sparsity S] [--iterations T] "
      "[--method ksvd|online] [--batch B] [--remove-mean] [--png ATOMS.png]";
  args.expectPositionals(1, 100000, usage);
  if (!args.has("output"))
    throw UsageError("usage: " + usage);
  applyCommonOptions(args);
  const bool quiet = args.has("quiet") || args.has("json");
  PatchDictionary dictionary;
  dictionary.setNumAtoms(static_cast<int>(args.getInt("atoms", 100, 1, 65536)));
  dictionary.setSparsity(static_cast<int>(args.getInt("sparsity", 8, 1, 1024)));
  const std::string method = args.get("method", "ksvd");
  if (method != "ksvd" && method != "online")
    throw UsageError("option --method: '" + method + "' is not ksvd or online");
  dictionary.setLearningMethod(method == "ksvd" ? PatchDictionary::LearningMethod::KSVD
                                                : PatchDictionary::LearningMethod::Online);
  dictionary.setIterations(static_cast<int>(args.getInt("iterations", method == "ksvd" ? 20 : 3, 1, 100000)));
  dictionary.setBatchSize(static_cast<int>(args.getInt("batch", 512, 1, 1 << 20)));
  dictionary.setSeed(static_cast<std::uint64_t>(args.getInt("seed", 1, 0, (1LL << 62))));
  dictionary.setRemoveMean(args.has("remove-mean"));

  for (const std::string& path : args.positionals()) {
    checkOutputPath(args.get("output"), path);
    checkOutputPath(args.get("png"), path);
  }
  StageTimer timer(quiet);
  for (const std::string& path : args.positionals())
    if (formatFromPath(path) != MeshFormat::Unknown)
      throw Error("'" + path + "' is a mesh or cloud: learning straight from surfaces needs the quad and patch stages, "
                  "which are not in this version; give .pds patch files");
  LearningReport report;
  std::size_t patch_count = 0;
  int grid_size = 0;
  double observed_fraction = 0.0;
  if (method == "online" && dictionary.getRemoveMean())
    throw UsageError("--remove-mean is available with --method ksvd only");
  if (method == "online") {
    // Global dictionaries: stream the files, one in memory at a time, `iterations` passes.
    timer.start("learn");
    OnlineLearningParameters parameters;
    parameters.num_atoms = dictionary.getNumAtoms();
    parameters.sparsity = dictionary.getSparsity();
    parameters.batch_size = dictionary.getBatchSize();
    parameters.seed = dictionary.getSeed();
    OnlineDictionaryLearner learner(parameters);
    double observed_sum = 0.0;
    for (int pass = 0; pass < dictionary.getIterations(); ++pass)
      for (const std::string& path : args.positionals()) {
        const PatchSet part = PatchSet::load(path);
        if (part.numPatches() == 0)
          continue;
        if (grid_size == 0)
          grid_size = part.grid_size;
        else if (part.grid_size != grid_size)
          throw Error("'" + path + "' has " + std::to_string(part.grid_size) + "×" + std::to_string(part.grid_size) +
                      " patches, the first file " + std::to_string(grid_size) + "×" + std::to_string(grid_size));
        if (pass == 0) {
          patch_count += part.numPatches();
          observed_sum += part.observedFraction() * static_cast<double>(part.numPatches());
        }
        learner.fit(part.heights, part.observed.all() ? ObservationMask() : part.observed, 1);
      }
    if (patch_count == 0)
      throw Error("the patch files hold no patches");
    observed_fraction = observed_sum / static_cast<double>(patch_count);
    dictionary.setAtoms(learner.dictionary(), patch_count);
  } else {
    timer.start("load");
    PatchSet patches;
    for (std::size_t i = 0; i < args.positionals().size(); ++i) {
      PatchSet part = PatchSet::load(args.positionals()[i]);
      if (i == 0)
        patches = std::move(part);
      else
        patches.append(part);
    }
    if (patches.numPatches() == 0)
      throw Error("the patch files hold no patches");
    patch_count = patches.numPatches();
    grid_size = patches.grid_size;
    observed_fraction = patches.observedFraction();
    timer.start("learn");
    report = dictionary.learn(patches.heights, patches.observed.all() ? ObservationMask() : patches.observed);
  }
  note(quiet, "  " + std::to_string(patch_count) + " patches of " + std::to_string(grid_size) + "×" +
                  std::to_string(grid_size) + " bins, " +
                  std::to_string(static_cast<int>(100.0 * observed_fraction + 0.5)) + " % observed");
  timer.start("save");
  dictionary.save(args.get("output"));
  if (args.has("png"))
    dictionary.saveAtomsPNG(args.get("png"));
  timer.stop();

  if (args.has("json")) {
    JsonObject json;
    json.add("command", "learn").add("output", args.get("output")).add("patches", patch_count);
    json.add("grid_size", grid_size).add("observed_fraction", observed_fraction);
    json.add("atoms", dictionary.getNumAtoms()).add("sparsity", dictionary.getSparsity()).add("method", method);
    if (!report.rmse_per_iteration.empty())
      json.add("final_rmse", report.rmse_per_iteration.back());
    json.add("atoms_replaced", report.atoms_replaced).add("seconds", timer.json());
    std::cout << json.str() << '\n';
  } else if (!quiet) {
    std::printf("learned %d atoms from %zu patches -> %s", dictionary.getNumAtoms(), patch_count,
                args.get("output").c_str());
    if (!report.rmse_per_iteration.empty())
      std::printf(" (RMS representation error %.4g after the last coding step)", report.rmse_per_iteration.back());
    std::printf("\n");
  }
  return 0;
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
