// `pcl_patchdict learn INPUT... -o DICT.pdd`: a local dictionary (K-SVD on one input) or a global
// one (online learning, Mairal et al. 2009, streamed from many patch sets or surfaces, resumable).
#include "cli.h"
#include "options.h"
#include "learn_inputs.h"
#include "learn_ranks.h"
#include "learn_shards.h"
#include "learn_stream.h"
#include "surface_patches.h"

#include <pcl_patchdict/coding/learning_checkpoint.h>
#include <pcl_patchdict/coding/patch_dictionary.h>
#include <pcl_patchdict/patches/patch_set.h>
#include <pcl_patchdict/coding/patch_shuffle_buffer.h>
#include <pcl_patchdict/io/learning_checkpoint_io.h>
#include <pcl_patchdict/io/patch_dictionary_io.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

namespace pcl {
namespace patchdict {
namespace cli {

namespace {

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

/** One run of `learn`: the command line as read, and what the learning made. */
struct LearnRun {
  bool quiet = false;
  std::string output, png, checkpoint_path, resume_path;
  LearnInputs inputs;
  std::size_t num_inputs = 0;
  std::string method;
  bool online = false;
  int passes = 0;
  std::size_t buffer_capacity = 0, checkpoint_every = 0, stop_after = 0;
  std::size_t inputs_before_stop = 0;  ///< inputs begun when the run stopped (a sharded run stops at a round's end)
  bool skip_bad = false;
  int shards = 1;                              ///< --shards, or the MPI ranks
  int ranks = 1, rank = 0;
  std::vector<std::uint64_t> patches_coded;    ///< per shard (sharded runs)
  JsonObject round_seconds;                    ///< where rank 0's rounds went (sharded runs)
  bool patch_cache = true;        ///< keep surface inputs' patches on disk between passes
  std::size_t cache_reads = 0;    ///< inputs read back from the cache
  std::uintmax_t cache_bytes = 0; ///< the cache's size at its largest
  SurfacePatchOptions surface_options;
  int grid_size = 0;  ///< --grid binds .pds inputs too; without it the first input's grid does
  DictionaryLearningOptions options;
  PatchDictionary dictionary;

  LearningReport report;
  std::size_t max_input_patches = 0, max_buffered = 0, checkpoints_written = 0, batches = 0;
  bool complete = true, resumed = false;
  std::uint32_t resumed_pass = 0;
  std::uint64_t resumed_input = 0;
  LearningCheckpoint progress;

