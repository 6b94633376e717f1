// The one table of the tool's command lines: every subcommand's positionals and options (name,
// argument, default, one-line help). The parser (Arguments), `pcl_patchdict CMD --help`, the
// top-level help and docs/cli.md (`pcl_patchdict help --markdown`) all read it.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace pcl {
namespace patchdict {
namespace cli {

/** One option of a command. */
struct OptionSpec {
  std::string name;      ///< without the leading "--"
  std::string argument;  ///< what its value is called (FILE.pdd, L, ...); empty: a flag
  std::string fallback;  ///< the default, as help shows it; empty: none
  std::string help;      ///< one line
  bool required = false;
  /// Accepted by the parser only so that the command can refuse it with a message of its own
  /// (e.g. --mu in denoise, which names --fidelity); never shown in the help.
  bool hidden = false;
};

/** One subcommand (or one path of it: denoise and fill-holes have a mesh and a cloud path). */
struct CommandSpec {
  std::string name;
  std::string variant;      ///< "" or "cloud"
  std::string positionals;  ///< as the synopsis shows them ("IN", "INPUT...", "REF OUT")
  std::size_t min_positionals = 1, max_positionals = 1;
  std::string what;         ///< one line
  std::vector<OptionSpec> options;  ///< its own; the common ones (commonOptions) are added
  /// Old spellings still accepted (old name, new name); each use notes the new one on stderr.
  std::vector<std::pair<std::string, std::string>> deprecated;
};

/** --threads, --seed, --json, --quiet: accepted by every command. */
const std::vector<OptionSpec>& commonOptions();

/** Every command, in the order of the help (a command's cloud path right after it). */
const std::vector<CommandSpec>& commandSpecs();
/** The command `name` (and `variant`); std::logic_error when the table has none. */
const CommandSpec& commandSpec(const std::string& name, const std::string& variant = "");
/** The option of `spec` (common ones included) called `name`, or null. */
const OptionSpec* findOption(const CommandSpec& spec, const std::string& name);

/** "pcl_patchdict NAME POSITIONALS REQUIRED... [options]". */
std::string synopsis(const CommandSpec& spec);
/** `pcl_patchdict NAME --help`: synopsis, what, and the options of every path of NAME. */
std::string commandHelp(const std::string& name);
/** `pcl_patchdict help`: the commands, one synopsis and one line each. */
std::string overviewHelp();
/** `pcl_patchdict help --markdown`: docs/cli.md. */
std::string markdownHelp();

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
