// pcl_patchdict — one tool, many subcommands (see `pcl_patchdict help`). Every failure is one line
// on stderr and a non-zero exit: 1 for bad input or a failed run, 2 for a malformed command line.
#include "cli.h"
#include "learn_ranks.h"
#include "options.h"

#include <pcl_patchdict/coding/sparse_coding.h>
#include <pcl_patchdict/core/atomic_file.h>

#include <exception>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <functional>
#include <iostream>
#include <map>
#include <new>

namespace cli = pcl::patchdict::cli;

namespace {

/** The commands in the order of the option table (options.h), which gives their help. */
const std::map<std::string, std::function<int(const std::vector<std::string>&)>>& subcommands()
{
  static const std::map<std::string, std::function<int(const std::vector<std::string>&)>> table{
      {"demo", cli::runDemo},         {"info", cli::runInfo},
      {"eval", cli::runEval},         {"quads", cli::runQuads},
      {"patches", cli::runPatches},   {"learn", cli::runLearn},
      {"reconstruct", cli::runReconstruct}, {"compress", cli::runCompress},
      {"decompress", cli::runDecompress},   {"denoise", cli::runDenoise},
      {"fill-missing", cli::runFillMissing}, {"fill-holes", cli::runFillHoles},
  };
  return table;
}

/** A command's current name: `inpaint` is fill-missing's former one, still accepted. */
std::string commandName(const std::string& name) { return name == "inpaint" ? std::string("fill-missing") : name; }

bool asksForHelp(const std::vector<std::string>& args)
{
  for (const std::string& arg : args)
    if (arg == "--help" || arg == "-h")
      return true;
  return false;
}

}  // namespace

// `help`, `help --markdown`, `help COMMAND`.
int cli::runHelp(const std::vector<std::string>& args)
{
  if (args.empty()) {
    std::cout << overviewHelp();
    return 0;
  }
  if (args.size() == 1 && args[0] == "--markdown") {
    std::cout << markdownHelp();
    return 0;
  }
  const std::string command = commandName(args.at(0));
  if (args.size() == 1 && subcommands().count(command)) {
    std::cout << commandHelp(command);
    return 0;
  }
  throw UsageError("usage: pcl_patchdict help [COMMAND | --markdown]");
}

int main(int argc, char** argv)
{
  pcl::patchdict::removeTemporaryFilesOnInterrupt();
#ifdef __GLIBC__
  // The stages allocate and free the same large blocks over and over (learning batches and
  // statistics, K-SVD's residual every iteration, input patch sets of tens of MB): kept in the heap
  // instead of mapped and unmapped each time, whose page faults cost a quarter of a self-similar
  // denoising (the demo's bunny: 4.75 → 3.45 s, peak 137 → 145 MB) and a third of learn's reading
  // (the 11 meshes' .pds on 2 shards: 3.0 → 2.3 s).
  mallopt(M_MMAP_THRESHOLD, 256 << 20);
  mallopt(M_TRIM_THRESHOLD, 512 << 20);
#endif
  const std::vector<std::string> all(argv + 1, argv + argc);
  if (all.empty() || all[0] == "--help" || all[0] == "-h")
    return cli::runHelp({});
  const std::string name = commandName(all[0]);
  const std::vector<std::string> args(all.begin() + 1, all.end());
  try {
    if (name == "help")
      return cli::runHelp(args);
    pcl::patchdict::sparseCodingKernels();  // a bad PCL_PATCHDICT_SIMD: one error line, before any work
    const auto command = subcommands().find(name);
    if (command != subcommands().end())
      return asksForHelp(args) ? cli::runHelp({name}) : command->second(args);
    std::cerr << "pcl_patchdict: unknown command '" << name << "' (see 'pcl_patchdict help')\n";
    return 2;
  } catch (const cli::StoppedByAnotherRank&) {  // that rank printed the error
    return 1;
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