  /** A bad input: an Error, or (--skip-bad) a note and an entry of the skipped list. */
  void skip(std::size_t index, const Error& error)
  {
    if (!skip_bad)
      throw Error("input " + std::to_string(index + 1) + "/" + std::to_string(num_inputs) + ": " + error.what() +
                  " (--skip-bad skips bad inputs)");
    note(quiet, "  skipped input " + std::to_string(index + 1) + "/" + std::to_string(num_inputs) + ": " + error.what());
    progress.skipped.emplace_back(index, error.what());
  }
};

// 1. The command line: the inputs expanded, the method chosen, the options checked against it.
void readLearnLine(const Arguments& args, LearnRun& run)
{
  run.quiet = args.quiet();
  run.output = args.get("output");
  run.png = args.get("png");
  run.checkpoint_path = args.get("checkpoint");
  run.resume_path = args.get("resume");

  run.inputs = expandLearnInputs(args.positionals());
  run.num_inputs = run.inputs.paths.size();
  // One input is a local dictionary: K-SVD, the paper's method and the better one when the
  // patches fit in memory. Several are a global dictionary: online learning, whose memory does
  // not grow with the number of patches and which can be checkpointed and resumed.
  run.method = args.getWord("method", run.num_inputs == 1 ? "ksvd" : "online");
  run.online = run.method == "online";
  for (const char* name :
       {"batch", "buffer", "checkpoint", "checkpoint-every", "resume", "stop-after", "no-patch-cache", "shards"})
    if (!run.online && args.has(name))
      throw UsageError(std::string("--") + name + " is available with --method online only");
  if (run.online && args.has("remove-mean"))
    throw UsageError("--remove-mean is available with --method ksvd only");
  run.shards = static_cast<int>(args.getInt("shards", run.ranks));
  if (run.ranks > 1 && !run.online)
    throw UsageError("mpirun runs 'learn --method online' only (K-SVD needs every patch in one process)");
  if (run.ranks > 1 && run.shards != run.ranks)
    throw UsageError("--shards " + std::to_string(run.shards) + " under mpirun with " + std::to_string(run.ranks) +
                     " ranks: one shard per rank");
  if ((args.has("checkpoint-every") || args.has("stop-after")) && run.checkpoint_path.empty())
    throw UsageError("--checkpoint-every and --stop-after need --checkpoint FILE");

  DictionaryLearningOptions& options = run.options;
  options.num_atoms = static_cast<int>(args.getInt("atoms"));
  options.sparsity = static_cast<int>(args.getInt("sparsity"));
  options.method = run.online ? LearningMethod::Online : LearningMethod::KSVD;
  // Not given: 3 passes online, the learner's own K-SVD iterations (20) otherwise, as the table says.
  run.passes = static_cast<int>(args.getInt("iterations", run.online ? 3 : options.iterations));
  options.iterations = run.passes;
  options.batch_size = static_cast<int>(args.getInt("batch"));
  if (run.online && options.batch_size < run.shards)
    throw UsageError("--batch " + std::to_string(options.batch_size) + " has fewer patches than shards (" +
                     std::to_string(run.shards) + "): each shard's part of a batch needs one at least");
  options.seed = static_cast<std::uint64_t>(args.getInt("seed"));
  run.dictionary.setRemoveMean(args.has("remove-mean"));
  run.buffer_capacity = static_cast<std::size_t>(args.getInt("buffer"));
  run.checkpoint_every = static_cast<std::size_t>(args.getInt("checkpoint-every"));
  run.stop_after = static_cast<std::size_t>(args.getInt("stop-after", 0));  // 0: never
  run.skip_bad = args.has("skip-bad");
  run.patch_cache = !args.has("no-patch-cache");
  run.surface_options.grid_size = static_cast<int>(args.getInt("grid"));
  run.surface_options.quad_length = args.getDouble("quad-length");
  run.surface_options.overlap = static_cast<int>(args.getInt("overlap"));
  run.surface_options.seed = options.seed;
  run.grid_size = args.has("grid") ? run.surface_options.grid_size : 0;

  for (const std::string& path : run.inputs.paths) {
    checkOutputPath(run.output, path);
    checkOutputPath(run.png, path);
    checkOutputPath(run.checkpoint_path, path);
  }
  if (!run.png.empty() && sameFile(run.png, run.output))
    throw UsageError("--png and -o name the same file");
  if (!run.checkpoint_path.empty() &&
      (sameFile(run.checkpoint_path, run.output) || (!run.png.empty() && sameFile(run.checkpoint_path, run.png))))
    throw UsageError("--checkpoint names the same file as -o or --png");
  if (run.inputs.ignored > 0)
    note(run.quiet || run.rank > 0,
         "  " + std::to_string(run.inputs.ignored) + " files in the input folders are neither .pds nor surfaces: ignored");
}

// 2a. What shapes an online result (--checkpoint-every and --stop-after do not): the settings a
// checkpoint records and a resumed run must match.
void describeOnline(const Arguments& args, LearnRun& run)
{
  LearningCheckpoint& progress = run.progress;
  progress.settings = {{"method", run.method},
                       {"atoms", std::to_string(run.options.num_atoms)},
                       {"sparsity", std::to_string(run.options.sparsity)},
                       {"batch", std::to_string(run.options.batch_size)},
                       {"seed", std::to_string(run.options.seed)},
                       {"iterations", std::to_string(run.passes)},
                       {"buffer", std::to_string(run.buffer_capacity)},
                       {"grid", args.has("grid") ? args.get("grid") : "(first input)"},
                       {"quad-length", number(run.surface_options.quad_length)},
                       {"overlap", std::to_string(run.surface_options.overlap)},
                       {"skip-bad", run.skip_bad ? "yes" : "no"}};
  progress.num_inputs = run.num_inputs;
  progress.inputs_fingerprint = fingerprintInputs(run.inputs.paths);
}

/** The checkpoint to resume from, checked against this run (settings, inputs, shard count). */
LearningCheckpoint loadResumable(const LearnRun& run)
{
  LearningCheckpoint saved = loadLearningCheckpoint(run.resume_path);
  checkResumable(saved, run.progress, run.resume_path);
  const std::size_t shards = run.shards > 1 ? static_cast<std::size_t>(run.shards) : 0;
  if (saved.shards.size() != shards)
    throw Error("cannot resume from '" + run.resume_path + "': it was made by " +
                std::to_string(std::max<std::size_t>(saved.shards.size(), 1)) + " shard(s) (or ranks), this run has " +
                std::to_string(run.shards));
  saved.settings = run.progress.settings;
  return saved;
}

void noteResuming(LearnRun& run, const LearningCheckpoint& saved)
{
  run.grid_size = saved.grid_size;
  run.resumed = true;
  run.resumed_pass = saved.pass;
  run.resumed_input = saved.next_input;
  std::string where = "  resuming at pass " + std::to_string(std::min<int>(static_cast<int>(saved.pass) + 1, run.passes)) +
                      "/" + std::to_string(run.passes);
  if (saved.shards.empty())
    where += ", input " + std::to_string(saved.next_input + 1) + "/" + std::to_string(run.num_inputs);
  note(run.quiet || run.rank > 0, where);
}

// 2b. Where a resumed one-shard run starts.
void startOnline(LearnRun& run, OnlineDictionaryLearner& learner, PatchShuffleBuffer& buffer)
{
  if (run.resume_path.empty())
    return;
  LearningCheckpoint saved = loadResumable(run);
  learner.setState(saved.learner);
  buffer.setState(saved.buffer);
  noteResuming(run, saved);
  run.progress = std::move(saved);
  run.progress.learner = OnlineDictionaryLearner::State();  // restored above; not kept twice
  run.progress.buffer = PatchShuffleBuffer::State();
}

// 2. Online learning: the inputs streamed through a shuffle buffer, pass after pass, checkpointed.
void learnOnline(const Arguments& args, LearnRun& run)
{
  LearningCheckpoint& progress = run.progress;
  OnlineLearningParameters parameters;
  parameters.num_atoms = run.options.num_atoms;
  parameters.sparsity = run.options.sparsity;
  parameters.batch_size = run.options.batch_size;
  parameters.seed = run.options.seed;
  OnlineDictionaryLearner learner(parameters);
  PatchShuffleBuffer buffer(run.buffer_capacity, parameters.batch_size, parameters.seed);
  describeOnline(args, run);
  startOnline(run, learner, buffer);
  const auto saveCheckpoint = [&]() {
    if (run.checkpoint_path.empty())
      return;
    progress.grid_size = run.grid_size;
    progress.learner = learner.state();
    progress.buffer = buffer.state();
    saveLearningCheckpoint(run.checkpoint_path, progress);
    ++run.checkpoints_written;
    progress.learner = OnlineDictionaryLearner::State();  // copies not kept between checkpoints
    progress.buffer = PatchShuffleBuffer::State();
  };

  const auto started = std::chrono::steady_clock::now();
  std::size_t inputs_this_run = 0, since_checkpoint = 0, streamed_this_run = 0;
  PatchCache cache(run.patch_cache, run.num_inputs);
  for (int pass = static_cast<int>(progress.pass); pass < run.passes && run.complete; ++pass) {
    for (std::size_t i = progress.next_input; i < run.num_inputs; ++i) {
      if (run.stop_after > 0 && inputs_this_run == run.stop_after) {
        run.complete = false;
        run.inputs_before_stop = inputs_this_run;
        break;
      }
      const std::string& path = run.inputs.paths[i];
      PatchSet part;
      bool bad = false;
      try {
        if (cache.has(i)) {
          part = cache.load(i);
          ++run.cache_reads;
        } else {
          part = loadInputPatches(path, run.surface_options, run.grid_size);
          if (pass + 1 < run.passes && !readsAsPatchSet(path))  // a .pds is read as fast as a cache
            cache.store(i, part, run.quiet);
        }
      } catch (const Error& error) {
        // A bad input fails the same way on every pass: reported once, on the first.
        if (pass == 0 || !run.skip_bad)
          run.skip(i, error);
        bad = true;
      }
      if (!bad && part.numPatches() > 0) {
        if (run.grid_size == 0)
          run.grid_size = part.grid_size;
        if (pass == 0) {
          progress.patches += part.numPatches();
          progress.observed_sum += part.observedFraction() * static_cast<double>(part.numPatches());
        }
        run.max_input_patches = std::max(run.max_input_patches, part.numPatches());
        buffer.add(part.heights, part.observed.all() ? ObservationMask() : part.observed, learner);
        progress.patches_streamed += part.numPatches();
        streamed_this_run += part.numPatches();
      }
      ++inputs_this_run;
      progress.next_input = i + 1;
      if (!run.quiet) {
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
        char line[160];
        std::snprintf(line, sizeof line, "  pass %d/%d, input %zu/%zu: %zu patches (%llu so far, %.0f patches/s) ",
                      pass + 1, run.passes, i + 1, run.num_inputs, bad ? std::size_t(0) : part.numPatches(),
                      static_cast<unsigned long long>(progress.patches_streamed),
                      seconds > 0 ? static_cast<double>(streamed_this_run) / seconds : 0.0);
        note(false, line + std::filesystem::path(path).filename().string() + (bad ? " (skipped)" : ""));
      }
      if (++since_checkpoint == run.checkpoint_every) {
        saveCheckpoint();
        since_checkpoint = 0;
      }
    }
    if (!run.complete)
      break;
    buffer.flush(learner);
    progress.pass = static_cast<std::uint32_t>(pass + 1);
    progress.next_input = 0;
  }
  run.max_buffered = buffer.highWater();
  run.cache_bytes = cache.bytes();
  run.batches = static_cast<std::size_t>(learner.state().steps);
  if (!run.complete) {
    saveCheckpoint();
  } else {
    if (progress.patches == 0 || learner.dictionary().size() == 0)
      throw Error(progress.skipped.size() == run.num_inputs ? "every input was bad and skipped"
                                                            : "the inputs hold no patches");
    run.dictionary.setAtoms(learner.dictionary(), progress.patches, run.options);
    saveCheckpoint();  // the finished state: resuming from it only writes the dictionary again
  }
}

// 2c. Online learning over several shards (in this process, or one per MPI rank).
void learnOnlineSharded(const Arguments& args, LearnRun& run, const Ranks& ranks)
{
  describeOnline(args, run);
  run.progress.settings.emplace_back("shards", std::to_string(run.shards));
  LearningCheckpoint saved;
  if (!run.resume_path.empty()) {
    ranks.agree([&]() { saved = loadResumable(run); });  // every rank reads it (shared storage)
    noteResuming(run, saved);
  }
  ShardedLearningJob job;
  job.checkpoint_path = run.checkpoint_path;
  job.checkpoint_every = run.checkpoint_every;
  job.stop_after = run.stop_after;
  job.checkpoint = run.progress;
  job.resume = run.resume_path.empty() ? nullptr : &saved;
  job.paths = run.inputs.paths;
  job.shards = run.shards;
  job.passes = run.passes;
  job.buffer_capacity = run.buffer_capacity;
  job.skip_bad = run.skip_bad;
  job.patch_cache = run.patch_cache;
  job.quiet = run.quiet;
  job.surface_options = run.surface_options;
  job.grid_size = run.grid_size;
  job.parameters.num_atoms = run.options.num_atoms;
  job.parameters.sparsity = run.options.sparsity;
  job.parameters.batch_size = run.options.batch_size;
  job.parameters.seed = run.options.seed;
  const ShardedLearningResult result = learnSharded(job, ranks);
  run.grid_size = result.grid_size;
  run.progress.patches = result.patches;
  run.progress.patches_streamed = result.patches_streamed;
  run.progress.observed_sum = result.observed_sum;
  run.progress.skipped = result.skipped;
  run.patches_coded = result.patches_coded;
  run.max_input_patches = result.max_input_patches;
  run.max_buffered = result.max_buffered;
  run.batches = result.steps;
  run.inputs_before_stop = result.inputs_begun;
  run.cache_reads = result.cache_reads;
  run.cache_bytes = result.cache_bytes;
  run.complete = result.complete;
  run.checkpoints_written = result.checkpoints_written;
  run.round_seconds.add("read", result.seconds_read)
      .add("code", result.seconds_code)
      .add("exchange", result.seconds_exchange)
      .add("update", result.seconds_update);
  if (run.complete)
    run.dictionary.setAtoms(result.dictionary, result.patches, run.options);
}

// 3. K-SVD needs every patch at once: the inputs are appended in memory.
void learnKsvd(LearnRun& run, StageTimer& timer)
{
  timer.start("load");
  PatchSet patches;
  for (std::size_t i = 0; i < run.num_inputs; ++i) {
    try {
      PatchSet part = loadInputPatches(run.inputs.paths[i], run.surface_options, run.grid_size);
      if (part.numPatches() == 0)
        continue;
      run.grid_size = part.grid_size;
      run.max_input_patches = std::max(run.max_input_patches, part.numPatches());
      if (patches.numPatches() == 0)
        patches = std::move(part);
      else
        patches.append(part);
    } catch (const Error& error) {
      run.skip(i, error);
    }
  }
  if (patches.numPatches() == 0)
    throw Error(run.progress.skipped.size() == run.num_inputs ? "every input was bad and skipped"
                                                              : "the inputs hold no patches");
  run.progress.patches = patches.numPatches();
  run.progress.patches_streamed = patches.numPatches();
  run.progress.observed_sum = patches.observedFraction() * static_cast<double>(patches.numPatches());
  run.max_buffered = patches.numPatches();
  timer.start("learn");
  run.report = run.dictionary.learn(patches.heights, patches.observed.all() ? ObservationMask() : patches.observed,
                                    run.options);
}

// 4. --json.
JsonObject learnJson(const LearnRun& run, std::size_t patch_count, double observed_fraction, const StageTimer& timer)
{
  JsonObject json;
  json.add("command", "learn").add("output", run.output).add("method", run.method).add("complete", run.complete);
  json.add("inputs", run.num_inputs).add("inputs_skipped", run.progress.skipped.size());
  std::vector<JsonObject> skipped;
  for (const auto& entry : run.progress.skipped) {
    JsonObject item;
    item.add("input", run.inputs.paths[static_cast<std::size_t>(entry.first)]).add("reason", entry.second);
    skipped.push_back(item);
  }
  json.add("skipped", skipped);
  json.add("patches", patch_count).add("patches_streamed", static_cast<std::size_t>(run.progress.patches_streamed));
  json.add("grid_size", run.grid_size).add("observed_fraction", observed_fraction);
  json.add("atoms", run.options.num_atoms).add("sparsity", run.options.sparsity).add("iterations", run.passes);
  json.add("max_input_patches", run.max_input_patches).add("max_buffered_patches", run.max_buffered);
  if (run.online) {
    json.add("buffer", run.buffer_capacity).add("batch", run.options.batch_size).add("batches", run.batches);
    json.add("ranks", run.ranks).add("shards", run.shards);
    if (!run.patches_coded.empty()) {
      std::vector<long long> coded(run.patches_coded.begin(), run.patches_coded.end());
      json.add("patches_coded_per_shard", coded).add("round_seconds", run.round_seconds);
    }
    json.add("resumed", run.resumed);
    if (run.resumed)
      json.add("resumed_pass", static_cast<std::size_t>(run.resumed_pass))
          .add("resumed_input", static_cast<std::size_t>(run.resumed_input));
    json.add("checkpoints_written", run.checkpoints_written);
    json.add("patch_cache", JsonObject()
                                .add("inputs_read_back", run.cache_reads)
                                .add("bytes", static_cast<std::size_t>(run.cache_bytes)));
    if (!run.checkpoint_path.empty())
      json.add("checkpoint", run.checkpoint_path);
  }
  if (!run.report.rmse_per_iteration.empty())
    json.add("final_rmse", run.report.rmse_per_iteration.back());
  json.add("atoms_replaced", run.report.atoms_replaced).add("seconds", timer.json());
  return json;
}

}  // namespace

namespace {
int learnAndReport(const Arguments& args, LearnRun& run, const Ranks& ranks);
}  // namespace

int runLearn(const std::vector<std::string>& raw)
{
  if (Ranks::launchedAsMany() && !Ranks::built())
    throw UsageError("started by an MPI launcher, but this pcl_patchdict was built without MPI (install libopenmpi-dev "
                     "and build again), so each copy would learn alone");
  Ranks& ranks = Ranks::world();
  struct Finish {
    Ranks& ranks;
    ~Finish() { ranks.finish(); }
  } finish{ranks};
  // Every rank reads the same command line: an error in it is reported once, by rank 0.
  std::optional<Arguments> read;
  LearnRun run;
  run.ranks = ranks.size();
  run.rank = ranks.rank();
  ranks.agree([&]() {
    read.emplace(readCommandLine(raw, commandSpec("learn")));
    readLearnLine(*read, run);
  });
  try {
    return learnAndReport(*read, run, ranks);
  } catch (const StoppedByAnotherRank&) {
    throw;
  } catch (const std::exception& error) {
    if (ranks.size() > 1 && !ranks.stoppedTogether()) {
      // An error this rank alone met outside the agreed exchanges: the others wait for it in the
      // next one, which only MPI_Abort ends. Said here, as main would, before the abort.
      const bool usage = dynamic_cast<const UsageError*>(&error) != nullptr;
      std::cerr << "pcl_patchdict learn: " << (usage ? "" : "error: ") << error.what() << std::endl;
      ranks.abortAll();
    }
    throw;
  }
}

namespace {

// The learning, the dictionary written by rank 0, the report.
int learnAndReport(const Arguments& args, LearnRun& run, const Ranks& ranks)
{
  StageTimer timer(run.quiet || run.rank > 0);
  if (run.online && run.shards > 1) {
    timer.start("learn");
    learnOnlineSharded(args, run, ranks);
  } else if (run.online) {
    timer.start("learn");
    learnOnline(args, run);
  } else {
    learnKsvd(run, timer);
  }
  if (run.rank > 0)
    return 0;  // rank 0 writes the dictionary and reports
  const std::size_t patch_count = static_cast<std::size_t>(run.progress.patches);
  const double observed_fraction = patch_count ? run.progress.observed_sum / static_cast<double>(patch_count) : 0.0;
  if (run.complete) {
    note(run.quiet, "  " + std::to_string(patch_count) + " patches of " + std::to_string(run.grid_size) + "×" +
                        std::to_string(run.grid_size) + " bins, " +
                        std::to_string(static_cast<int>(100.0 * observed_fraction + 0.5)) + " % observed");
    timer.start("save");
    savePatchDictionary(run.output, run.dictionary);
    if (!run.png.empty())
      saveDictionaryAtomsPNG(run.png, run.dictionary);
  }
  timer.stop();

  if (args.has("json")) {
    std::cout << learnJson(run, patch_count, observed_fraction, timer).str() << '\n';
  } else if (!run.quiet) {
    if (!run.complete) {
      std::printf("stopped after %zu inputs; continue with --resume %s\n", run.inputs_before_stop,
                  run.checkpoint_path.c_str());
    } else {
      std::printf("learned %d atoms from %zu patches of %zu inputs -> %s", run.options.num_atoms, patch_count,
                  run.num_inputs - run.progress.skipped.size(), run.output.c_str());
      if (!run.report.rmse_per_iteration.empty())
        std::printf(" (RMS representation error %.4g after the last coding step)", run.report.rmse_per_iteration.back());
      std::printf("\n");
    }
  }
  return 0;
}

}  // namespace

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
