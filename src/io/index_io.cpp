#include <pcl_patchdict/core/atomic_file.h>
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/io/index_io.h>

#include "io/formats.h"

#include <cerrno>
#include <cstdlib>
#include <sstream>

namespace pcl {
namespace patchdict {

std::vector<int> readIndexFile(const std::string& path, std::size_t num_vertices)
{
  return parseIndexFile(readWholeFile(path), num_vertices, path);
}

std::vector<int> parseIndexFile(const std::string& text, std::size_t num_vertices, const std::string& path)
{
  std::istringstream in(text);
  std::vector<int> indices;
  std::vector<char> seen(num_vertices, 0);
  std::string line;
  std::size_t line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#')
      continue;
    const auto last = line.find_last_not_of(" \t\r");
    const std::string token = line.substr(first, last - first + 1);
    const std::string where = "index file '" + path + "' line " + std::to_string(line_number) + ": ";
    errno = 0;
    char* end = nullptr;
    const long long value = std::strtoll(token.c_str(), &end, 10);
    if (end == token.c_str() || end != token.c_str() + token.size() || errno == ERANGE)
      throw Error(where + io_detail::quoted(token) + " is not an integer vertex index");
    if (value < 0)
      throw Error(where + "negative vertex index " + io_detail::quoted(token));
    if (static_cast<unsigned long long>(value) >= num_vertices)
      throw Error(where + "vertex index " + token + " is out of range (the mesh has " +
                  std::to_string(num_vertices) + " vertices)");
    if (seen[value])
      throw Error(where + "vertex index " + token + " is listed twice");
    seen[value] = 1;
    indices.push_back(static_cast<int>(value));
  }
  return indices;
}

void writeIndexFile(const std::string& path, const std::vector<int>& indices)
{
  std::ostringstream out;
  for (const int index : indices)
    out << index << '\n';
  writeFileAtomically(path, out.str());
}

}  // namespace patchdict
}  // namespace pcl
