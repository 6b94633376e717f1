#include "cli.h"
#include "options.h"

#include <pcl_patchdict/core/atomic_file.h>
#include <pcl_patchdict/geometry/mesh_hygiene.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <omp.h>
#include <sstream>
#include <stdexcept>

namespace pcl {
namespace patchdict {
namespace cli {

Arguments::Arguments(const std::vector<std::string>& args, const CommandSpec& spec) : specs_{&spec}
{
  parse(args, specs_);
}

Arguments::Arguments(const std::vector<std::string>& args, const std::vector<const CommandSpec*>& specs)
    : specs_(specs)
{
  parse(args, specs_);
}

Arguments readCommandLine(const std::vector<std::string>& args, const CommandSpec& spec)
{
  Arguments arguments(args, spec);
  arguments.expectUsage();
  applyCommonOptions(arguments);
  return arguments;
}

void Arguments::parse(const std::vector<std::string>& args, const std::vector<const CommandSpec*>& specs)
{
  const auto lookup = [&](std::string& name, std::vector<std::string>& deprecated) -> const OptionSpec* {
    for (const CommandSpec* spec : specs) {
      for (const auto& [old_name, new_name] : spec->deprecated)
        if (name == old_name) {
          deprecated.push_back("option --" + old_name + " is now spelled --" + new_name);
          name = new_name;
          break;
        }
      if (const OptionSpec* option = findOption(*spec, name))
        return option;
    }
    return nullptr;
  };
  std::vector<std::string> deprecated;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg.size() < 3 || arg.compare(0, 2, "--") != 0) {
      if (arg.size() > 1 && arg[0] == '-' && arg != "-o")
        throw UsageError("unknown option '" + arg + "'");
      if (arg == "-o") {  // the one short option: -o OUT
        std::string output = "output";
        if (!lookup(output, deprecated))
          throw UsageError("unknown option '-o' (this command writes no output file)");
        if (i + 1 >= args.size())
          throw UsageError("option -o needs a value");
        values_["output"] = args[++i];
        continue;
      }
      positionals_.push_back(arg);
      continue;
    }
    std::string name = arg.substr(2), value;
    const auto equals = name.find('=');
    const bool inline_value = equals != std::string::npos;
    if (inline_value) {
      value = name.substr(equals + 1);
      name = name.substr(0, equals);
    }
    const OptionSpec* option = lookup(name, deprecated);
    if (!option)
      throw UsageError("unknown option '--" + name + "'");
    if (option->argument.empty()) {
      if (inline_value)
        throw UsageError("option --" + name + " takes no value");
      values_[name] = "1";
    } else {
      if (!inline_value) {
        if (i + 1 >= args.size())
          throw UsageError("option --" + name + " needs a value");
        value = args[++i];
      }
      values_[name] = value;
    }
  }
  if (!has("quiet") && !has("json"))
    for (const std::string& text : deprecated)
      note(false, text);
}

void Arguments::expectUsage() const
{
  const CommandSpec& spec = *specs_.front();
  bool ok = positionals_.size() >= spec.min_positionals && positionals_.size() <= spec.max_positionals;
  for (const OptionSpec& option : spec.options)
    ok = ok && (!option.required || has(option.name));
  if (!ok)
    throw UsageError("usage: " + synopsis(spec) + " (see 'pcl_patchdict " + spec.name + " --help')");
}

void Arguments::needs(const std::string& name, const std::string& other, const std::string& why) const
{
  if (has(name) && !has(other))
    throw UsageError("--" + name + " needs --" + other + (why.empty() ? "" : ": " + why));
}

void Arguments::refuse(const std::string& name, const std::string& message) const
{
  if (has(name))
    throw UsageError("--" + name + " " + message);
}

bool Arguments::takes(const std::string& name) const
{
  for (const CommandSpec* spec : specs_)
    if (const OptionSpec* found = findOption(*spec, name))
      return !found->hidden;
  return false;
}

const OptionSpec& Arguments::option(const std::string& name) const
{
  for (const CommandSpec* spec : specs_)
    if (const OptionSpec* found = findOption(*spec, name))
      return *found;
  throw std::logic_error("option --" + name + " is read but not in the table of '" +
                         (specs_.empty() ? std::string("?") : specs_.front()->name) + "'");
}

const OptionSpec& Arguments::option(const std::string& name, OptionKind kind) const
{
  const OptionSpec& found = option(name);
  if (found.kind != kind)
    throw std::logic_error("option --" + name + " is read as another kind than its table's");
  return found;
}

std::string Arguments::get(const std::string& name) const
{
  const OptionSpec& found = option(name);
  const auto it = values_.find(name);
  if (it != values_.end())
    return it->second;
  return found.kind == OptionKind::Text && found.has_default ? found.text_default : std::string();
}

namespace {

[[noreturn]] void noDefault(const OptionSpec& option, bool typed)
{
  throw std::logic_error("option --" + option.name +
                         (typed ? " has a default in the table: it is read without one"
                                : " has no default in the table: the command passes the value it computes"));
}

std::string outOfRange(const OptionSpec& option, const std::string& text)
{
  return "option --" + option.name + ": " + text + " is out of range (" + rangeText(option) + ")";
}

}  // namespace

double Arguments::parseReal(const OptionSpec& spec) const
{
  const std::string text = values_.at(spec.name);
  double value = 0.0;
  const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
  if (result.ec != std::errc() || result.ptr != text.data() + text.size() || !std::isfinite(value))
    throw UsageError("option --" + spec.name + ": '" + text + "' is not a number");
  if (value < spec.real_min || value > spec.real_max || (spec.above_min && value == spec.real_min))
    throw UsageError(outOfRange(spec, text));
  return value;
}

long long Arguments::parseInteger(const OptionSpec& spec) const
{
  const std::string text = values_.at(spec.name);
  long long value = 0;
  const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
  if (result.ec != std::errc() || result.ptr != text.data() + text.size())
    throw UsageError("option --" + spec.name + ": '" + text + "' is not an integer");
  if (value < spec.int_min || value > spec.int_max)
    throw UsageError(outOfRange(spec, text));
  return value;
}

std::string Arguments::parseWord(const OptionSpec& spec) const
{
  const std::string text = values_.at(spec.name);
  std::string list;
  for (const std::string& word : spec.words) {
    if (word == text)
      return text;
    list += (list.empty() ? "" : ", ") + word;
  }
  throw UsageError("option --" + spec.name + ": '" + text + "' is not one of " + list);
}

const OptionSpec& Arguments::checked(const std::string& name, OptionKind kind, bool computed) const
{
  const OptionSpec& spec = option(name, kind);
  if (computed && spec.has_default)
    noDefault(spec, true);
  if (!computed && !spec.has_default && !has(name))
    noDefault(spec, false);
  return spec;
}

double Arguments::getDouble(const std::string& name) const
{
  const OptionSpec& spec = checked(name, OptionKind::Real, false);
  return has(name) ? parseReal(spec) : spec.real_default;
}

double Arguments::getDouble(const std::string& name, double computed) const
{
  const OptionSpec& spec = checked(name, OptionKind::Real, true);
  return has(name) ? parseReal(spec) : computed;
}

long long Arguments::getInt(const std::string& name) const
{
  const OptionSpec& spec = checked(name, OptionKind::Integer, false);
  return has(name) ? parseInteger(spec) : spec.int_default;
}

long long Arguments::getInt(const std::string& name, long long computed) const
{
  const OptionSpec& spec = checked(name, OptionKind::Integer, true);
  return has(name) ? parseInteger(spec) : computed;
}

std::string Arguments::getWord(const std::string& name) const
{
  const OptionSpec& spec = checked(name, OptionKind::Word, false);
  return has(name) ? parseWord(spec) : spec.text_default;
}

std::string Arguments::getWord(const std::string& name, const std::string& computed) const
{
  const OptionSpec& spec = checked(name, OptionKind::Word, true);
  return has(name) ? parseWord(spec) : computed;
}

void applyCommonOptions(const Arguments& args)
{
  if (args.has("threads"))
    omp_set_num_threads(static_cast<int>(args.getInt("threads")));
}

namespace {

std::string quote(const std::string& text)
{
  std::string out = "\"";
  for (const char c : text) {
    switch (c) {
    case '"': out += "\\\""; break;
    case '\\': out += "\\\\"; break;
    case '\n': out += "\\n"; break;
    case '\t': out += "\\t"; break;
    case '\r': out += "\\r"; break;
    default:
      if (static_cast<unsigned char>(c) < 0x20) {
        char buffer[8];
        std::snprintf(buffer, sizeof buffer, "\\u%04x", c);
        out += buffer;
      } else {
        out += c;
      }
    }
  }
  return out + "\"";
}

}  // namespace

JsonObject& JsonObject::add(const std::string& key, double value)
{
  if (!std::isfinite(value)) {
    // JSON has no Infinity/NaN: an infinite PSNR (identical surfaces) is written as null.
    members_.emplace_back(key, "null");
    return *this;
  }
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  members_.emplace_back(key, std::string(buffer, result.ptr));
  return *this;
}

JsonObject& JsonObject::add(const std::string& key, long long value)
{
  members_.emplace_back(key, std::to_string(value));
  return *this;
}

JsonObject& JsonObject::add(const std::string& key, bool value)
{
  members_.emplace_back(key, value ? "true" : "false");
  return *this;
}

JsonObject& JsonObject::add(const std::string& key, const std::string& value)
{
  members_.emplace_back(key, quote(value));
  return *this;
}

JsonObject& JsonObject::add(const std::string& key, const JsonObject& value)
{
  members_.emplace_back(key, value.str());
  return *this;
}

JsonObject& JsonObject::add(const std::string& key, const std::vector<JsonObject>& values)
{
  std::string array = "[";
  for (std::size_t i = 0; i < values.size(); ++i)
    array += (i ? ", " : "") + values[i].str();
  members_.emplace_back(key, array + "]");
  return *this;
}

JsonObject& JsonObject::add(const std::string& key, const std::vector<long long>& values)
{
  std::string array = "[";
  for (std::size_t i = 0; i < values.size(); ++i)
    array += (i ? "," : "") + std::to_string(values[i]);
  members_.emplace_back(key, array + "]");
  return *this;
}

JsonObject& JsonObject::add(const std::string& key, const std::vector<double>& values)
{
  std::string array = "[";
  for (std::size_t i = 0; i < values.size(); ++i) {
    char buffer[64];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, values[i]);
    array += (i ? "," : "") + (std::isfinite(values[i]) ? std::string(buffer, result.ptr) : std::string("null"));
  }
  members_.emplace_back(key, array + "]");
  return *this;
}

