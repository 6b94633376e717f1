// PCD through PCL's own reader and writer (it is PCL's format). PCD stores x/y/z as float32: a
// round trip is exact only for coordinates that are representable as float; others are rounded.
// Clouds from depth sensors carry NaN points: they are dropped (and counted), not an error.

#include "io/formats.h"

#include <pcl_patchdict/core/atomic_file.h>
#include <pcl_patchdict/pcl/conversions.h>

#include <algorithm>
#include <exception>
#include <limits>
#include <set>
#include <utility>
#include <vector>

#include <pcl/PolygonMesh.h>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>

namespace pcl {
namespace patchdict {
namespace io_detail {

namespace {

// PCL reports failures on the console as well as in its return codes; we turn the codes into one
// Error line, so its own messages would only be noise. (The level is process-wide state.)
class QuietPcl {
public:
  QuietPcl() : saved_(pcl::console::getVerbosityLevel())
  {
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  }
  ~QuietPcl() { pcl::console::setVerbosityLevel(saved_); }
  QuietPcl(const QuietPcl&) = delete;
  QuietPcl& operator=(const QuietPcl&) = delete;

private:
  pcl::console::VERBOSITY_LEVEL saved_;
};

bool hasField(const pcl::PCLPointCloud2& cloud, const char* name)
{
  for (const auto& field : cloud.fields)
    if (field.name == name)
      return true;
  return false;
}

std::uint32_t loadU32LE(const unsigned char* data)
{
  return static_cast<std::uint32_t>(data[0]) | (static_cast<std::uint32_t>(data[1]) << 8) |
         (static_cast<std::uint32_t>(data[2]) << 16) | (static_cast<std::uint32_t>(data[3]) << 24);
}

/** What checkPcd reads of a PCD header: its lines up to DATA, as PCL would read them. */
struct PcdHeader {
  std::vector<std::string_view> fields, sizes, types, counts;
  std::uint64_t width = 0, height = 1, points = 0;
  bool have_width = false, have_height = false, have_points = false;
  std::string_view data_kind;
  std::size_t body_start = 0;  ///< the byte after the DATA line
  std::size_t lines = 0;       ///< header lines read
};

/** A header number (≥ 0), or an error naming the line. */
std::uint64_t headerNumber(const std::string& path, std::size_t line_number, std::string_view token)
{
  std::int64_t value = 0;
  if (!parseInt(token, value) || value < 0)
    failReadLine(path, line_number, "bad number " + quoted(token) + " in the PCD header");
  return static_cast<std::uint64_t>(value);
}

/** The header lines up to DATA: each keyword once, no white space or '#' where PCL misreads them. */
PcdHeader readPcdHeader(const std::string& path, std::string_view bytes)
{
  PcdHeader h;
  std::set<std::string> seen;
  std::size_t pos = 0;
  while (h.data_kind.empty()) {
    if (pos >= bytes.size())
      failRead(path, "not a valid PCD file (no DATA line)");
    const std::size_t newline = bytes.find('\n', pos);
    const std::size_t line_end = newline == std::string_view::npos ? bytes.size() : newline;
    const std::string_view text = bytes.substr(pos, line_end - pos);
    const std::size_t line_number = ++h.lines;
    TextCursor cursor(text, line_number, '#');
    pos = line_end + 1;
    // As PCL reads a header: a line starting with '#' is a comment, and a line starting with white
    // space ends the header (PCL then crashes on what it has not read); empty lines are refused too.
    if (text.empty() || text[0] == ' ' || text[0] == '\t' || text[0] == '\r')
      failReadLine(path, line_number, "PCD header line is empty or starts with white space");
    if (!text.empty() && text[0] != '#' && text.find('#') != std::string_view::npos)
      failReadLine(path, line_number, "'#' inside a PCD header line");
    std::string_view keyword, token;
    if (!cursor.nextOnLine(keyword))
      continue;
    std::vector<std::string_view> values;
    while (cursor.nextOnLine(token))
      values.push_back(token);
    // Each keyword once: PCL keeps the last of repeated lines, and misreads files where they disagree.
    if (!seen.insert(std::string(keyword)).second)
      failReadLine(path, line_number, "repeated PCD header line " + quoted(keyword));
    const bool one = values.size() == 1;
    if (keyword == "FIELDS" || keyword == "COLUMNS") h.fields = values;
    else if (keyword == "SIZE") h.sizes = values;
    else if (keyword == "TYPE") h.types = values;
    else if (keyword == "COUNT") h.counts = values;
    else if (keyword == "VERSION" || keyword == "VIEWPOINT") continue;
    else if (keyword == "WIDTH" && one) {
      h.width = headerNumber(path, line_number, values[0]);
      h.have_width = true;
    }
    else if (keyword == "HEIGHT" && one) {
      h.height = headerNumber(path, line_number, values[0]);
      h.have_height = true;
    }
    else if (keyword == "POINTS" && one) {
      h.points = headerNumber(path, line_number, values[0]);
      h.have_points = true;
    }
    else if (keyword == "DATA" && one &&
             (values[0] == "ascii" || values[0] == "binary" || values[0] == "binary_compressed"))
      h.data_kind = values[0];
    else
      failReadLine(path, line_number, "unexpected PCD header line starting with " + quoted(keyword));
  }
  h.body_start = pos;
  return h;
}

/** The fields' sizes, types and counts, and the point count: consistent and supported. Returns
  * {bytes per point, values per point}. */
std::pair<std::uint64_t, std::uint64_t> checkPcdLayout(const std::string& path, PcdHeader& h)
{
  if (h.fields.empty() || h.sizes.size() != h.fields.size() || h.types.size() != h.fields.size() ||
      (!h.counts.empty() && h.counts.size() != h.fields.size()))
    failRead(path, "PCD header: FIELDS, SIZE, TYPE and COUNT do not match");
  std::uint64_t point_bytes = 0, values_per_point = 0;
  for (std::size_t f = 0; f < h.fields.size(); ++f) {
    const std::uint64_t size = headerNumber(path, h.lines, h.sizes[f]);
    const std::uint64_t count = h.counts.empty() ? 1 : headerNumber(path, h.lines, h.counts[f]);
    const bool valid_type = (h.types[f] == "F" && (size == 4 || size == 8)) ||
                            ((h.types[f] == "I" || h.types[f] == "U") && (size == 1 || size == 2 || size == 4));
    if (!valid_type || count == 0 || count > 1000000)
      failRead(path, "PCD header: unsupported field " + quoted(h.fields[f]));
    point_bytes += size * count;
    values_per_point += count;
  }
  // PCL reads garbage (and once asked for a 100 TB string) when WIDTH, HEIGHT or POINTS is missing.
  if (!h.have_width || !h.have_height || !h.have_points)
    failRead(path, "PCD header: WIDTH, HEIGHT and POINTS are all required");
  if (h.height != 0 && h.width > std::numeric_limits<std::uint32_t>::max() / h.height)
    failRead(path, "PCD header: bad WIDTH/HEIGHT");
  if (h.points != h.width * h.height)
    failRead(path, "PCD header: POINTS is not WIDTH x HEIGHT");
  h.points = h.width * h.height;
  if (h.points == 0)
    failRead(path, "the PCD file holds no points");
  return {point_bytes, values_per_point};
}

/** PCL's header loop goes on reading lines after DATA while they are empty, comments, or start
  * with a header keyword (matched as a prefix), so binary data beginning with, say, "FIELDS…" is
  * parsed as a new header (and once made PCL ask for a 100 TB string). Refuses what it would misread. */
void refuseHeaderLikeData(const std::string& path, std::string_view bytes, std::size_t pos)
{
  static const char* const keywords[] = {"VERSION", "FIELDS", "COLUMNS", "SIZE",   "TYPE", "COUNT",
                                         "WIDTH",   "HEIGHT", "VIEWPOINT", "POINTS", "DATA"};
  for (std::size_t at = pos; at < bytes.size();) {
    const std::size_t newline = bytes.find('\n', at);
    const std::string_view line = bytes.substr(at, newline == std::string_view::npos ? bytes.npos : newline - at);
    const std::string_view first = line.substr(0, line.find_first_of("\t\r "));
    for (const char* keyword : keywords)
      if (first.substr(0, std::char_traits<char>::length(keyword)) == keyword)
        failRead(path, "PCD binary data starts like a header line (" + quoted(first) +
                           "), which PCL would read as one");
    if (!line.empty() && line[0] != '#')
      break;
    if (newline == std::string_view::npos)
      break;
    at = newline + 1;
  }
}

/** Ascii data: every value a number, one point of `values_per_point` values per line (blank lines
  * skipped, as PCL reads it). */
void checkPcdAsciiBody(const std::string& path, std::string_view body, std::size_t first_line, std::uint64_t points,
                       std::uint64_t values_per_point)
{
  TextCursor data(body, first_line);
  std::string_view token;
  for (std::uint64_t point = 0; point < points; ++point) {
    std::uint64_t values = 0;
    double value = 0.0;
    while (values == 0) {
      if (data.atEnd())
        failRead(path, "truncated: " + std::to_string(point) + " of " + std::to_string(points) + " points present");
      for (; data.nextOnLine(token); ++values)
        if (!parseDouble(token, value))
          failReadLine(path, data.line(), "bad number " + quoted(token));
      if (values == 0)
        data.skipLine();
    }
    if (values != values_per_point)
      failReadLine(path, data.line(), "a point has " + std::to_string(values) + " values, expected " +
                                          std::to_string(values_per_point));
    data.skipLine();
  }
}

// PCL's reader crashes on some malformed headers (e.g. one without FIELDS or POINTS) and reads
// unparsable ascii values as 0, so the file is checked here first: a consistent header, a body of
// the size it promises, and (ascii) every value a number, one point per line.
void checkPcd(const std::string& path, std::string_view bytes)
{
  PcdHeader header = readPcdHeader(path, bytes);
  const auto [point_bytes, values_per_point] = checkPcdLayout(path, header);
  const std::size_t pos = header.body_start;
  const std::uint64_t points = header.points;
  if (header.data_kind != "ascii")
    refuseHeaderLikeData(path, bytes, pos);
  const std::size_t remaining = pos < bytes.size() ? bytes.size() - pos : 0;
  const auto* body = reinterpret_cast<const unsigned char*>(bytes.data()) + std::min(pos, bytes.size());
  if (header.data_kind == "binary") {
    if (points > remaining / point_bytes)
      failRead(path, "truncated: " + std::to_string(points) + " points declared, " +
                         std::to_string(remaining / point_bytes) + " present");
  }
  else if (header.data_kind == "binary_compressed") {
    if (remaining < 8 || loadU32LE(body) > remaining - 8 || loadU32LE(body + 4) != points * point_bytes)
      failRead(path, "truncated or corrupt compressed PCD data");
  }
  else {
    checkPcdAsciiBody(path, bytes.substr(std::min(pos, bytes.size())), header.lines + 1, points, values_per_point);
  }
}

}  // namespace

void readPcd(const std::string& path, std::string_view bytes, TriangleMesh& mesh, ReadInfo& info)
{
  checkPcd(path, bytes);
  pcl::PolygonMesh wrapper;  // a cloud without polygons, so that fromPolygonMesh can decode it
  pcl::PCDReader reader;
  Eigen::Vector4f origin;
  Eigen::Quaternionf orientation;
  int version = 0, data_type = 0;
  unsigned int data_offset = 0;
  try {
    QuietPcl quiet;
    if (reader.readHeader(path, wrapper.cloud, origin, orientation, version, data_type, data_offset) < 0)
      failRead(path, "not a valid PCD file (bad header)");
    if (reader.read(path, wrapper.cloud) < 0)
      failRead(path, "not a valid PCD file (bad or truncated data)");
  }
  catch (const Error&) {
    throw;
  }
  catch (const std::exception&) {
    failRead(path, "not a valid PCD file");
  }
  if (!hasField(wrapper.cloud, "x") || !hasField(wrapper.cloud, "y") || !hasField(wrapper.cloud, "z"))
    failRead(path, "the PCD file has no x/y/z fields");

  TriangleMesh all;
  try {
    fromPolygonMesh(wrapper, all);
  }
  catch (const Error& e) {
    failRead(path, e.what());
  }
  TriangleMesh result;
  result.vertices.reserve(all.vertices.size());
  if (all.hasNormals())
    result.normals.reserve(all.vertices.size());
  for (std::size_t i = 0; i < all.vertices.size(); ++i) {
    if (!all.vertices[i].allFinite()) {
      ++info.points_dropped;
      continue;
    }
    result.vertices.push_back(all.vertices[i]);
    if (all.hasNormals())
      result.normals.push_back(all.normals[i]);
  }
  // Normals are optional, derived data (PCL marks unknown ones NaN): keep them only if all are usable.
  for (const Eigen::Vector3d& n : result.normals)
    if (!n.allFinite()) {
      result.normals.clear();
      break;
    }
  if (result.vertices.empty() && info.points_dropped > 0)
    failRead(path, "all " + std::to_string(info.points_dropped) + " points are non-finite");
  info.binary = data_type != 0;
  mesh = std::move(result);
}

void writePcd(const std::string& target, const std::string& file_path, const TriangleMesh& mesh,
              const WriteOptions& options)
{
  pcl::PolygonMesh wrapper;
  if (mesh.hasNormals() && !options.write_normals) {
    TriangleMesh positions_only;
    positions_only.vertices = mesh.vertices;
    toPolygonMesh(positions_only, wrapper);
  }
  else {
    toPolygonMesh(mesh, wrapper);
  }
  pcl::PCDWriter writer;
  int status = -1;
  try {
    QuietPcl quiet;
    // 9 significant digits read back to the same float32 (PCL's default of 8 does not).
    status = options.binary ? writer.writeBinary(file_path, wrapper.cloud)
                            : writer.writeASCII(file_path, wrapper.cloud, Eigen::Vector4f::Zero(),
                                                Eigen::Quaternionf::Identity(), 9);
  }
  catch (const std::exception&) {
    status = -1;
  }
  if (status < 0)
    throw Error("cannot write '" + target + "': PCL failed to write the PCD file");
}

}  // namespace io_detail

void readPointCloudBlob(const std::string& path, pcl::PCLPointCloud2& blob, Eigen::Vector4f& origin,
                        Eigen::Quaternionf& orientation)
{
  const std::string bytes = readWholeFile(path);
  io_detail::checkPcd(path, bytes);
  pcl::PCDReader reader;
  int version = 0;
  try {
    io_detail::QuietPcl quiet;
    if (reader.read(path, blob, origin, orientation, version) < 0)
      io_detail::failRead(path, "not a valid PCD file (bad or truncated data)");
  }
  catch (const Error&) {
    throw;
  }
  catch (const std::exception&) {
    io_detail::failRead(path, "not a valid PCD file");
  }
  for (const char* name : {"x", "y", "z"}) {
    const auto field = std::find_if(blob.fields.begin(), blob.fields.end(),
                                    [&](const pcl::PCLPointField& f) { return f.name == name; });
    if (field == blob.fields.end())
      io_detail::failRead(path, "the PCD file has no x/y/z fields");
    if (field->count != 1 || (field->datatype != pcl::PCLPointField::FLOAT32 && field->datatype != pcl::PCLPointField::FLOAT64))
      io_detail::failRead(path, std::string("the PCD field ") + name + " is not one float32 or float64 value");
  }
}

void writePointCloudBlob(const std::string& path, const pcl::PCLPointCloud2& blob, const Eigen::Vector4f& origin,
                         const Eigen::Quaternionf& orientation)
{
  writeFileAtomically(path, [&](const std::string& temporary) {
    pcl::PCDWriter writer;
    int status = -1;
    try {
      io_detail::QuietPcl quiet;
      status = writer.writeBinary(temporary, blob, origin, orientation);
    }
    catch (const std::exception&) {
      status = -1;
    }
    if (status < 0)
      throw Error("cannot write '" + path + "': PCL failed to write the PCD file");
  });
}

}  // namespace patchdict
}  // namespace pcl
