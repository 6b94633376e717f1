// Vertex index files (IDX.txt): 0-based vertex indices, one per line, as the CLI's --missing and
// --vertices take them. Validated strictly: a bad line is an error that names it.
#pragma once

#include <string>
#include <vector>

namespace pcl {
namespace patchdict {

/** Reads the indices. Blank lines and lines starting with '#' are skipped. Throws Error (naming
  * the line) for a non-numeric entry, a negative index, an index ≥ num_vertices, or a duplicate.
  * Indices are returned in file order. */
std::vector<int> readIndexFile(const std::string& path, std::size_t num_vertices);
/** The same from the text of an index file held in memory; `name` is what error messages call it. */
std::vector<int> parseIndexFile(const std::string& text, std::size_t num_vertices, const std::string& name = "<memory>");

/** Writes one index per line (atomically: temporary file, then rename). */
void writeIndexFile(const std::string& path, const std::vector<int>& indices);

}  // namespace patchdict
}  // namespace pcl