JsonObject& JsonObject::addNull(const std::string& key)
{
  members_.emplace_back(key, "null");
  return *this;
}

std::string JsonObject::str() const
{
  std::string out = "{";
  for (std::size_t i = 0; i < members_.size(); ++i) {
    if (i)
      out += ", ";
    out += quote(members_[i].first) + ": " + members_[i].second;
  }
  return out + "}";
}

void StageTimer::start(const std::string& stage)
{
  stop();
  current_ = stage;
  started_ = std::chrono::steady_clock::now();
  note(quiet_, stage + " ...");
}

void StageTimer::stop()
{
  if (current_.empty())
    return;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  seconds_.emplace_back(current_, seconds);
  current_.clear();
}

JsonObject StageTimer::json() const
{
  JsonObject object;
  for (const auto& [stage, seconds] : seconds_)
    object.add(stage, seconds);
  return object;
}

void makeFolder(const std::string& path, const std::string& what)
{
  std::error_code ec;
  std::filesystem::create_directories(path, ec);
  if (ec)
    throw Error("cannot create the " + what + " folder '" + path + "': " + ec.message());
}

void checkInputExists(const std::string& path, const std::string& what)
{
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw Error(what + " '" + path + "': no such file");
}

void note(bool quiet, const std::string& text)
{
  if (!quiet)
    std::cerr << text << '\n';
}

