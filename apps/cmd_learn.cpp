// `pcl_patchdict learn INPUT... -o DICT.pdd`: a local dictionary (K-SVD on one input) or a global
// one (online learning, Mairal et al. 2009, streamed from many patch sets or surfaces, resumable).
#include "cli.h"
#include "learn_inputs.h"
#include "surface_patches.h"

#include <pcl_patchdict/coding/learning_checkpoint.h>
#include <pcl_patchdict/coding/patch_dictionary.h>
#include <pcl_patchdict/patches/patch_set.h>
#include <pcl_patchdict/coding/patch_shuffle_buffer.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

namespace pcl {
namespace patchdict {
namespace cli {

namespace {

/** Reads one input as patches: a .pds as it is, a surface through the `patches` stages. A file
  * that is neither is read as .pds, whose reader says what is wrong with it. */
PatchSet loadInputPatches(const std::string& path, SurfacePatchOptions options, int grid_size)
{
  PatchSet patches;
  if (isPatchSetPath(path) || formatFromPath(path) == MeshFormat::Unknown) {
    patches = PatchSet::load(path);
  } else {
    if (grid_size > 0)
      options.grid_size = grid_size;
    patches = surfacePatches(path, options, true).patches;
  }
  if (grid_size > 0 && patches.numPatches() > 0 && patches.grid_size != grid_size)
    throw Error("'" + path + "' has " + std::to_string(patches.grid_size) + "×" + std::to_string(patches.grid_size) +
                " patches, the inputs before it (or --grid) " + std::to_string(grid_size) + "×" +
                std::to_string(grid_size));
  return patches;
}

std::string number(double value)
{
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

/** The first setting of the checkpoint that differs from this run's, as "--name then, now". */
void checkResumable(const LearningCheckpoint& saved, const LearningCheckpoint& wanted, const std::string& path)
{
  const std::string where = "cannot resume from '" + path + "': ";
  for (const auto& setting : wanted.settings) {
    const auto found = std::find_if(saved.settings.begin(), saved.settings.end(),
                                    [&](const auto& entry) { return entry.first == setting.first; });
    if (found == saved.settings.end())
      throw Error(where + "it does not record --" + setting.first);
    if (found->second != setting.second)
      throw Error(where + "it was made with --" + setting.first + " " + found->second + ", this run has " +
                  setting.second);
  }
  if (saved.num_inputs != wanted.num_inputs || saved.inputs_fingerprint != wanted.inputs_fingerprint)
    throw Error(where + "it was made for another input list (" + std::to_string(saved.num_inputs) + " inputs then, " +
                std::to_string(wanted.num_inputs) + " now, or their names or sizes changed)");
}

}  // namespace

int runLearn(const std::vector<std::string>& raw)
{
  auto value_options = commonValueOptions();
  value_options.insert({"output", "atoms", "sparsity", "iterations", "method", "batch", "png", "grid", "quad-length",
                        "overlap", "buffer", "checkpoint", "checkpoint-every", "resume", "stop-after"});
  auto flag_options = commonFlagOptions();
  flag_options.insert({"remove-mean", "skip-bad"});
  const Arguments args(raw, value_options, flag_options);
  const std::string usage =
      "pcl_patchdict learn INPUT... -o DICT.pdd [--method ksvd|online] [--atoms K] [--sparsity S] "
      "[--iterations T] [--batch B] [--buffer N] [--grid N] [--quad-length L] [--overlap K] [--skip-bad] "
      "[--checkpoint FILE.pdk [--checkpoint-every N] [--stop-after N]] [--resume FILE.pdk] [--remove-mean] "
      "[--png ATOMS.png] [--json]   (INPUT: .pds, mesh or cloud, folder, glob, @LIST.txt)";
  args.expectPositionals(1, 1000000, usage);
  if (!args.has("output"))
    throw UsageError("usage: " + usage);
  applyCommonOptions(args);
  const bool quiet = args.has("quiet") || args.has("json");
  const std::string output = args.get("output"), png = args.get("png");
  const std::string checkpoint_path = args.get("checkpoint"), resume_path = args.get("resume");

  const LearnInputs inputs = expandLearnInputs(args.positionals());
  const std::size_t num_inputs = inputs.paths.size();
  // One input is a local dictionary: K-SVD, the paper's method and the better one when the
  // patches fit in memory. Several are a global dictionary: online learning, whose memory does
  // not grow with the number of patches and which can be checkpointed and resumed.
  const std::string method = args.get("method", num_inputs == 1 ? "ksvd" : "online");
  if (method != "ksvd" && method != "online")
    throw UsageError("option --method: '" + method + "' is not ksvd or online");
  const bool online = method == "online";
  for (const char* name : {"buffer", "checkpoint", "checkpoint-every", "resume", "stop-after"})
    if (!online && args.has(name))
      throw UsageError(std::string("--") + name + " is available with --method online only");
  if (online && args.has("remove-mean"))
    throw UsageError("--remove-mean is available with --method ksvd only");
  if ((args.has("checkpoint-every") || args.has("stop-after")) && checkpoint_path.empty())
    throw UsageError("--checkpoint-every and --stop-after need --checkpoint FILE");

  PatchDictionary dictionary;
  dictionary.setNumAtoms(static_cast<int>(args.getInt("atoms", 100, 1, 65536)));
  dictionary.setSparsity(static_cast<int>(args.getInt("sparsity", 8, 1, 1024)));
  dictionary.setLearningMethod(online ? PatchDictionary::LearningMethod::Online : PatchDictionary::LearningMethod::KSVD);
  const int passes = static_cast<int>(args.getInt("iterations", online ? 3 : 20, 1, 100000));
  dictionary.setIterations(passes);
  dictionary.setBatchSize(static_cast<int>(args.getInt("batch", 512, 1, 1 << 20)));
  dictionary.setSeed(static_cast<std::uint64_t>(args.getInt("seed", 1, 0, (1LL << 62))));
  dictionary.setRemoveMean(args.has("remove-mean"));
  const auto buffer_capacity = static_cast<std::size_t>(args.getInt("buffer", 20000, 1, 1LL << 32));
  const auto checkpoint_every = static_cast<std::size_t>(args.getInt("checkpoint-every", 10, 1, 1LL << 40));
  const auto stop_after = static_cast<std::size_t>(args.getInt("stop-after", 0, 1, 1LL << 40));
  const bool skip_bad = args.has("skip-bad");
  SurfacePatchOptions surface_options;
  surface_options.grid_size = static_cast<int>(args.getInt("grid", 16, 2, 64));
  surface_options.quad_length = args.getDouble("quad-length", 0.03, 1e-3, 0.5);
  surface_options.overlap = static_cast<int>(args.getInt("overlap", 1, 0, 16));
  surface_options.seed = dictionary.getSeed();
  // --grid binds .pds inputs too; without it the first input's grid does.
  int grid_size = args.has("grid") ? surface_options.grid_size : 0;

  for (const std::string& path : inputs.paths) {
    checkOutputPath(output, path);
    checkOutputPath(png, path);
    checkOutputPath(checkpoint_path, path);
  }
  if (!png.empty() && sameFile(png, output))
    throw UsageError("--png and -o name the same file");
  if (!checkpoint_path.empty() && (sameFile(checkpoint_path, output) || (!png.empty() && sameFile(checkpoint_path, png))))
    throw UsageError("--checkpoint names the same file as -o or --png");
  if (inputs.ignored > 0)
    note(quiet, "  " + std::to_string(inputs.ignored) + " files in the input folders are neither .pds nor surfaces: ignored");

  StageTimer timer(quiet);
  LearningReport report;
  std::size_t max_input_patches = 0, max_buffered = 0, checkpoints_written = 0, batches = 0;
  bool complete = true, resumed = false;
  std::uint32_t resumed_pass = 0;
  std::uint64_t resumed_input = 0;
  LearningCheckpoint progress;
  const auto skip = [&](std::size_t index, const Error& error) {
    if (!skip_bad)
      throw Error("input " + std::to_string(index + 1) + "/" + std::to_string(num_inputs) + ": " + error.what() +
                  " (--skip-bad skips bad inputs)");
    note(quiet, "  skipped input " + std::to_string(index + 1) + "/" + std::to_string(num_inputs) + ": " + error.what());
    progress.skipped.emplace_back(index, error.what());
  };

  if (online) {
    timer.start("learn");
    OnlineLearningParameters parameters;
    parameters.num_atoms = dictionary.getNumAtoms();
    parameters.sparsity = dictionary.getSparsity();
    parameters.batch_size = dictionary.getBatchSize();
    parameters.seed = dictionary.getSeed();
    OnlineDictionaryLearner learner(parameters);
    PatchShuffleBuffer buffer(buffer_capacity, parameters.batch_size, parameters.seed);
    // What shapes the result; --checkpoint-every and --stop-after do not.
    progress.settings = {{"method", method},
                         {"atoms", std::to_string(parameters.num_atoms)},
                         {"sparsity", std::to_string(parameters.sparsity)},
                         {"batch", std::to_string(parameters.batch_size)},
                         {"seed", std::to_string(parameters.seed)},
                         {"iterations", std::to_string(passes)},
                         {"buffer", std::to_string(buffer_capacity)},
                         {"grid", args.get("grid", "(first input)")},
                         {"quad-length", number(surface_options.quad_length)},
                         {"overlap", std::to_string(surface_options.overlap)},
                         {"skip-bad", skip_bad ? "yes" : "no"}};
    progress.num_inputs = num_inputs;
    progress.inputs_fingerprint = fingerprintInputs(inputs.paths);
    if (!resume_path.empty()) {
      LearningCheckpoint saved = LearningCheckpoint::load(resume_path);
      checkResumable(saved, progress, resume_path);
      learner.setState(saved.learner);
      buffer.setState(saved.buffer);
      saved.settings = progress.settings;
      progress = std::move(saved);
      progress.learner = OnlineDictionaryLearner::State();  // restored above; not kept twice
      progress.buffer = PatchShuffleBuffer::State();
      grid_size = progress.grid_size;
      resumed = true;
      resumed_pass = progress.pass;
      resumed_input = progress.next_input;
      note(quiet, "  resuming at pass " + std::to_string(std::min<int>(static_cast<int>(progress.pass) + 1, passes)) +
                      "/" + std::to_string(passes) + ", input " + std::to_string(progress.next_input + 1) + "/" +
                      std::to_string(num_inputs));
    }
    const auto saveCheckpoint = [&]() {
      if (checkpoint_path.empty())
        return;
      progress.grid_size = grid_size;
      progress.learner = learner.state();
      progress.buffer = buffer.state();
      progress.save(checkpoint_path);
      ++checkpoints_written;
      progress.learner = OnlineDictionaryLearner::State();  // copies not kept between checkpoints
      progress.buffer = PatchShuffleBuffer::State();
    };

    const auto started = std::chrono::steady_clock::now();
    std::size_t inputs_this_run = 0, since_checkpoint = 0, streamed_this_run = 0;
    for (int pass = static_cast<int>(progress.pass); pass < passes && complete; ++pass) {
      for (std::size_t i = progress.next_input; i < num_inputs; ++i) {
        if (stop_after > 0 && inputs_this_run == stop_after) {
          complete = false;
          break;
        }
        const std::string& path = inputs.paths[i];
        PatchSet part;
        bool bad = false;
        try {
          part = loadInputPatches(path, surface_options, grid_size);
        } catch (const Error& error) {
          // A bad input fails the same way on every pass: reported once, on the first.
          if (pass == 0 || !skip_bad)
            skip(i, error);
          bad = true;
        }
        if (!bad && part.numPatches() > 0) {
          if (grid_size == 0)
            grid_size = part.grid_size;
          if (pass == 0) {
            progress.patches += part.numPatches();
            progress.observed_sum += part.observedFraction() * static_cast<double>(part.numPatches());
          }
          max_input_patches = std::max(max_input_patches, part.numPatches());
          buffer.add(part.heights, part.observed.all() ? ObservationMask() : part.observed, learner);
          progress.patches_streamed += part.numPatches();
          streamed_this_run += part.numPatches();
        }
        ++inputs_this_run;
        progress.next_input = i + 1;
        if (!quiet) {
          const double seconds =
              std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
          char line[160];
          std::snprintf(line, sizeof line, "  pass %d/%d, input %zu/%zu: %zu patches (%llu so far, %.0f patches/s) ",
                        pass + 1, passes, i + 1, num_inputs, bad ? std::size_t(0) : part.numPatches(),
                        static_cast<unsigned long long>(progress.patches_streamed),
                        seconds > 0 ? static_cast<double>(streamed_this_run) / seconds : 0.0);
          note(false, line + std::filesystem::path(path).filename().string() + (bad ? " (skipped)" : ""));
        }
        if (++since_checkpoint == checkpoint_every) {
          saveCheckpoint();
          since_checkpoint = 0;
        }
      }
      if (!complete)
        break;
      buffer.flush(learner);
      progress.pass = static_cast<std::uint32_t>(pass + 1);
      progress.next_input = 0;
    }
    max_buffered = buffer.highWater();
    batches = static_cast<std::size_t>(learner.state().steps);
    if (!complete) {
      saveCheckpoint();
    } else {
      if (progress.patches == 0 || learner.dictionary().size() == 0)
        throw Error(progress.skipped.size() == num_inputs ? "every input was bad and skipped" : "the inputs hold no patches");
      dictionary.setAtoms(learner.dictionary(), progress.patches);
      saveCheckpoint();  // the finished state: resuming from it only writes the dictionary again
    }
  } else {
    // K-SVD needs every patch at once: the inputs are appended in memory.
    timer.start("load");
    PatchSet patches;
    for (std::size_t i = 0; i < num_inputs; ++i) {
      try {
        PatchSet part = loadInputPatches(inputs.paths[i], surface_options, grid_size);
        if (part.numPatches() == 0)
          continue;
        grid_size = part.grid_size;
        max_input_patches = std::max(max_input_patches, part.numPatches());
        if (patches.numPatches() == 0)
          patches = std::move(part);
        else
          patches.append(part);
      } catch (const Error& error) {
        skip(i, error);
      }
    }
    if (patches.numPatches() == 0)
      throw Error(progress.skipped.size() == num_inputs ? "every input was bad and skipped" : "the inputs hold no patches");
    progress.patches = patches.numPatches();
    progress.patches_streamed = patches.numPatches();
    progress.observed_sum = patches.observedFraction() * static_cast<double>(patches.numPatches());
    max_buffered = patches.numPatches();
    timer.start("learn");
    report = dictionary.learn(patches.heights, patches.observed.all() ? ObservationMask() : patches.observed);
  }
  const std::size_t patch_count = static_cast<std::size_t>(progress.patches);
  const double observed_fraction = patch_count ? progress.observed_sum / static_cast<double>(patch_count) : 0.0;
  if (complete) {
    note(quiet, "  " + std::to_string(patch_count) + " patches of " + std::to_string(grid_size) + "×" +
                    std::to_string(grid_size) + " bins, " +
                    std::to_string(static_cast<int>(100.0 * observed_fraction + 0.5)) + " % observed");
    timer.start("save");
    dictionary.save(output);
    if (!png.empty())
      dictionary.saveAtomsPNG(png);
  }
  timer.stop();

  if (args.has("json")) {
    JsonObject json;
    json.add("command", "learn").add("output", output).add("method", method).add("complete", complete);
    json.add("inputs", num_inputs).add("inputs_skipped", progress.skipped.size());
    std::vector<JsonObject> skipped;
    for (const auto& entry : progress.skipped) {
      JsonObject item;
      item.add("input", inputs.paths[static_cast<std::size_t>(entry.first)]).add("reason", entry.second);
      skipped.push_back(item);
    }
    json.add("skipped", skipped);
    json.add("patches", patch_count).add("patches_streamed", static_cast<std::size_t>(progress.patches_streamed));
    json.add("grid_size", grid_size).add("observed_fraction", observed_fraction);
    json.add("atoms", dictionary.getNumAtoms()).add("sparsity", dictionary.getSparsity()).add("iterations", passes);
    json.add("max_input_patches", max_input_patches).add("max_buffered_patches", max_buffered);
    if (online) {
      json.add("buffer", buffer_capacity).add("batch", dictionary.getBatchSize()).add("batches", batches);
      json.add("resumed", resumed);
      if (resumed)
        json.add("resumed_pass", static_cast<std::size_t>(resumed_pass)).add("resumed_input", static_cast<std::size_t>(resumed_input));
      json.add("checkpoints_written", checkpoints_written);
      if (!checkpoint_path.empty())
        json.add("checkpoint", checkpoint_path);
    }
    if (!report.rmse_per_iteration.empty())
      json.add("final_rmse", report.rmse_per_iteration.back());
    json.add("atoms_replaced", report.atoms_replaced).add("seconds", timer.json());
    std::cout << json.str() << '\n';
  } else if (!quiet) {
    if (!complete) {
      std::printf("stopped after %zu inputs; continue with --resume %s\n", stop_after, checkpoint_path.c_str());
    } else {
      std::printf("learned %d atoms from %zu patches of %zu inputs -> %s", dictionary.getNumAtoms(), patch_count,
                  num_inputs - progress.skipped.size(), output.c_str());
      if (!report.rmse_per_iteration.empty())
        std::printf(" (RMS representation error %.4g after the last coding step)", report.rmse_per_iteration.back());
      std::printf("\n");
    }
  }
  return 0;
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
