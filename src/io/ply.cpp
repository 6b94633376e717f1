// PLY reader (ascii, binary little- and big-endian) and writer (binary little-endian or ascii).
// Every count the header declares is checked against the bytes that follow before anything is
// allocated, so a corrupt header cannot make us reserve gigabytes or read past the buffer.

#include "io/formats.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

namespace pcl {
namespace patchdict {
namespace io_detail {

namespace {

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };
enum class PlyEncoding { Ascii, BinaryLittle, BinaryBig };

bool plyTypeFromName(std::string_view name, PlyType& type)
{
  struct Entry { const char* name; PlyType type; };
  static const Entry entries[] = {
      {"char", PlyType::Int8},     {"int8", PlyType::Int8},       {"uchar", PlyType::UInt8},
      {"uint8", PlyType::UInt8},   {"short", PlyType::Int16},     {"int16", PlyType::Int16},
      {"ushort", PlyType::UInt16}, {"uint16", PlyType::UInt16},   {"int", PlyType::Int32},
      {"int32", PlyType::Int32},   {"uint", PlyType::UInt32},     {"uint32", PlyType::UInt32},
      {"float", PlyType::Float32}, {"float32", PlyType::Float32}, {"double", PlyType::Float64},
      {"float64", PlyType::Float64}};
  for (const Entry& entry : entries)
    if (name == entry.name) {
      type = entry.type;
      return true;
    }
  return false;
}

std::size_t plyTypeSize(PlyType type)
{
  switch (type) {
  case PlyType::Int8: case PlyType::UInt8: return 1;
  case PlyType::Int16: case PlyType::UInt16: return 2;
  case PlyType::Int32: case PlyType::UInt32: case PlyType::Float32: return 4;
  case PlyType::Float64: return 8;
  }
  return 0;
}

struct PlyProperty {
  std::string name;
  bool is_list = false;
  PlyType count_type = PlyType::UInt8;
  PlyType type = PlyType::Float32;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::size_t header_line = 0;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  PlyEncoding encoding = PlyEncoding::Ascii;
  std::vector<PlyElement> elements;
  std::size_t data_offset = 0;  ///< first byte after the end_header line
  std::size_t data_line = 0;    ///< line number of that byte (ascii messages)
};

PlyHeader parseHeader(const std::string& path, std::string_view bytes)
{
  PlyHeader header;
  bool have_format = false;
  std::size_t pos = 0, line_number = 0;
  for (;;) {
    if (pos >= bytes.size())
      failRead(path, line_number == 0 ? "not a PLY file" : "PLY header has no end_header line");
    const std::size_t newline = bytes.find('\n', pos);
    const std::size_t line_end = newline == std::string_view::npos ? bytes.size() : newline;
    std::string_view line = bytes.substr(pos, line_end - pos);
    pos = newline == std::string_view::npos ? bytes.size() : newline + 1;
    ++line_number;

    TextCursor cursor(line, line_number);
    std::string_view keyword;
    const bool has_keyword = cursor.next(keyword);
    if (line_number == 1) {
      if (!has_keyword || keyword != "ply" || cursor.next(keyword))
        failRead(path, "not a PLY file (it does not start with 'ply')");
      continue;
    }
    if (!has_keyword)
      continue;
    if (keyword == "comment" || keyword == "obj_info")
      continue;
    std::vector<std::string_view> words;
    for (std::string_view word; cursor.next(word);)
      words.push_back(word);
    if (keyword == "end_header") {
      if (!have_format)
        failRead(path, "PLY header has no format line");
      header.data_offset = pos;
      header.data_line = line_number + 1;
      return header;
    }
    if (keyword == "format") {
      if (words.empty())
        failReadLine(path, line_number, "format line without an encoding");
      if (words[0] == "ascii") header.encoding = PlyEncoding::Ascii;
      else if (words[0] == "binary_little_endian") header.encoding = PlyEncoding::BinaryLittle;
      else if (words[0] == "binary_big_endian") header.encoding = PlyEncoding::BinaryBig;
      else failReadLine(path, line_number, "unknown PLY format " + quoted(words[0]));
      have_format = true;
    }
    else if (keyword == "element") {
      std::int64_t count = 0;
      if (words.size() != 2 || !parseInt(words[1], count) || count < 0)
        failReadLine(path, line_number, "malformed element line");
      PlyElement element;
      element.name = std::string(words[0]);
      element.count = static_cast<std::uint64_t>(count);
      element.header_line = line_number;
      header.elements.push_back(std::move(element));
    }
    else if (keyword == "property") {
      if (header.elements.empty())
        failReadLine(path, line_number, "property before any element");
      PlyProperty property;
      if (words.size() == 4 && words[0] == "list") {
        property.is_list = true;
        if (!plyTypeFromName(words[1], property.count_type) || !plyTypeFromName(words[2], property.type))
          failReadLine(path, line_number, "unknown property type");
        if (property.count_type == PlyType::Float32 || property.count_type == PlyType::Float64)
          failReadLine(path, line_number, "list count type must be an integer type");
        property.name = std::string(words[3]);
      }
      else if (words.size() == 2) {
        if (!plyTypeFromName(words[0], property.type))
          failReadLine(path, line_number, "unknown property type " + quoted(words[0]));
        property.name = std::string(words[1]);
      }
      else {
        failReadLine(path, line_number, "malformed property line");
      }
      header.elements.back().properties.push_back(std::move(property));
    }
    else {
      failReadLine(path, line_number, "unexpected PLY header keyword " + quoted(keyword));
    }
  }
}

std::string numberText(double value)
{
  std::string text;
  appendNumber(text, value);
  return text;
}

// Decodes one binary value whatever the host's byte order is.
double decodeBinary(const unsigned char* data, PlyType type, bool big_endian)
{
  const std::size_t size = plyTypeSize(type);
  std::uint64_t bits = 0;
  for (std::size_t i = 0; i < size; ++i)
    bits |= static_cast<std::uint64_t>(data[big_endian ? i : size - 1 - i]) << (8 * (size - 1 - i));
  switch (type) {
  case PlyType::Int8: return static_cast<std::int8_t>(bits);
  case PlyType::UInt8: return static_cast<std::uint8_t>(bits);
  case PlyType::Int16: return static_cast<std::int16_t>(bits);
  case PlyType::UInt16: return static_cast<std::uint16_t>(bits);
  case PlyType::Int32: return static_cast<std::int32_t>(bits);
  case PlyType::UInt32: return static_cast<std::uint32_t>(bits);
  case PlyType::Float32: {
    const std::uint32_t bits32 = static_cast<std::uint32_t>(bits);
    float value;
    std::memcpy(&value, &bits32, 4);
    return value;
  }
  case PlyType::Float64: {
    double value;
    std::memcpy(&value, &bits, 8);
    return value;
  }
  }
  return 0.0;
}

// Reads the data section item by item, ascii or binary, with bounds checks on every value.
class PlyDataReader {
public:
  PlyDataReader(const std::string& path, std::string_view bytes, const PlyHeader& header)
      : path_(path), ascii_(header.encoding == PlyEncoding::Ascii),
        big_endian_(header.encoding == PlyEncoding::BinaryBig),
        data_(reinterpret_cast<const unsigned char*>(bytes.data()) + header.data_offset),
        end_(reinterpret_cast<const unsigned char*>(bytes.data()) + bytes.size()),
        text_(bytes.substr(header.data_offset), header.data_line) {}

