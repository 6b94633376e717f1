// STL reader (binary and ASCII) and writer (binary float32, or ASCII with exact doubles).
// STL stores a soup of triangles; identical positions (bit for bit) are merged into one vertex,
// numbered in order of first appearance, to give an indexed mesh.

#include "io/formats.h"

#include <cstring>
#include <limits>
#include <unordered_map>
#include <vector>

namespace pcl {
namespace patchdict {
namespace io_detail {

namespace {

constexpr std::size_t kHeaderBytes = 84;  // 80-byte comment + uint32 triangle count
constexpr std::size_t kFacetBytes = 50;   // normal + 3 corners (12 float32) + uint16 attribute

struct BitKey {
  std::uint64_t bits[3];
  bool operator==(const BitKey& other) const
  {
    return bits[0] == other.bits[0] && bits[1] == other.bits[1] && bits[2] == other.bits[2];
  }
};

struct BitKeyHash {
  std::size_t operator()(const BitKey& key) const
  {
    std::uint64_t h = 0x9e3779b97f4a7c15ull;
    for (const std::uint64_t b : key.bits) {
      h ^= b + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
      h *= 0xff51afd7ed558ccdull;
    }
    return static_cast<std::size_t>(h ^ (h >> 33));
  }
};

// Merges corners by exact bit pattern: -0.0 and 0.0 stay apart, nothing within a tolerance is
// merged (that would be a geometric decision, and hygiene belongs to another module).
class VertexWelder {
public:
  explicit VertexWelder(std::size_t expected_corners) { index_.reserve(expected_corners / 4 + 16); }

