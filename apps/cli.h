// Shared plumbing of the pcl_patchdict tool: argument parsing (options in any order), a small
// ordered JSON writer for --json, stage timing, and the load step every subcommand shares.
#pragma once

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/io/mesh_io.h>

#include "options.h"

#include <chrono>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace pcl {
namespace patchdict {
namespace cli {

/** Thrown for a malformed command line (exit code 2, usage hint). */
struct UsageError : Error {
  using Error::Error;
};


/** Parsed command line of one subcommand: positionals in order, options by name. The getters read
  * an option's default, range and words from the command's table (options.h), never from the call. */
class Arguments {
public:
  /** The options of `spec`'s table (options.h) and the common ones: value options take a value
    * (--name V or --name=V), flags none; -o V is --output V. An option not in the table, a missing
    * value or a value given to a flag is a UsageError; a deprecated spelling is read as the new one
    * (noted on stderr unless --quiet or --json). */
  Arguments(const std::vector<std::string>& args, const CommandSpec& spec);
  /** The union of several paths' tables (denoise and fill-holes read IN before choosing one). */
  Arguments(const std::vector<std::string>& args, const std::vector<const CommandSpec*>& specs);

  const std::vector<std::string>& positionals() const { return positionals_; }
  bool has(const std::string& name) const { return values_.count(name) > 0; }
  /** --quiet or --json: no progress on stderr. */
  bool quiet() const { return has("quiet") || has("json"); }
  /** True when the command's table has a visible option `name` (a hidden one is only refused). */
  bool takes(const std::string& name) const;
  /** The value as given; not given: a Text option's table default, or "". */
  std::string get(const std::string& name) const;
  /** A Real, Integer or Word option: the value given, checked against the table's range or words
    * (UsageError "option --name: 'V' is out of range (R)" or "is not one of ..."); not given, the
    * table's default. std::logic_error when the table has no such option, it is of another kind,
    * or it has no typed default and is not given (read it with the overload below). */
  double getDouble(const std::string& name) const;
  long long getInt(const std::string& name) const;
  std::string getWord(const std::string& name) const;
  /** The same for an option whose default the command computes (the table has none and says
    * how): `computed` when not given. std::logic_error when the table has a typed default. */
  double getDouble(const std::string& name, double computed) const;
  long long getInt(const std::string& name, long long computed) const;
  std::string getWord(const std::string& name, const std::string& computed) const;
  /** The table's positional count and required options; UsageError "usage: SYNOPSIS" otherwise. */
  void expectUsage() const;
  /** UsageError "--name needs --other" when `name` is given without `other`. */
  void needs(const std::string& name, const std::string& other, const std::string& why = "") const;
  /** UsageError "--name: message" when `name` is given. */
  void refuse(const std::string& name, const std::string& message) const;

private:
  void parse(const std::vector<std::string>& args, const std::vector<const CommandSpec*>& specs);
  /** The table's option `name` (std::logic_error when none, or when `kind` differs). */
  const OptionSpec& option(const std::string& name) const;
  const OptionSpec& option(const std::string& name, OptionKind kind) const;
  /** option(name, kind), and std::logic_error for a typed default read as computed (`computed`) or
    * a computed one read without its value and not given. */
  const OptionSpec& checked(const std::string& name, OptionKind kind, bool computed) const;
  /** The given value of a Real/Integer/Word option, checked. */
  double parseReal(const OptionSpec& option) const;
  long long parseInteger(const OptionSpec& option) const;
  std::string parseWord(const OptionSpec& option) const;
  std::vector<const CommandSpec*> specs_;
  std::vector<std::string> positionals_;
  std::map<std::string, std::string> values_;
};

/** Arguments of `spec`'s table with its usage checked (expectUsage) and --threads applied: the
  * first lines of every command. */
Arguments readCommandLine(const std::vector<std::string>& args, const CommandSpec& spec);

/** Applies --threads. */
void applyCommonOptions(const Arguments& args);


/** Insertion-ordered JSON object; values are written as they are added. */
class JsonObject {
public:
  JsonObject& add(const std::string& key, double value);
  JsonObject& add(const std::string& key, long long value);
  JsonObject& add(const std::string& key, std::size_t value) { return add(key, static_cast<long long>(value)); }
  JsonObject& add(const std::string& key, int value) { return add(key, static_cast<long long>(value)); }
  JsonObject& add(const std::string& key, bool value);
  JsonObject& add(const std::string& key, const std::string& value);
  JsonObject& add(const std::string& key, const char* value) { return add(key, std::string(value)); }
  JsonObject& add(const std::string& key, const JsonObject& value);
  JsonObject& add(const std::string& key, const std::vector<JsonObject>& values);  ///< an array of objects
  JsonObject& add(const std::string& key, const std::vector<long long>& values);   ///< an array of integers
  JsonObject& add(const std::string& key, const std::vector<double>& values);      ///< an array of numbers
  JsonObject& addNull(const std::string& key);
  std::string str() const;

private:
  std::vector<std::pair<std::string, std::string>> members_;  // key, serialised value
};

/** Wall-clock time per named stage, for --json and progress lines. */
class StageTimer {
public:
  explicit StageTimer(bool quiet) : quiet_(quiet) {}
  /** Starts a stage (ending the previous one) and prints its name to stderr unless quiet. */
  void start(const std::string& stage);
  void stop();
  JsonObject json() const;

private:
  bool quiet_;
  std::string current_;
  std::chrono::steady_clock::time_point started_;
  std::vector<std::pair<std::string, double>> seconds_;
};

/** Reads a mesh with the reader's notes and the hygiene summary printed to stderr (unless quiet). */
TriangleMesh loadMesh(const std::string& path, bool quiet, ReadInfo* info = nullptr);
/** cleanMesh() for a mesh that has faces (a cloud is left alone); Error "'path': all its N faces are
  * degenerate" when none is left, instead of an empty mesh failing later for a reason nobody sees. */
void cleanInputMesh(TriangleMesh& mesh, const std::string& path);

/** True when both names lead to the same file (an output that would overwrite the input). */
bool sameFile(const std::string& a, const std::string& b);

/** Throws Error when `output` (if not empty) is the same file as `input`, lies in a directory that
  * does not exist, or is a directory: checked before any work is done. */
void checkOutputPath(const std::string& output, const std::string& input);

/** Creates `path` (and its parents) unless it exists; Error "cannot create the <what> folder …". */
void makeFolder(const std::string& path, const std::string& what);

/** Throws Error "<what> 'path': no such file" unless `path` exists: for inputs read only after the
  * work (decompress --ref), so that a typo fails the command before its output is written. */
void checkInputExists(const std::string& path, const std::string& what);

/** Progress/notes line on stderr unless quiet. */
void note(bool quiet, const std::string& text);

// Subcommands: each returns the process exit code.
int runHelp(const std::vector<std::string>& args);
int runInfo(const std::vector<std::string>& args);
/** info on a cloud file (called by runInfo). */
int runCloudInfo(const Arguments& args);
int runEval(const std::vector<std::string>& args);
int runDemo(const std::vector<std::string>& args);
int runLearn(const std::vector<std::string>& args);
int runPatches(const std::vector<std::string>& args);
int runReconstruct(const std::vector<std::string>& args);
int runFillHoles(const std::vector<std::string>& args);
int runFillMissing(const std::vector<std::string>& args);
int runDenoise(const std::vector<std::string>& args);
int runQuads(const std::vector<std::string>& args);
int runCompress(const std::vector<std::string>& args);
int runDecompress(const std::vector<std::string>& args);

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
