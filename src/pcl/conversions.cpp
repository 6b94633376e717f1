#include <pcl_patchdict/pcl/conversions.h>

#include <pcl_patchdict/core/error.h>

#include <cstring>
#include <limits>
#include <string>

#include <pcl/PCLPointField.h>

namespace pcl {
namespace patchdict {

namespace {

pcl::PCLPointField makeField(const std::string& name, std::uint32_t offset)
{
  pcl::PCLPointField field;
  field.name = name;
  field.offset = offset;
  field.datatype = pcl::PCLPointField::FLOAT32;
  field.count = 1;
  return field;
}

// Reads one scalar field of any PCL numeric type as double.
double readField(const std::uint8_t* data, const pcl::PCLPointField& field)
{
  switch (field.datatype) {
  case pcl::PCLPointField::INT8: { std::int8_t v; std::memcpy(&v, data, 1); return v; }
  case pcl::PCLPointField::UINT8: { std::uint8_t v; std::memcpy(&v, data, 1); return v; }
  case pcl::PCLPointField::INT16: { std::int16_t v; std::memcpy(&v, data, 2); return v; }
  case pcl::PCLPointField::UINT16: { std::uint16_t v; std::memcpy(&v, data, 2); return v; }
  case pcl::PCLPointField::INT32: { std::int32_t v; std::memcpy(&v, data, 4); return v; }
  case pcl::PCLPointField::UINT32: { std::uint32_t v; std::memcpy(&v, data, 4); return v; }
  case pcl::PCLPointField::FLOAT32: { float v; std::memcpy(&v, data, 4); return v; }
  case pcl::PCLPointField::FLOAT64: { double v; std::memcpy(&v, data, 8); return v; }
  default: return std::numeric_limits<double>::quiet_NaN();
  }
}

std::size_t fieldSize(std::uint8_t datatype)
{
  switch (datatype) {
  case pcl::PCLPointField::INT8: case pcl::PCLPointField::UINT8: return 1;
  case pcl::PCLPointField::INT16: case pcl::PCLPointField::UINT16: return 2;
  case pcl::PCLPointField::INT32: case pcl::PCLPointField::UINT32:
  case pcl::PCLPointField::FLOAT32: return 4;
  case pcl::PCLPointField::FLOAT64: return 8;
  default: return 0;
  }
}

}  // namespace

double readPointField(const pcl::PCLPointCloud2& blob, std::size_t point, const pcl::PCLPointField& field)
{
  return readField(blob.data.data() + point * blob.point_step + field.offset, field);
}

void toPolygonMesh(const TriangleMesh& mesh, pcl::PolygonMesh& out)
{
  out = pcl::PolygonMesh();
  auto& cloud = out.cloud;
  const bool normals = mesh.hasNormals();
  cloud.fields.push_back(makeField("x", 0));
  cloud.fields.push_back(makeField("y", 4));
  cloud.fields.push_back(makeField("z", 8));
  if (normals) {
    cloud.fields.push_back(makeField("normal_x", 12));
    cloud.fields.push_back(makeField("normal_y", 16));
    cloud.fields.push_back(makeField("normal_z", 20));
  }
  cloud.point_step = normals ? 24 : 12;
  cloud.width = static_cast<std::uint32_t>(mesh.vertices.size());
  cloud.height = 1;
  cloud.row_step = cloud.point_step * cloud.width;
  cloud.is_dense = true;
  cloud.is_bigendian = false;
  cloud.data.resize(static_cast<std::size_t>(cloud.row_step));
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    float values[6];
    for (int k = 0; k < 3; ++k)
      values[k] = static_cast<float>(mesh.vertices[i][k]);
    if (normals)
      for (int k = 0; k < 3; ++k)
        values[3 + k] = static_cast<float>(mesh.normals[i][k]);
    std::memcpy(&cloud.data[i * cloud.point_step], values, cloud.point_step);
  }
  out.polygons.resize(mesh.faces.size());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    out.polygons[f].vertices.assign(mesh.faces[f].begin(), mesh.faces[f].end());
}

void fromPolygonMesh(const pcl::PolygonMesh& in, TriangleMesh& mesh)
{
  const auto& cloud = in.cloud;
  const pcl::PCLPointField* xyz[3] = {nullptr, nullptr, nullptr};
  const pcl::PCLPointField* nrm[3] = {nullptr, nullptr, nullptr};
  static const char* xyz_names[3] = {"x", "y", "z"};
  static const char* nrm_names[3] = {"normal_x", "normal_y", "normal_z"};
  for (const auto& field : cloud.fields)
    for (int k = 0; k < 3; ++k) {
      if (field.name == xyz_names[k]) xyz[k] = &field;
      if (field.name == nrm_names[k]) nrm[k] = &field;
    }
  if (!xyz[0] || !xyz[1] || !xyz[2])
    throw Error("PolygonMesh cloud has no x/y/z fields");
  const std::size_t num_points = static_cast<std::size_t>(cloud.width) * cloud.height;
  if (cloud.data.size() < num_points * cloud.point_step)
    throw Error("PolygonMesh cloud data is shorter than width*height*point_step");
  auto fits = [&](const pcl::PCLPointField* f) {
    return f && fieldSize(f->datatype) > 0 && f->offset + fieldSize(f->datatype) <= cloud.point_step;
  };
  for (int k = 0; k < 3; ++k)
    if (!fits(xyz[k]))
      throw Error("PolygonMesh cloud has an unsupported or misplaced coordinate field");
  const bool has_normals = fits(nrm[0]) && fits(nrm[1]) && fits(nrm[2]);

  TriangleMesh result;
  result.vertices.resize(num_points);
  if (has_normals)
    result.normals.resize(num_points);
  for (std::size_t i = 0; i < num_points; ++i) {
    const std::uint8_t* point = &cloud.data[i * cloud.point_step];
    for (int k = 0; k < 3; ++k)
      result.vertices[i][k] = readField(point + xyz[k]->offset, *xyz[k]);
    if (has_normals)
      for (int k = 0; k < 3; ++k)
        result.normals[i][k] = readField(point + nrm[k]->offset, *nrm[k]);
  }
  for (const auto& polygon : in.polygons) {
    const auto& v = polygon.vertices;
    for (const auto index : v)
      if (static_cast<std::size_t>(index) >= num_points)
        throw Error("PolygonMesh face index " + std::to_string(index) + " is out of range (" +
                    std::to_string(num_points) + " vertices)");
    for (std::size_t k = 2; k < v.size(); ++k)  // fan triangulation of polygons
      result.faces.push_back({static_cast<std::int32_t>(v[0]), static_cast<std::int32_t>(v[k - 1]),
                              static_cast<std::int32_t>(v[k])});
  }
  mesh = std::move(result);
}

}  // namespace patchdict
}  // namespace pcl
