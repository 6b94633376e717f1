// Mesh and cloud I/O: dispatch on the file extension, checks shared by all formats, atomic writes.
//
// Why our own PLY/OBJ/OFF/STL readers and writers rather than PCL's: PCL's PLY and OBJ writers print
// 5 significant digits by default, which moves every vertex (we need exact round trips); PCL has no
// OFF reader; and we need every truncated or garbage file to fail with one clear line (with a line
// number for text formats), never a crash, a hang or a huge allocation. PCD, PCL's own format, goes
// through pcl::io.

#include "io/formats.h"

#include <pcl_patchdict/core/atomic_file.h>

#include <atomic>
#include <cerrno>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include <fcntl.h>
#include <unistd.h>

namespace pcl {
namespace patchdict {

namespace fs = std::filesystem;

namespace io_detail {

void failRead(const std::string& path, const std::string& what)
{
  throw Error("cannot read '" + path + "': " + what);
}

void failReadLine(const std::string& path, std::size_t line, const std::string& what)
{
  throw Error("cannot read '" + path + "': line " + std::to_string(line) + ": " + what);
}

std::string quoted(std::string_view token)
{
  constexpr std::size_t max_length = 24;
  std::string out = "'";
  for (std::size_t i = 0; i < token.size() && i < max_length; ++i) {
    const unsigned char c = static_cast<unsigned char>(token[i]);
    out += (c < 0x20 || c >= 0x7f) ? '?' : static_cast<char>(c);
  }
  if (token.size() > max_length)
    out += "...";
  return out + "'";
}

namespace {

template <typename Real>
bool parseReal(std::string_view token, Real& value)
{
  const char* first = token.data();
  const char* last = first + token.size();
  // from_chars rejects a leading '+', which some writers emit.
  if (first != last && *first == '+') {
    ++first;
    if (first != last && (*first == '+' || *first == '-'))
      return false;
  }
  if (first == last)
    return false;
  Real parsed{};
  const auto result = std::from_chars(first, last, parsed);
  if (result.ptr != last)
    return false;
  if (result.ec == std::errc::result_out_of_range) {
    // from_chars leaves the value untouched on over/underflow; strtod gives ±inf / ±0 as wanted.
    const std::string copy(first, last);
    if constexpr (std::is_same_v<Real, float>)
      parsed = std::strtof(copy.c_str(), nullptr);
    else
      parsed = std::strtod(copy.c_str(), nullptr);
  }
  else if (result.ec != std::errc()) {
    return false;
  }
  value = parsed;
  return true;
}

}  // namespace

bool parseDouble(std::string_view token, double& value) { return parseReal(token, value); }
bool parseFloat(std::string_view token, float& value) { return parseReal(token, value); }

bool parseInt(std::string_view token, std::int64_t& value)
{
  const char* first = token.data();
  const char* last = first + token.size();
  if (first != last && *first == '+') {
    ++first;
    if (first != last && *first == '-')
      return false;
  }
  if (first == last)
    return false;
  const auto result = std::from_chars(first, last, value);
  return result.ec == std::errc() && result.ptr == last;
}

void appendNumber(std::string& out, double value)
{
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, result.ptr);
}

void appendVector(std::string& out, const Eigen::Vector3d& v, char end)
{
  appendNumber(out, v.x());
  out += ' ';
  appendNumber(out, v.y());
  out += ' ';
  appendNumber(out, v.z());
  out += end;
}

void appendNumber(std::string& out, float value)
{
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, result.ptr);
}

bool isFloatExact(double value)
{
  // The range test comes first: casting an out-of-range double to float is undefined behaviour.
  return std::isfinite(value) && std::fabs(value) <= static_cast<double>(FLT_MAX) &&
         static_cast<double>(static_cast<float>(value)) == value;
}

namespace {
bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }
}  // namespace

bool TextCursor::next(std::string_view& token)
{
  for (;;) {
    while (pos_ != end_ && (isBlank(*pos_) || *pos_ == '\n')) {
      if (*pos_ == '\n')
        ++line_;
      ++pos_;
    }
    if (pos_ != end_ && comment_ != 0 && *pos_ == comment_) {
      while (pos_ != end_ && *pos_ != '\n')
        ++pos_;
      continue;
    }
    break;
  }
  if (pos_ == end_)
    return false;
  token = takeToken();
  return true;
}