  std::size_t remaining() const
  {
    return ascii_ ? text_.remaining() : static_cast<std::size_t>(end_ - data_);
  }
  bool ascii() const { return ascii_; }

  /** Next value of the given type; `what` names the item for the error message. */
  double value(PlyType type, const PlyElement& element, std::uint64_t item)
  {
    if (ascii_) {
      std::string_view token;
      if (!text_.next(token))
        truncated(element, item);
      if (type == PlyType::Float32) {
        float parsed;
        if (parseFloat(token, parsed))
          return parsed;
      }
      else {
        double parsed;
        if (parseDouble(token, parsed))
          return parsed;
      }
      failReadLine(path_, text_.line(), "bad number " + quoted(token) + " in element '" + element.name + "'");
    }
    const std::size_t size = plyTypeSize(type);
    if (static_cast<std::size_t>(end_ - data_) < size)
      truncated(element, item);
    const double result = decodeBinary(data_, type, big_endian_);
    data_ += size;
    return result;
  }

  /** A list length: a non-negative integer small enough to be backed by the remaining bytes. */
  std::size_t listCount(const PlyProperty& property, const PlyElement& element, std::uint64_t item)
  {
    const double count = value(property.count_type, element, item);
    const std::size_t min_bytes = ascii_ ? 2 : plyTypeSize(property.type);
    if (!(count >= 0.0) || count != std::floor(count) ||
        count > static_cast<double>(remaining() / min_bytes + 1))
      failRead(path_, "element '" + element.name + "' item " + std::to_string(item) +
                          ": bad or truncated list of length " + numberText(count));
    return static_cast<std::size_t>(count);
  }

