// Wavefront OBJ reader and writer: geometry records (v, vn, f) only; materials, groups, texture
// coordinates and free-form records are counted and ignored. Errors name the line.

#include "io/formats.h"

#include <limits>
#include <utility>
#include <vector>

namespace pcl {
namespace patchdict {
namespace io_detail {

namespace {

constexpr std::int64_t kMaxIndex = std::numeric_limits<std::int32_t>::max();

// Records that carry nothing our mesh stores. Anything else that looks like a keyword (letters and
// underscores only) is ignored as well, for extensions; a record with digits or punctuation in its
// keyword is garbage (a mangled "v1 2 3", a stray number) and rejected.
bool isIgnorableKeyword(std::string_view keyword)
{
  static const char* const known_with_digits[] = {"curv2"};
  for (const char* known : known_with_digits)
    if (keyword == known)
      return true;
  for (const char c : keyword)
    if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'))
      return false;
  return true;
}

// Positive OBJ indices may point forward (some writers emit faces first), so they are checked
// once all records are known; the first line holding the largest one is kept for the message.
struct DeferredRange {
  std::int64_t max_index = -1;  // 0-based
  std::size_t line = 0;
  void note(std::int64_t index, std::size_t line_number)
  {
    if (index > max_index) {
      max_index = index;
      line = line_number;
    }
  }
};

class ObjParser {
public:
  ObjParser(const std::string& path, ReadInfo& info) : path_(path), info_(info) {}

  void parse(std::string_view bytes)
  {
    std::size_t pos = 0;
    while (pos < bytes.size()) {
      const std::size_t newline = bytes.find('\n', pos);
      const std::size_t line_end = newline == std::string_view::npos ? bytes.size() : newline;
      ++line_;
      parseLine(bytes.substr(pos, line_end - pos));
      pos = line_end + 1;
    }
  }

  void finish(TriangleMesh& mesh)
  {
    const std::size_t num_vertices = mesh_.vertices.size();
    checkRange(vertex_range_, num_vertices, "vertex");
    checkRange(texcoord_range_, texcoord_count_, "texture coordinate");
    checkRange(normal_range_, normal_list_.size(), "normal");
    if (!normal_list_.empty()) {
      // OBJ gives normals per face corner; we keep one per vertex: the first corner's, or the
      // i-th normal when the file has exactly one per vertex (as our writer does, and as clouds do).
      std::vector<bool> assigned(num_vertices, false);
      mesh_.normals.assign(num_vertices, Eigen::Vector3d::Zero());
      for (const auto& [vertex, normal] : corner_normals_)
        if (!assigned[vertex]) {
          assigned[vertex] = true;
          mesh_.normals[vertex] = normal_list_[normal];
        }
      const bool one_per_vertex = normal_list_.size() == num_vertices;
      for (std::size_t i = 0; i < num_vertices && !mesh_.normals.empty(); ++i)
        if (!assigned[i]) {
          if (one_per_vertex)
            mesh_.normals[i] = normal_list_[i];
          else
            mesh_.normals.clear();
        }
      // Normals are optional, derived data: broken ones are dropped rather than failing the file.
      for (const Eigen::Vector3d& n : mesh_.normals)
        if (!n.allFinite()) {
          mesh_.normals.clear();
          break;
        }
    }
    mesh = std::move(mesh_);
  }

private:
  [[noreturn]] void fail(const std::string& what) const { failReadLine(path_, line_, what); }

  void checkRange(const DeferredRange& range, std::size_t count, const char* what) const
  {
    if (range.max_index >= static_cast<std::int64_t>(count))
      failReadLine(path_, range.line, std::string(what) + " index " + std::to_string(range.max_index + 1) +
                                          " is out of range (" + std::to_string(count) + " defined)");
  }

  void readVector(TextCursor& cursor, Eigen::Vector3d& out, const char* record)
  {
    std::string_view token;
    for (int k = 0; k < 3; ++k) {
      if (!cursor.nextOnLine(token))
        fail(std::string("'") + record + "' record needs 3 coordinates");
      if (!parseDouble(token, out[k]))
        fail("bad number " + quoted(token) + " in '" + record + "' record");
    }
    // Extra values (v's w or vertex colours) are allowed but must still be numbers.
    double ignored;
    while (cursor.nextOnLine(token))
      if (!parseDouble(token, ignored))
        fail("bad number " + quoted(token) + " in '" + record + "' record");
  }