std::string_view TextCursor::takeToken()
{
  const char* start = pos_;
  while (pos_ != end_ && !isBlank(*pos_) && *pos_ != '\n' && !(comment_ != 0 && *pos_ == comment_))
    ++pos_;
  return std::string_view(start, static_cast<std::size_t>(pos_ - start));
}

bool TextCursor::nextOnLine(std::string_view& token)
{
  while (pos_ != end_ && isBlank(*pos_))
    ++pos_;
  if (pos_ != end_ && comment_ != 0 && *pos_ == comment_)
    while (pos_ != end_ && *pos_ != '\n')
      ++pos_;
  if (pos_ == end_ || *pos_ == '\n')
    return false;
  token = takeToken();
  return true;
}

void TextCursor::skipLine()
{
  while (pos_ != end_ && *pos_ != '\n')
    ++pos_;
  if (pos_ != end_) {
    ++pos_;
    ++line_;
  }
}

}  // namespace io_detail

// ---------------------------------------------------------------- dispatch

namespace {

const char* const kSupported = "supported: .ply .obj .off .stl .pcd";

std::string lowerExtension(const std::string& path)
{
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext)
    if (c >= 'A' && c <= 'Z')
      c = static_cast<char>(c - 'A' + 'a');
  return ext;
}

[[noreturn]] void failWrite(const std::string& path, const std::string& what)
{
  throw Error("cannot write '" + path + "': " + what);
}

// Checks that make a written file readable again; the readers reject all of these.
void validateForWrite(const std::string& path, const TriangleMesh& mesh, MeshFormat format,
                      bool with_normals)
{
  const std::size_t n = mesh.vertices.size();
  if (n == 0)
    failWrite(path, "the mesh is empty (no vertices)");
  const bool float32_only = format == MeshFormat::PCD || format == MeshFormat::STL;
  for (std::size_t i = 0; i < n; ++i) {
    if (!mesh.vertices[i].allFinite())
      failWrite(path, "vertex " + std::to_string(i) + " has a non-finite coordinate");
    if (float32_only && mesh.vertices[i].cwiseAbs().maxCoeff() > static_cast<double>(FLT_MAX))
      failWrite(path, "vertex " + std::to_string(i) + " is outside the float32 range of " +
                          formatName(format));
  }
  if (with_normals)
    for (std::size_t i = 0; i < n; ++i)
      if (!mesh.normals[i].allFinite() ||
          (float32_only && mesh.normals[i].cwiseAbs().maxCoeff() > static_cast<double>(FLT_MAX)))
        failWrite(path, "normal " + std::to_string(i) + " is not finite");
  for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    for (const std::int32_t index : mesh.faces[f])
      if (index < 0 || static_cast<std::size_t>(index) >= n)
        failWrite(path, "face " + std::to_string(f) + " has vertex index " + std::to_string(index) +
                            " out of range (" + std::to_string(n) + " vertices)");
  if (format == MeshFormat::STL && mesh.faces.empty())
    failWrite(path, "STL stores triangles only and the mesh has no faces");
}

// POSIX rather than ofstream: O_EXCL never clobbers another writer's temporary file, and fsync
// makes "appears whole" hold across a crash too.
}  // namespace

MeshFormat formatFromPath(const std::string& path)
{
  const std::string ext = lowerExtension(path);
  if (ext == ".ply") return MeshFormat::PLY;
  if (ext == ".obj") return MeshFormat::OBJ;
  if (ext == ".off") return MeshFormat::OFF;
  if (ext == ".stl") return MeshFormat::STL;
  if (ext == ".pcd") return MeshFormat::PCD;
  return MeshFormat::Unknown;
}

std::string formatName(MeshFormat format)
{
  switch (format) {
  case MeshFormat::PLY: return "ply";
  case MeshFormat::OBJ: return "obj";
  case MeshFormat::OFF: return "off";
  case MeshFormat::STL: return "stl";
  case MeshFormat::PCD: return "pcd";
  case MeshFormat::Unknown: break;
  }
  return "unknown";
}