  void skip(PlyType type, std::size_t n, const PlyElement& element, std::uint64_t item)
  {
    if (ascii_) {
      std::string_view token;
      for (std::size_t i = 0; i < n; ++i)
        if (!text_.next(token))
          truncated(element, item);
      return;
    }
    const std::size_t bytes = n * plyTypeSize(type);  // n was bounded by the remaining bytes
    if (static_cast<std::size_t>(end_ - data_) < bytes)
      truncated(element, item);
    data_ += bytes;
  }

  [[noreturn]] void truncated(const PlyElement& element, std::uint64_t item) const
  {
    failRead(path_, "truncated: element '" + element.name + "' ends at item " + std::to_string(item) +
                        " of " + std::to_string(element.count));
  }

  /** Rejects a declared count that the rest of the file cannot hold, before anything is allocated. */
  void checkCount(const PlyElement& element) const
  {
    std::size_t min_item = 0;
    for (const PlyProperty& property : element.properties)
      min_item += ascii_ ? 2 : plyTypeSize(property.is_list ? property.count_type : property.type);
    if (min_item == 0)
      return;
    // An ascii item of k values takes at least 2k-1 characters (digits and separators).
    const std::size_t available = remaining() + (ascii_ ? 1 : 0);
    if (element.count > available / min_item)
      failRead(path_, "truncated: element '" + element.name + "' declares " + std::to_string(element.count) +
                          " items but only " + std::to_string(remaining()) + " bytes follow the header");
  }

private:
  const std::string& path_;
  bool ascii_;
  bool big_endian_;
  const unsigned char* data_;
  const unsigned char* end_;
  TextCursor text_;
};

int findProperty(const PlyElement& element, const char* name)
{
  for (std::size_t i = 0; i < element.properties.size(); ++i)
    if (element.properties[i].name == name)
      return static_cast<int>(i);
  return -1;
}

void appendLE(std::string& out, std::uint64_t bits, std::size_t size)
{
  for (std::size_t i = 0; i < size; ++i)
    out += static_cast<char>((bits >> (8 * i)) & 0xffu);
}

void appendBinary(std::string& out, double value, bool as_float)
{
  if (as_float) {
    const float narrow = static_cast<float>(value);
    std::uint32_t bits;
    std::memcpy(&bits, &narrow, 4);
    appendLE(out, bits, 4);
  }
  else {
    std::uint64_t bits;
    std::memcpy(&bits, &value, 8);
    appendLE(out, bits, 8);
  }
}

/** Where the vertex element keeps x, y, z (scalar properties, required) and nx, ny, nz (all three
  * scalar, or no normals). */
struct PlyVertexLayout {
  const PlyElement* element = nullptr;
  int xyz[3] = {-1, -1, -1}, normal[3] = {-1, -1, -1};
  bool has_normals = true;
  std::size_t count = 0;
};

PlyVertexLayout vertexLayout(const std::string& path, const PlyHeader& header)
{
  PlyVertexLayout layout;
  for (const PlyElement& element : header.elements)
    if (element.name == "vertex") {
      if (layout.element)
        failReadLine(path, element.header_line, "a second vertex element");
      layout.element = &element;
    }
  if (!layout.element)
    failRead(path, "PLY header declares no vertex element");
  const PlyElement& vertex = *layout.element;
  const char* xyz_names[3] = {"x", "y", "z"};
  const char* normal_names[3] = {"nx", "ny", "nz"};
  for (int k = 0; k < 3; ++k) {
    layout.xyz[k] = findProperty(vertex, xyz_names[k]);
    if (layout.xyz[k] < 0 || vertex.properties[layout.xyz[k]].is_list)
      failReadLine(path, vertex.header_line,
                   std::string("vertex element has no scalar property '") + xyz_names[k] + "'");
    layout.normal[k] = findProperty(vertex, normal_names[k]);
    layout.has_normals = layout.has_normals && layout.normal[k] >= 0 && !vertex.properties[layout.normal[k]].is_list;
  }
  if (vertex.count > static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max()))
    failRead(path, "too many vertices (" + std::to_string(vertex.count) + ")");
  layout.count = static_cast<std::size_t>(vertex.count);
  return layout;
}

/** The face element's list of corners (vertex_indices, or vertex_index); room reserved for as
  * many faces as the bytes left can hold. */
int faceListProperty(const std::string& path, const PlyElement& element, const PlyDataReader& reader,
                     TriangleMesh& result)
{
  int face_list = findProperty(element, "vertex_indices");
  if (face_list < 0)
    face_list = findProperty(element, "vertex_index");
  if (face_list < 0 || !element.properties[face_list].is_list)
    failReadLine(path, element.header_line, "face element has no vertex_indices list");
  // checkCount bounded the count by the bytes left; a real face (3+ corners) needs more
  // than that bound assumes, so reserve no more than the file can actually hold.
  const PlyProperty& list = element.properties[face_list];
  const std::size_t min_face = reader.ascii() ? 2 * (element.properties.size() + 3)
                                              : plyTypeSize(list.count_type) + 3 * plyTypeSize(list.type);
  result.faces.reserve(
      std::min<std::size_t>(static_cast<std::size_t>(element.count), reader.remaining() / min_face + 1));
  return face_list;
}

/** One face's corner list (`count` indices), checked and fan-triangulated into `result`. */
void readPlyFace(const std::string& path, PlyDataReader& reader, const PlyProperty& property,
                 const PlyElement& element, std::uint64_t item, std::size_t count, std::size_t num_vertices,
                 std::vector<std::int32_t>& corners, TriangleMesh& result, ReadInfo& info)
{
  if (count < 3)
    failRead(path, "face " + std::to_string(item) + " has " + std::to_string(count) + " vertices (at least 3 needed)");
  corners.clear();
  for (std::size_t c = 0; c < count; ++c) {
    const double value = reader.value(property.type, element, item);
    if (!(value >= 0.0 && value < static_cast<double>(num_vertices)) || value != std::floor(value))
      failRead(path, "face " + std::to_string(item) + " has vertex index " + numberText(value) + " out of range (" +
                         std::to_string(num_vertices) + " vertices)");
    corners.push_back(static_cast<std::int32_t>(value));
  }
  if (count > 3)
    ++info.polygons_triangulated;
  for (std::size_t c = 2; c < count; ++c)  // fan triangulation
    result.faces.push_back({corners[0], corners[c - 1], corners[c]});
}

}  // namespace

void readPly(const std::string& path, std::string_view bytes, TriangleMesh& mesh, ReadInfo& info)
{
  const PlyHeader header = parseHeader(path, bytes);
  const PlyVertexLayout vertices = vertexLayout(path, header);
  PlyDataReader reader(path, bytes, header);
  TriangleMesh result;
  bool seen_faces = false;
  std::vector<std::int32_t> corners;
  for (const PlyElement& element : header.elements) {
    if (element.properties.empty())
      continue;  // nothing stored, and counting to a huge declared count would only waste time
    reader.checkCount(element);
    const bool is_vertex = &element == vertices.element;
    const bool is_face = element.name == "face" && !seen_faces;
    int face_list = -1;
    if (is_face) {
      seen_faces = true;
      face_list = faceListProperty(path, element, reader, result);
    }
    if (is_vertex) {
      result.vertices.resize(vertices.count);
      if (vertices.has_normals)
        result.normals.resize(vertices.count);
    }
    for (std::uint64_t item = 0; item < element.count; ++item) {
      for (std::size_t p = 0; p < element.properties.size(); ++p) {
        const PlyProperty& property = element.properties[p];
        const int index = static_cast<int>(p);
        if (!property.is_list) {
          if (!is_vertex) {
            reader.skip(property.type, 1, element, item);
            continue;
          }
          const double value = reader.value(property.type, element, item);
          for (int k = 0; k < 3; ++k) {
            if (index == vertices.xyz[k])
              result.vertices[item][k] = value;
            if (vertices.has_normals && index == vertices.normal[k])
              result.normals[item][k] = value;
          }
          continue;
        }
        const std::size_t count = reader.listCount(property, element, item);
        if (index != face_list)
          reader.skip(property.type, count, element, item);
        else
          readPlyFace(path, reader, property, element, item, count, vertices.count, corners, result, info);
      }
    }
  }
  for (std::size_t i = 0; i < result.vertices.size(); ++i)
    if (!result.vertices[i].allFinite())
      failRead(path, "vertex " + std::to_string(i) + " has a non-finite coordinate");
  // Normals are optional, derived data: a file with broken ones still gives its geometry.
  for (const Eigen::Vector3d& n : result.normals)
    if (!n.allFinite()) {
      result.normals.clear();
      break;
    }
  info.binary = !reader.ascii();
  mesh = std::move(result);
}

std::string writePly(const TriangleMesh& mesh, const WriteOptions& options)
{
  const bool with_normals = options.write_normals && mesh.hasNormals();
  // float32 when that loses nothing, so binary files of float data stay compact and still exact.
  auto all_float = [](const std::vector<Eigen::Vector3d>& points) {
    for (const Eigen::Vector3d& p : points)
      for (int k = 0; k < 3; ++k)
        if (!isFloatExact(p[k]))
          return false;
    return true;
  };
  const bool xyz_float = all_float(mesh.vertices);
  const bool normal_float = with_normals && all_float(mesh.normals);
  const bool binary = options.binary;

  std::string out = "ply\nformat ";
  out += binary ? "binary_little_endian 1.0\n" : "ascii 1.0\n";
  out += "comment written by pcl_patchdict\n";
  out += "element vertex " + std::to_string(mesh.vertices.size()) + "\n";
  for (const char* name : {"x", "y", "z"})
    out += std::string("property ") + (xyz_float ? "float " : "double ") + name + "\n";
  if (with_normals)
    for (const char* name : {"nx", "ny", "nz"})
      out += std::string("property ") + (normal_float ? "float " : "double ") + name + "\n";
  if (!mesh.faces.empty()) {
    out += "element face " + std::to_string(mesh.faces.size()) + "\n";
    out += "property list uchar int vertex_indices\n";
  }
  out += "end_header\n";

  const std::size_t vertex_bytes = (xyz_float ? 12 : 24) + (with_normals ? (normal_float ? 12 : 24) : 0);
  out.reserve(out.size() + mesh.vertices.size() * (binary ? vertex_bytes : 3 * vertex_bytes) +
              mesh.faces.size() * (binary ? 13 : 40));
  auto put = [&](double value, bool as_float) {
    if (binary)
      appendBinary(out, value, as_float);
    else if (as_float)
      appendNumber(out, static_cast<float>(value));
    else
      appendNumber(out, value);
  };
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      put(mesh.vertices[i][k], xyz_float);
      if (!binary)
        out += (k < 2 || with_normals) ? ' ' : '\n';
    }
    if (with_normals)
      for (int k = 0; k < 3; ++k) {
        put(mesh.normals[i][k], normal_float);
        if (!binary)
          out += k < 2 ? ' ' : '\n';
      }
  }
  for (const Face& face : mesh.faces) {
    if (binary) {
      out += static_cast<char>(3);
      for (const std::int32_t index : face)
        appendLE(out, static_cast<std::uint32_t>(index), 4);
    }
    else {
      out += "3 " + std::to_string(face[0]) + " " + std::to_string(face[1]) + " " +
             std::to_string(face[2]) + "\n";
    }
  }
  return out;
}

}  // namespace io_detail
}  // namespace patchdict
}  // namespace pcl
