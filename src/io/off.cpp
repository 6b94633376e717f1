// OFF (Geomview Object File Format) reader and writer: OFF, NOFF (normals read), COFF/STOFF (colours
// and texture coordinates after the coordinates ignored), '#' comments, polygons fan-triangulated.

#include "io/formats.h"

#include <limits>
#include <utility>
#include <vector>

namespace pcl {
namespace patchdict {
namespace io_detail {

namespace {

// Yields the lines that hold data: comments stripped, blank lines skipped, line numbers kept.
class DataLines {
public:
  explicit DataLines(std::string_view bytes) : bytes_(bytes) {}

  bool next(TextCursor& cursor)
  {
    while (pos_ < bytes_.size()) {
      const std::size_t newline = bytes_.find('\n', pos_);
      const std::size_t line_end = newline == std::string_view::npos ? bytes_.size() : newline;
      const std::string_view line = bytes_.substr(pos_, line_end - pos_);
      pos_ = line_end + 1;
      ++line_;
      TextCursor probe(line, line_, '#');
      std::string_view token;
      if (probe.nextOnLine(token)) {
        cursor = TextCursor(line, line_, '#');
        return true;
      }
    }
    return false;
  }
  std::size_t line() const { return line_; }
  std::size_t remaining() const { return pos_ < bytes_.size() ? bytes_.size() - pos_ : 0; }

private:
  std::string_view bytes_;
  std::size_t pos_ = 0;
  std::size_t line_ = 0;
};

/** The header keyword [ST][C][N]OFF on the first data line (the cursor left after it); whether
  * the vertices carry normals. */
bool readOffKeyword(const std::string& path, DataLines& lines, TextCursor& cursor)
{
  std::string_view token;
  if (!lines.next(cursor) || !cursor.nextOnLine(token))
    failRead(path, "not an OFF file (no header)");
  if (token.size() < 3 || token.substr(token.size() - 3) != "OFF")
    failReadLine(path, lines.line(), "not an OFF file (header " + quoted(token) + ")");
  std::string_view prefix = token.substr(0, token.size() - 3);
  auto take = [&prefix](std::string_view part) {
    if (prefix.substr(0, part.size()) != part)
      return false;
    prefix.remove_prefix(part.size());
    return true;
  };
  take("ST");
  take("C");
  const bool has_normals = take("N");
  if (!prefix.empty())
    failReadLine(path, lines.line(), "unsupported OFF variant " + quoted(token) + " (only [ST][C][N]OFF)");
  return has_normals;
}

/** The vertex and face counts, on the header line or on the next data line; checked against the
  * bytes that follow before anything is allocated. */
std::pair<std::uint64_t, std::uint64_t> readOffCounts(const std::string& path, DataLines& lines, TextCursor& cursor)
{
  std::string_view token;
  std::int64_t counts[3] = {0, 0, 0};
  int num_counts = 0;
  if (!cursor.nextOnLine(token) && (!lines.next(cursor) || !cursor.nextOnLine(token)))
    failRead(path, "truncated: no vertex/face counts after the OFF header");
  do {
    if (token == "BINARY")
      failReadLine(path, lines.line(), "binary OFF is not supported");
    if (num_counts == 3 || !parseInt(token, counts[num_counts]) || counts[num_counts] < 0)
      failReadLine(path, lines.line(), "bad OFF counts line (expected: vertices faces [edges])");
    ++num_counts;
  } while (cursor.nextOnLine(token));
  if (num_counts < 2)
    failReadLine(path, lines.line(), "bad OFF counts line (expected: vertices faces [edges])");
  const std::uint64_t num_vertices = static_cast<std::uint64_t>(counts[0]);
  const std::uint64_t num_faces = static_cast<std::uint64_t>(counts[1]);
  if (num_vertices > static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max()))
    failRead(path, "too many vertices (" + std::to_string(num_vertices) + ")");
  // Before allocating: a vertex line is at least "0 0 0" plus a separator, a face "3 0 0 0".
  const std::uint64_t remaining = lines.remaining();
  if (num_vertices > remaining / 6 + 1 || num_faces > remaining / 8 + 1 ||
      num_vertices * 6 + num_faces * 8 > remaining + 2)
    failRead(path, "truncated: the header declares " + std::to_string(num_vertices) + " vertices and " +
                       std::to_string(num_faces) + " faces but only " + std::to_string(remaining) +
                       " bytes follow");
  return {num_vertices, num_faces};
}

/** One vertex a line: x y z (and nx ny nz with normals); whatever follows is not ours to keep. */
void readOffVertices(const std::string& path, DataLines& lines, TextCursor& cursor, std::uint64_t num_vertices,
                     bool has_normals, TriangleMesh& result)
{
  std::string_view token;
  result.vertices.resize(num_vertices);
  if (has_normals)
    result.normals.resize(num_vertices);
  const int values_per_vertex = has_normals ? 6 : 3;
  for (std::size_t i = 0; i < num_vertices; ++i) {
    if (!lines.next(cursor))
      failRead(path, "truncated: " + std::to_string(i) + " of " + std::to_string(num_vertices) +
                         " vertices present");
    for (int k = 0; k < values_per_vertex; ++k) {
      double value = 0.0;
      if (!cursor.nextOnLine(token))
        failReadLine(path, lines.line(), "vertex line needs " + std::to_string(values_per_vertex) + " numbers");
      if (!parseDouble(token, value))
        failReadLine(path, lines.line(), "bad number " + quoted(token));
      if (k < 3)
        result.vertices[i][k] = value;
      else
        result.normals[i][k - 3] = value;
    }
    if (!result.vertices[i].allFinite())
      failReadLine(path, lines.line(), "vertex " + std::to_string(i) + " has a non-finite coordinate");
  }
}

/** One face a line: its corner count and indices, fan-triangulated. */
void readOffFaces(const std::string& path, DataLines& lines, TextCursor& cursor, std::uint64_t num_vertices,
                  std::uint64_t num_faces, TriangleMesh& result, ReadInfo& info)
{
  std::string_view token;
  result.faces.reserve(num_faces);
  std::vector<std::int32_t> corners;
  for (std::size_t f = 0; f < num_faces; ++f) {
    if (!lines.next(cursor))
      failRead(path, "truncated: " + std::to_string(f) + " of " + std::to_string(num_faces) + " faces present");
    std::int64_t count = 0;
    if (!cursor.nextOnLine(token) || !parseInt(token, count))
      failReadLine(path, lines.line(), "bad face line");
    if (count < 3)
      failReadLine(path, lines.line(), "face with " + std::to_string(count) + " vertices (at least 3 needed)");
    corners.clear();
    for (std::int64_t c = 0; c < count; ++c) {
      std::int64_t index = 0;
      if (!cursor.nextOnLine(token))
        failReadLine(path, lines.line(), "face line has fewer indices than its count");
      if (!parseInt(token, index))
        failReadLine(path, lines.line(), "bad vertex index " + quoted(token));
      if (index < 0 || static_cast<std::uint64_t>(index) >= num_vertices)
        failReadLine(path, lines.line(), "vertex index " + std::to_string(index) + " is out of range (" +
                                             std::to_string(num_vertices) + " vertices)");
      corners.push_back(static_cast<std::int32_t>(index));
    }
    if (count > 3)
      ++info.polygons_triangulated;
    for (std::size_t c = 2; c < corners.size(); ++c)  // fan triangulation
      result.faces.push_back({corners[0], corners[c - 1], corners[c]});
  }
}

}  // namespace

void readOff(const std::string& path, std::string_view bytes, TriangleMesh& mesh, ReadInfo& info)
{
  DataLines lines(bytes);
  TextCursor cursor(std::string_view{}, 0);
  const bool has_normals = readOffKeyword(path, lines, cursor);
  const auto [num_vertices, num_faces] = readOffCounts(path, lines, cursor);
  TriangleMesh result;
  readOffVertices(path, lines, cursor, num_vertices, has_normals, result);
  readOffFaces(path, lines, cursor, num_vertices, num_faces, result, info);
  // Normals are optional, derived data: broken ones are dropped rather than failing the file.
  for (const Eigen::Vector3d& n : result.normals)
    if (!n.allFinite()) {
      result.normals.clear();
      break;
    }
  info.binary = false;
  mesh = std::move(result);
}

std::string writeOff(const TriangleMesh& mesh, const WriteOptions&)
{
  std::string out = "OFF\n# written by pcl_patchdict\n";
  out += std::to_string(mesh.vertices.size()) + " " + std::to_string(mesh.faces.size()) + " 0\n";
  out.reserve(out.size() + mesh.vertices.size() * 60 + mesh.faces.size() * 40);
  for (const Eigen::Vector3d& v : mesh.vertices)
    appendVector(out, v);
  for (const Face& face : mesh.faces)
    out += "3 " + std::to_string(face[0]) + " " + std::to_string(face[1]) + " " + std::to_string(face[2]) + "\n";
  return out;
}

}  // namespace io_detail
}  // namespace patchdict
}  // namespace pcl