namespace {

void readBytes(const std::string& path, const std::string& bytes, MeshFormat format, TriangleMesh& mesh,
               ReadInfo* info)
{
  ReadInfo local;
  local.format = format;
  TriangleMesh result;
  try {
    if (bytes.empty())
      io_detail::failRead(path, "file is empty");
    switch (format) {
    case MeshFormat::PLY: io_detail::readPly(path, bytes, result, local); break;
    case MeshFormat::OBJ: io_detail::readObj(path, bytes, result, local); break;
    case MeshFormat::OFF: io_detail::readOff(path, bytes, result, local); break;
    case MeshFormat::STL: io_detail::readStl(path, bytes, result, local); break;
    case MeshFormat::PCD: io_detail::readPcd(path, bytes, result, local); break;
    case MeshFormat::Unknown: io_detail::failRead(path, "unknown format"); break;
    }
  }
  catch (const std::bad_alloc&) {
    io_detail::failRead(path, "out of memory");
  }
  catch (const std::length_error&) {
    io_detail::failRead(path, "out of memory");
  }
  if (result.vertices.empty())
    io_detail::failRead(path, "the file contains no vertices");
  mesh = std::move(result);
  if (info)
    *info = local;
}

}  // namespace

void readMesh(const std::string& path, TriangleMesh& mesh, ReadInfo* info)
{
  const MeshFormat format = formatFromPath(path);
  if (format == MeshFormat::Unknown)
    io_detail::failRead(path, "unknown extension " + io_detail::quoted(lowerExtension(path)) + " (" +
                                  kSupported + ")");
  std::string bytes;
  try {
    bytes = readWholeFile(path);
  }
  catch (const std::bad_alloc&) {
    io_detail::failRead(path, "out of memory");
  }
  readBytes(path, bytes, format, mesh, info);
}

void readMeshFromMemory(const std::string& bytes, MeshFormat format, TriangleMesh& mesh, ReadInfo* info,
                        const std::string& name)
{
  if (format == MeshFormat::PCD)
    io_detail::failRead(name, "PCD data can only be read from a file (PCL's reader takes a path)");
  readBytes(name, bytes, format, mesh, info);
}

void writeMesh(const std::string& path, const TriangleMesh& mesh, const WriteOptions& options)
{
  const MeshFormat format = formatFromPath(path);
  if (format == MeshFormat::Unknown)
    failWrite(path, "unknown extension " + io_detail::quoted(lowerExtension(path)) + " (" +
                        kSupported + ")");
  const bool with_normals = options.write_normals && mesh.hasNormals() &&
                            (format == MeshFormat::PLY || format == MeshFormat::OBJ ||
                             format == MeshFormat::PCD);
  validateForWrite(path, mesh, format, with_normals);

  if (format == MeshFormat::PCD) {
    // PCL's writer wants a file name: it writes the temporary file itself.
    writeFileAtomically(path, [&](const std::string& temporary) { io_detail::writePcd(path, temporary, mesh, options); });
    return;
  }
  std::string bytes;
  switch (format) {
  case MeshFormat::PLY: bytes = io_detail::writePly(mesh, options); break;
  case MeshFormat::OBJ: bytes = io_detail::writeObj(mesh, options); break;
  case MeshFormat::OFF: bytes = io_detail::writeOff(mesh, options); break;
  case MeshFormat::STL: bytes = io_detail::writeStl(mesh, options); break;
  default: break;
  }
  writeFileAtomically(path, bytes);
}

void writeQuadMesh(const std::string& path, const QuadMesh& mesh)
{
  const MeshFormat format = formatFromPath(path);
  std::ostringstream out;
  out.precision(17);
  if (format == MeshFormat::OBJ) {
    out << "# quad-dominant mesh written by pcl_patchdict\n";
    for (const auto& v : mesh.vertices)
      out << "v " << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
    for (const auto& face : mesh.faces) {
      out << 'f';
      for (const std::int32_t v : face)
        out << ' ' << v + 1;
      out << '\n';
    }
  } else if (format == MeshFormat::PLY) {
    out << "ply\nformat ascii 1.0\ncomment quad-dominant mesh written by pcl_patchdict\nelement vertex "
        << mesh.vertices.size() << "\nproperty double x\nproperty double y\nproperty double z\nelement face "
        << mesh.faces.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
    for (const auto& v : mesh.vertices)
      out << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
    for (const auto& face : mesh.faces) {
      out << face.size();
      for (const std::int32_t v : face)
        out << ' ' << v;
      out << '\n';
    }
  } else {
    throw Error("cannot write '" + path + "': a quad mesh is written as .obj or .ply");
  }
  writeFileAtomically(path, out.str());
}

}  // namespace patchdict
}  // namespace pcl
