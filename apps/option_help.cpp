// The help texts made from the command-line table (see options.h): `CMD --help`, `help`, and
// docs/cli.md (`help --markdown`), with each option's default and range as the getters use them.
#include "options.h"

#include <charconv>
#include <cmath>
#include <sstream>

namespace pcl {
namespace patchdict {
namespace cli {

namespace {

std::string optionLabel(const OptionSpec& option)
{
  std::string label = (option.name == "output" ? "-o, --" : "--") + option.name;
  if (!option.argument.empty())
    label += " " + option.argument;
  return label;
}

std::string markdownCell(const std::string& text)
{
  std::string out;
  for (const char c : text)
    out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

std::vector<const CommandSpec*> pathsOf(const std::string& name)
{
  std::vector<const CommandSpec*> paths;
  for (const CommandSpec& spec : commandSpecs())
    if (spec.name == name)
      paths.push_back(&spec);
  return paths;
}

/** One line of `CMD --help`: label, help, (range), [default] or (required). */
std::string helpLine(const OptionSpec& option)
{
  const std::string label = optionLabel(option), range = rangeText(option), fallback = defaultText(option);
  std::string line = "  " + label + std::string(label.size() < 34 ? 34 - label.size() : 1, ' ') + option.help;
  if (!range.empty())
    line += " (" + range + ")";
  if (option.required)
    line += " (required)";
  else if (!fallback.empty())
    line += " [" + fallback + "]";
  return line + "\n";
}

/** One row of a docs/cli.md option table: option, default, range, help. */
std::string markdownRow(const OptionSpec& option)
{
  return "| `" + markdownCell(optionLabel(option)) + "` | " +
         (option.required ? std::string("required") : markdownCell(defaultText(option))) + " | " +
         markdownCell(rangeText(option)) + " | " + markdownCell(option.help) + " |\n";
}

const char* const kMarkdownHeader = "\n| option | default | range | |\n|---|---|---|---|\n";

}  // namespace

std::string formatNumber(double value)
{
  if (std::isinf(value))
    return value > 0 ? "∞" : "-∞";
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  std::string text(buffer, result.ptr);
  const auto e = text.find('e');
  if (e == std::string::npos)
    return text;
  std::string exponent = text.substr(e + 1);  // "+06", "-09"
  const bool negative = exponent[0] == '-';
  if (exponent[0] == '+' || exponent[0] == '-')
    exponent.erase(0, 1);
  exponent.erase(0, std::min(exponent.find_first_not_of('0'), exponent.size() - 1));
  return text.substr(0, e) + "e" + (negative ? "-" : "") + exponent;
}

std::string formatInteger(long long value)
{
  if (value >= (1LL << 20) && (value & (value - 1)) == 0) {
    int power = 0;
    while ((1LL << power) != value)
      ++power;
    return "2^" + std::to_string(power);
  }
  if (value >= 1000000) {
    long long rest = value;
    int power = 0;
    while (rest % 10 == 0) {
      rest /= 10;
      ++power;
    }
    if (rest == 1)
      return "1e" + std::to_string(power);
  }
  return std::to_string(value);
}

std::string defaultText(const OptionSpec& option)
{
  if (!option.has_default)
    return option.note;
  std::string text;
  switch (option.kind) {
  case OptionKind::Integer: text = formatInteger(option.int_default); break;
  case OptionKind::Real: text = formatNumber(option.real_default); break;
  case OptionKind::Text:
  case OptionKind::Word: text = option.text_default; break;
  case OptionKind::Flag: break;
  }
  return option.note.empty() ? text : text + " (" + option.note + ")";
}

std::string rangeText(const OptionSpec& option)
{
  if (option.kind == OptionKind::Integer)
    return option.int_max == std::numeric_limits<long long>::max()
               ? "≥ " + formatInteger(option.int_min)
               : formatInteger(option.int_min) + " to " + formatInteger(option.int_max);
  if (option.kind != OptionKind::Real)
    return "";
  if (std::isinf(option.real_max))
    return (option.above_min ? "> " : "≥ ") + formatNumber(option.real_min);
  if (option.above_min)
    return "> " + formatNumber(option.real_min) + ", ≤ " + formatNumber(option.real_max);
  return formatNumber(option.real_min) + " to " + formatNumber(option.real_max);
}

std::string synopsis(const CommandSpec& spec)
{
  std::string text = "pcl_patchdict " + spec.name;
  if (!spec.positionals.empty())
    text += " " + spec.positionals;
  for (const OptionSpec& option : spec.options)
    if (option.required)
      text += (option.name == "output" ? " -o " : " --" + option.name + " ") + option.argument;
  return text + " [options]";
}

std::string commandHelp(const std::string& name)
{
  std::ostringstream out;
  for (const CommandSpec* spec : pathsOf(name)) {
    out << (spec->variant.empty() ? "usage: " : "\n   or: ") << synopsis(*spec) << "\n  " << spec->what << "\n\n"
        << (spec->variant.empty() ? "options" : "options of the " + spec->variant + " path") << ":\n";
    for (const OptionSpec& option : spec->options)
      if (!option.hidden)
        out << helpLine(option);
    for (const auto& [old_name, new_name] : spec->deprecated)
      out << "  --" << old_name << std::string(old_name.size() < 32 ? 32 - old_name.size() : 1, ' ')
          << "deprecated spelling of --" << new_name << '\n';
  }
  out << "\ncommon options:\n";
  for (const OptionSpec& option : commonOptions())
    if (&option == findOption(*pathsOf(name).front(), option.name))  // not one the command lists itself
      out << helpLine(option);
  return out.str();
}

std::string overviewHelp()
{
  std::ostringstream out;
  out << "pcl_patchdict — repair and compress 3D surfaces with learned dictionaries of height-map patches\n\n"
         "usage: pcl_patchdict COMMAND [ARGS] [OPTIONS]   (pcl_patchdict COMMAND --help: its options)\n\n"
         "commands:\n";
  for (const CommandSpec& spec : commandSpecs())
    if (spec.variant.empty())
      out << "  " << synopsis(spec) << "\n      " << spec.what << '\n';
  out << "  pcl_patchdict help [COMMAND] [--markdown]\n      this text, a command's options, or all of them as "
         "Markdown (docs/cli.md)\n\ncommon options:";
  for (const OptionSpec& option : commonOptions())
    out << ' ' << optionLabel(option);
  out << "\nformats: PLY (ascii/binary), OBJ, OFF, STL meshes; PCD and face-less PLY clouds\n";
  return out.str();
}

std::string markdownHelp()
{
  std::ostringstream out;
  out << "# The command line\n\n"
         "<!-- Generated by `pcl_patchdict help --markdown` from the option table in apps/options.cpp; the test\n"
         "     Cli.DocsMatchTheOptionTable fails when this file differs from what the tool prints. -->\n\n"
         "`pcl_patchdict COMMAND [ARGS] [OPTIONS]`; options may come before, between or after the positionals, "
         "as `--name VALUE` or `--name=VALUE`. A malformed command line (an unknown option, a value out of range, "
         "options that contradict each other or that the command would ignore) is one line on stderr and exit "
         "code 2; bad input or a failed run, one line and exit code 1. A value out of its range is refused, never "
         "clamped.\n\n"
         "| command | what it does |\n|---|---|\n";
  for (const CommandSpec& spec : commandSpecs())
    if (spec.variant.empty())
      out << "| [`" << spec.name << "`](#" << spec.name << ") | " << markdownCell(spec.what) << " |\n";
  out << "\nEvery command also takes (a command that lists one of these itself has its own default):\n"
      << kMarkdownHeader;
  for (const OptionSpec& option : commonOptions())
    out << markdownRow(option);
  for (const CommandSpec& spec : commandSpecs()) {
    if (spec.variant.empty())
      out << "\n## " << spec.name << "\n";
    else
      out << "\n### " << spec.name << " on a " << spec.variant << "\n";
    out << "\n`" << synopsis(spec) << "`\n\n" << spec.what << "\n";
    bool any = false;
    for (const OptionSpec& option : spec.options) {
      if (option.hidden)
        continue;
      if (!any)
        out << kMarkdownHeader;
      any = true;
      out << markdownRow(option);
    }
    for (const auto& [old_name, new_name] : spec.deprecated)
      out << "\n`--" << old_name << "` is still accepted as a deprecated spelling of `--" << new_name << "`.\n";
  }
  return out.str();
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