  std::int32_t add(const Eigen::Vector3d& position, TriangleMesh& mesh)
  {
    BitKey key;
    for (int k = 0; k < 3; ++k)
      std::memcpy(&key.bits[k], &position[k], 8);
    const auto [it, inserted] = index_.emplace(key, static_cast<std::int32_t>(mesh.vertices.size()));
    if (inserted)
      mesh.vertices.push_back(position);
    return it->second;
  }

private:
  std::unordered_map<BitKey, std::int32_t, BitKeyHash> index_;
};

float loadFloatLE(const unsigned char* data)
{
  const std::uint32_t bits = static_cast<std::uint32_t>(data[0]) | (static_cast<std::uint32_t>(data[1]) << 8) |
                             (static_cast<std::uint32_t>(data[2]) << 16) |
                             (static_cast<std::uint32_t>(data[3]) << 24);
  float value;
  std::memcpy(&value, &bits, 4);
  return value;
}

void appendFloatLE(std::string& out, float value)
{
  std::uint32_t bits;
  std::memcpy(&bits, &value, 4);
  for (int i = 0; i < 4; ++i)
    out += static_cast<char>((bits >> (8 * i)) & 0xffu);
}

void readBinary(const std::string& path, std::string_view bytes, TriangleMesh& mesh)
{
  if (bytes.size() < kHeaderBytes)
    failRead(path, "truncated binary STL (" + std::to_string(bytes.size()) + " bytes, header needs 84)");
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const std::uint64_t count = static_cast<std::uint64_t>(data[80]) | (static_cast<std::uint64_t>(data[81]) << 8) |
                              (static_cast<std::uint64_t>(data[82]) << 16) |
                              (static_cast<std::uint64_t>(data[83]) << 24);
  // Trailing bytes after the facets are tolerated (some exporters pad); missing ones are not.
  if (count > (bytes.size() - kHeaderBytes) / kFacetBytes)
    failRead(path, "truncated binary STL: " + std::to_string(count) + " triangles declared, room for " +
                       std::to_string((bytes.size() - kHeaderBytes) / kFacetBytes));
  if (count * 3 > static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max()))
    failRead(path, "too many triangles (" + std::to_string(count) + ")");
  VertexWelder welder(count * 3);
  mesh.faces.reserve(count);
  for (std::uint64_t t = 0; t < count; ++t) {
    const unsigned char* facet = data + kHeaderBytes + t * kFacetBytes;
    Face face;
    for (int c = 0; c < 3; ++c) {
      Eigen::Vector3d position;
      for (int k = 0; k < 3; ++k)
        position[k] = loadFloatLE(facet + 12 + 12 * c + 4 * k);
      if (!position.allFinite())
        failRead(path, "triangle " + std::to_string(t) + " has a non-finite coordinate");
      face[c] = welder.add(position, mesh);
    }
    mesh.faces.push_back(face);
  }
}

void readAscii(const std::string& path, std::string_view bytes, TriangleMesh& mesh, ReadInfo& info)
{
  TextCursor cursor(bytes);
  std::string_view token;
  auto expect = [&](const char* word) {
    if (!cursor.next(token))
      failRead(path, std::string("truncated ASCII STL: expected '") + word + "'");
    if (token != word)
      failReadLine(path, cursor.line(), std::string("expected '") + word + "', found " + quoted(token));
  };
  auto number = [&]() {
    double value = 0.0;
    if (!cursor.next(token))
      failRead(path, "truncated ASCII STL: expected a number");
    if (!parseDouble(token, value))
      failReadLine(path, cursor.line(), "bad number " + quoted(token));
    return value;
  };
  VertexWelder welder(bytes.size() / 40);
  std::vector<std::int32_t> corners;
  bool in_solid = false;
  std::size_t facet_index = 0;
  while (cursor.next(token)) {
    if (!in_solid) {
      // Several solids may follow each other; each opens with "solid [name]".
      if (token != "solid")
        failReadLine(path, cursor.line(), "expected 'solid', found " + quoted(token));
      cursor.skipLine();
      in_solid = true;
      continue;
    }
    if (token == "endsolid") {
      cursor.skipLine();
      in_solid = false;
      continue;
    }
    if (token != "facet")
      failReadLine(path, cursor.line(), "expected 'facet' or 'endsolid', found " + quoted(token));
    expect("normal");
    for (int k = 0; k < 3; ++k)
      number();  // facet normals are per face; ours are per vertex
    expect("outer");
    expect("loop");
    corners.clear();
    for (;;) {
      if (!cursor.next(token))
        failRead(path, "truncated ASCII STL: facet without 'endloop'");
      if (token == "endloop")
        break;
      if (token != "vertex")
        failReadLine(path, cursor.line(), "expected 'vertex' or 'endloop', found " + quoted(token));
      const std::size_t line = cursor.line();
      Eigen::Vector3d position;
      for (int k = 0; k < 3; ++k)
        position[k] = number();
      if (!position.allFinite())
        failReadLine(path, line, "triangle " + std::to_string(facet_index) + " has a non-finite coordinate");
      if (mesh.vertices.size() >= static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
        failRead(path, "too many vertices");
      corners.push_back(welder.add(position, mesh));
    }
    if (corners.size() < 3)
      failReadLine(path, cursor.line(), "facet with " + std::to_string(corners.size()) +
                                            " vertices (at least 3 needed)");
    expect("endfacet");
    if (corners.size() > 3)
      ++info.polygons_triangulated;
    for (std::size_t c = 2; c < corners.size(); ++c)  // fan triangulation
      mesh.faces.push_back({corners[0], corners[c - 1], corners[c]});
    ++facet_index;
  }
  if (in_solid)
    failRead(path, "truncated ASCII STL: no 'endsolid'");
}

bool looksAscii(std::string_view bytes)
{
  TextCursor cursor(bytes);
  std::string_view token;
  if (!cursor.next(token) || token != "solid")
    return false;
  // Binary files may start with "solid" too (some exporters do it), but then their size matches
  // the binary layout exactly; an ASCII file also has "facet" (or "endsolid" if empty) next.
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  if (bytes.size() >= kHeaderBytes) {
    const std::uint64_t count = static_cast<std::uint64_t>(data[80]) | (static_cast<std::uint64_t>(data[81]) << 8) |
                                (static_cast<std::uint64_t>(data[82]) << 16) |
                                (static_cast<std::uint64_t>(data[83]) << 24);
    if (bytes.size() == kHeaderBytes + count * kFacetBytes)
      return false;
  }
  cursor.skipLine();
  return cursor.next(token) && (token == "facet" || token == "endsolid");
}

}  // namespace

void readStl(const std::string& path, std::string_view bytes, TriangleMesh& mesh, ReadInfo& info)
{
  TriangleMesh result;
  info.binary = !looksAscii(bytes);
  if (info.binary)
    readBinary(path, bytes, result);
  else
    readAscii(path, bytes, result, info);
  mesh = std::move(result);
}

std::string writeStl(const TriangleMesh& mesh, const WriteOptions& options)
{
  std::string out;
  if (options.binary) {
    // The header must not begin with "solid", or readers might take the file for ASCII.
    std::string header = "binary STL written by pcl_patchdict";
    header.resize(80, ' ');
    out.reserve(kHeaderBytes + mesh.faces.size() * kFacetBytes);
    out += header;
    const std::uint32_t count = static_cast<std::uint32_t>(mesh.faces.size());
    for (int i = 0; i < 4; ++i)
      out += static_cast<char>((count >> (8 * i)) & 0xffu);
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
      const Eigen::Vector3d normal = mesh.faceNormal(f);
      for (int k = 0; k < 3; ++k)
        appendFloatLE(out, static_cast<float>(normal[k]));
      for (const std::int32_t index : mesh.faces[f])
        for (int k = 0; k < 3; ++k)
          appendFloatLE(out, static_cast<float>(mesh.vertices[index][k]));
      out += '\0';
      out += '\0';
    }
    return out;
  }
  out = "solid pcl_patchdict\n";
  out.reserve(mesh.faces.size() * 250);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const Eigen::Vector3d normal = mesh.faceNormal(f);
    out += "facet normal ";
    for (int k = 0; k < 3; ++k) {
      appendNumber(out, normal[k]);
      out += k < 2 ? ' ' : '\n';
    }
    out += " outer loop\n";
    for (const std::int32_t index : mesh.faces[f]) {
      out += "  vertex ";
      for (int k = 0; k < 3; ++k) {
        appendNumber(out, mesh.vertices[index][k]);
        out += k < 2 ? ' ' : '\n';
      }
    }
    out += " endloop\nendfacet\n";
  }
  out += "endsolid pcl_patchdict\n";
  return out;
}

}  // namespace io_detail
}  // namespace patchdict
}  // namespace pcl