  // OBJ indices: 1-based, or negative = relative to the elements defined so far.
  std::int64_t resolve(std::string_view text, std::size_t defined, DeferredRange& range, const char* what)
  {
    std::int64_t index = 0;
    if (!parseInt(text, index))
      fail(std::string("bad ") + what + " index " + quoted(text));
    if (index == 0)
      fail(std::string(what) + " index 0 is invalid (OBJ indices start at 1)");
    if (index < 0) {
      const std::int64_t absolute = static_cast<std::int64_t>(defined) + index;
      if (absolute < 0)
        fail(std::string("relative ") + what + " index " + std::to_string(index) + " is out of range (" +
             std::to_string(defined) + " defined so far)");
      return absolute;
    }
    if (index > kMaxIndex)
      fail(std::string(what) + " index " + std::to_string(index) + " is out of range");
    range.note(index - 1, line_);
    return index - 1;
  }

  void readFace(TextCursor& cursor)
  {
    corners_.clear();
    std::string_view token;
    while (cursor.nextOnLine(token)) {
      std::string_view parts[3];
      int num_parts = 0;
      std::size_t start = 0;
      for (;;) {
        const std::size_t slash = token.find('/', start);
        if (num_parts == 3)
          fail("bad face corner " + quoted(token));
        parts[num_parts++] = token.substr(start, slash == std::string_view::npos ? slash : slash - start);
        if (slash == std::string_view::npos)
          break;
        start = slash + 1;
      }
      const std::int64_t vertex = resolve(parts[0], mesh_.vertices.size(), vertex_range_, "vertex");
      if (num_parts >= 2 && !parts[1].empty())
        resolve(parts[1], texcoord_count_, texcoord_range_, "texture coordinate");
      if (num_parts == 3) {
        const std::int64_t normal = resolve(parts[2], normal_list_.size(), normal_range_, "normal");
        corner_normals_.emplace_back(static_cast<std::size_t>(vertex), static_cast<std::size_t>(normal));
      }
      corners_.push_back(static_cast<std::int32_t>(vertex));
    }
    if (corners_.size() < 3)
      fail("face with " + std::to_string(corners_.size()) + " vertices (at least 3 needed)");
    if (corners_.size() > 3)
      ++info_.polygons_triangulated;
    for (std::size_t c = 2; c < corners_.size(); ++c)  // fan triangulation
      mesh_.faces.push_back({corners_[0], corners_[c - 1], corners_[c]});
  }

  void parseLine(std::string_view line)
  {
    TextCursor cursor(line, line_, '#');
    std::string_view keyword;
    if (!cursor.nextOnLine(keyword))
      return;  // blank or comment
    if (keyword == "v") {
      if (mesh_.vertices.size() >= static_cast<std::size_t>(kMaxIndex))
        fail("too many vertices");
      Eigen::Vector3d position;
      readVector(cursor, position, "v");
      if (!position.allFinite())
        fail("vertex " + std::to_string(mesh_.vertices.size()) + " has a non-finite coordinate");
      mesh_.vertices.push_back(position);
    }
    else if (keyword == "vn") {
      Eigen::Vector3d normal;
      readVector(cursor, normal, "vn");
      normal_list_.push_back(normal);
    }
    else if (keyword == "f") {
      readFace(cursor);
    }
    else if (keyword == "vt") {
      ++texcoord_count_;
      ++info_.lines_ignored;
    }
    else if (isIgnorableKeyword(keyword)) {
      ++info_.lines_ignored;
    }
    else {
      fail("unknown record " + quoted(keyword));
    }
  }

  const std::string& path_;
  ReadInfo& info_;
  std::size_t line_ = 0;
  TriangleMesh mesh_;
  std::vector<Eigen::Vector3d> normal_list_;
  std::size_t texcoord_count_ = 0;
  std::vector<std::pair<std::size_t, std::size_t>> corner_normals_;  // (vertex, normal), 0-based
  std::vector<std::int32_t> corners_;
  DeferredRange vertex_range_, texcoord_range_, normal_range_;
};

}  // namespace

void readObj(const std::string& path, std::string_view bytes, TriangleMesh& mesh, ReadInfo& info)
{
  ObjParser parser(path, info);
  parser.parse(bytes);
  parser.finish(mesh);
}

std::string writeObj(const TriangleMesh& mesh, const WriteOptions& options)
{
  const bool with_normals = options.write_normals && mesh.hasNormals();
  std::string out = "# written by pcl_patchdict\n";
  out.reserve(mesh.vertices.size() * (with_normals ? 120 : 60) + mesh.faces.size() * 40);
  for (const Eigen::Vector3d& v : mesh.vertices) {
    out += "v ";
    appendVector(out, v);
  }
  if (with_normals)
    for (const Eigen::Vector3d& n : mesh.normals) {
      out += "vn ";
      appendVector(out, n);
    }
  for (const Face& face : mesh.faces) {
    out += 'f';
    for (const std::int32_t index : face) {
      const std::string one_based = std::to_string(index + 1);
      out += ' ';
      out += one_based;
      if (with_normals) {
        out += "//";
        out += one_based;
      }
    }
    out += '\n';
  }
  return out;
}

}  // namespace io_detail
}  // namespace patchdict
}  // namespace pcl
