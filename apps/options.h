// The one table of the tool's command lines: every subcommand's positionals and options (name,
// kind, argument, typed default, valid range or words, one-line help). The parser and its getters
// (Arguments), `pcl_patchdict CMD --help`, the top-level help and docs/cli.md
// (`pcl_patchdict help --markdown`) all read it: a default or a range is written here only.
#pragma once

#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace pcl {
namespace patchdict {
namespace cli {

enum class OptionKind {
  Flag,     ///< no value
  Text,     ///< a file name or other text, unchecked
  Integer,  ///< a whole number in [int_min, int_max]
  Real,     ///< a finite number in [real_min, real_max] (or (real_min, real_max] with above_min)
  Word      ///< one of `words`
};

/** One option of a command. */
struct OptionSpec {
  std::string name;  ///< without the leading "--"
  OptionKind kind = OptionKind::Flag;
  std::string argument;  ///< what its value is called (FILE.pdd, L, ...); a Word's: its words joined by '|'
  std::string help;      ///< one line
  /// The default the getters return when the option is not given. Without one (has_default false)
  /// the command computes it (`note` says how: "by risk", "the dictionary's") and passes the
  /// computed value to the getter, or the option has none ("" note: absent means off).
  bool has_default = false;
  long long int_default = 0;
  double real_default = 0.0;
  std::string text_default;  ///< Text and Word
  std::string note;          ///< shown after a typed default in parentheses, or alone without one
  long long int_min = std::numeric_limits<long long>::min(), int_max = std::numeric_limits<long long>::max();
  double real_min = -std::numeric_limits<double>::infinity(), real_max = std::numeric_limits<double>::infinity();
  bool above_min = false;  ///< Real: real_min itself is out of range
  std::vector<std::string> words;
  /// Why this option's argument, range or words differ from those of the same name in another
  /// command (checked by a test: without a reason, one name has one meaning).
  std::string differs;
  bool required = false;
  /// Accepted by the parser only so that the command can refuse it with a message of its own
  /// (e.g. --mu in denoise, which names --fidelity); never shown in the help.
  bool hidden = false;

  OptionSpec noted(const std::string& text) const;        ///< with `note` = text
  OptionSpec differing(const std::string& why) const;     ///< with `differs` = why
};

/** One subcommand (or one path of it: denoise and fill-holes have a mesh and a cloud path). */
struct CommandSpec {
  std::string name;
  std::string variant;      ///< "" or "cloud"
  std::string positionals;  ///< as the synopsis shows them ("IN", "INPUT...", "REF OUT")
  std::size_t min_positionals = 1, max_positionals = 1;
  std::string what;         ///< one line
  std::vector<OptionSpec> options;  ///< its own (they take precedence over the common ones of the same name)
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

/** The default as the help shows it: the typed default and its note, the note alone, or "". */
std::string defaultText(const OptionSpec& option);
/** The valid values as the help shows them ("0.001 to 1", "≥ 0", "> 0"); "" for flags, text, words. */
std::string rangeText(const OptionSpec& option);
/** A number as the help writes it: 0.03, 1e-09 as 1e-9, 2^40 for large powers of two. */
std::string formatNumber(double value);
std::string formatInteger(long long value);

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
