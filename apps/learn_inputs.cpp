#include "learn_inputs.h"

#include <pcl_patchdict/core/checksum.h>
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict/coding/patch_dictionary.h>

#include <glob.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>

namespace pcl {
namespace patchdict {
namespace cli {

namespace {

namespace fs = std::filesystem;

bool isLearnable(const std::string& path)
{
  return isPatchSetPath(path) || formatFromPath(path) != MeshFormat::Unknown;
}

bool hasGlobCharacters(const std::string& text)
{
  return text.find_first_of("*?[") != std::string::npos;
}

void expandDirectory(const std::string& directory, LearnInputs& out)
{
  std::vector<std::string> found;
  std::error_code error;
  for (fs::directory_iterator it(directory, error), end; !error && it != end; it.increment(error)) {
    std::error_code type_error;
    if (!it->is_regular_file(type_error))
      continue;
    const std::string name = it->path().filename().string();
    if (!name.empty() && name[0] == '.')
      continue;  // hidden files and the temporary files of atomic writes
    if (isLearnable(name))
      found.push_back(it->path().string());
    else
      ++out.ignored;
  }
  if (error)
    throw Error("cannot list the folder '" + directory + "': " + error.message());
  if (found.empty())
    throw Error("the folder '" + directory + "' holds no .pds, PLY, OBJ, OFF, STL or PCD file");
  std::sort(found.begin(), found.end());
  out.paths.insert(out.paths.end(), found.begin(), found.end());
  out.expanded = true;
}

void expandGlob(const std::string& pattern, LearnInputs& out)
{
  glob_t matches{};
  const int status = glob(pattern.c_str(), GLOB_NOSORT, nullptr, &matches);
  std::vector<std::string> found;
  if (status == 0)
    for (std::size_t i = 0; i < matches.gl_pathc; ++i)
      found.emplace_back(matches.gl_pathv[i]);
  globfree(&matches);
  if (status == GLOB_NOMATCH || (status == 0 && found.empty()))
    throw Error("the pattern '" + pattern + "' matches no file");
  if (status != 0)
    throw Error("cannot expand the pattern '" + pattern + "' (read error)");
  std::sort(found.begin(), found.end());
  for (const std::string& path : found) {
    std::error_code error;
    if (fs::is_directory(path, error))
      expandDirectory(path, out);
    else
      out.paths.push_back(path);
  }
  out.expanded = true;
}

void expandOne(const std::string& argument, LearnInputs& out)
{
  std::error_code error;
  if (fs::is_directory(argument, error))
    expandDirectory(argument, out);
  else if (hasGlobCharacters(argument) && !fs::exists(argument, error))
    expandGlob(argument, out);
  else
    out.paths.push_back(argument);
}

std::string trimmed(const std::string& line)
{
  std::size_t begin = 0, end = line.size();
  while (begin < end && std::isspace(static_cast<unsigned char>(line[begin])))
    ++begin;
  while (end > begin && std::isspace(static_cast<unsigned char>(line[end - 1])))
    --end;
  return line.substr(begin, end - begin);
}

void expandList(const std::string& list, LearnInputs& out)
{
  std::error_code error;
  if (fs::is_directory(list, error))
    throw Error("cannot read the list '" + list + "': it is a folder");
  std::ifstream in(list);
  if (!in)
    throw Error("cannot read the list '" + list + "': no such file or not readable");
  const fs::path folder = fs::path(list).parent_path();
  const std::size_t before = out.paths.size();
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::string entry = trimmed(line);
    if (entry.empty() || entry[0] == '#')
      continue;
    if (entry[0] == '@')
      throw Error("'" + list + "' line " + std::to_string(number) + ": lists cannot name other lists");
    const fs::path path(entry);
    expandOne(path.is_absolute() || folder.empty() ? entry : (folder / path).string(), out);
  }
  if (in.bad())
    throw Error("cannot read the list '" + list + "': read error");
  if (out.paths.size() == before)
    throw Error("the list '" + list + "' names no input");
  out.expanded = true;
}

}  // namespace

bool isPatchSetPath(const std::string& path)
{
  const std::string extension = fs::path(path).extension().string();
  std::string lower(extension);
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  return lower == ".pds";
}

LearnInputs expandLearnInputs(const std::vector<std::string>& arguments)
{
  LearnInputs out;
  for (const std::string& argument : arguments) {
    if (argument.size() > 1 && argument[0] == '@')
      expandList(argument.substr(1), out);
    else
      expandOne(argument, out);
  }
  return out;
}

std::uint64_t fingerprintInputs(const std::vector<std::string>& paths)
{
  std::uint64_t hash = fnv1a64(nullptr, 0);
  for (const std::string& path : paths) {
    std::error_code error;
    const std::string absolute = fs::absolute(path, error).lexically_normal().string();
    const std::string& name = error ? path : absolute;
    hash = fnv1a64(name.data(), name.size() + 1, hash);  // with the terminating NUL as separator
    const std::uintmax_t size = fs::file_size(path, error);
    const std::uint64_t stored_size = error ? ~0ULL : static_cast<std::uint64_t>(size);
    hash = fnv1a64(&stored_size, sizeof stored_size, hash);
  }
  return hash;
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