bool sameFile(const std::string& a, const std::string& b)
{
  std::error_code error;
  if (std::filesystem::exists(a, error) && std::filesystem::exists(b, error))
    return std::filesystem::equivalent(a, b, error) && !error;
  const auto ca = std::filesystem::weakly_canonical(a, error);
  if (error)
    return false;
  const auto cb = std::filesystem::weakly_canonical(b, error);
  return !error && ca == cb;
}

void checkOutputPath(const std::string& output, const std::string& input)
{
  if (output.empty())
    return;
  if (sameFile(output, input))
    throw Error("the output '" + output + "' is the input file; inputs are never overwritten");
  checkWritableFile(output);  // where the file cannot be written, say so before the work, not after it
}

TriangleMesh loadMesh(const std::string& path, bool quiet, ReadInfo* info)
{
  TriangleMesh mesh;
  ReadInfo local_info;
  readMesh(path, mesh, &local_info);
  if (info)
    *info = local_info;
  if (!quiet) {
    std::ostringstream out;
    out << "read " << path << " (" << formatName(local_info.format) << (local_info.binary ? ", binary" : "") << ")";
    if (local_info.polygons_triangulated)
      out << ", " << local_info.polygons_triangulated << " polygons triangulated";
    if (local_info.points_dropped)
      out << ", " << local_info.points_dropped << " non-finite points dropped";
    note(false, out.str());
    note(false, "  " + inspectMesh(mesh).summary());
  }
  return mesh;
}

void cleanInputMesh(TriangleMesh& mesh, const std::string& path)
{
  if (mesh.faces.empty())
    return;
  const std::size_t faces = mesh.faces.size();
  cleanMesh(mesh);
  if (mesh.faces.empty())
    throw Error("'" + path + "': all its " + std::to_string(faces) +
                " faces are degenerate (zero area or repeated corners): there is no surface to work on");
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
