// Cloud inputs (see cloud_input.h).
#include "cloud_input.h"
#include "cli.h"

#include <pcl_patchdict/pcl/conversions.h>
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/cloud/gross_outliers.h>
#include <pcl_patchdict/io/mesh_io.h>

#include <pcl/conversions.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

namespace pcl {
namespace patchdict {
namespace cli {

bool isCloudFile(const std::string& path)
{
  const MeshFormat format = formatFromPath(path);
  if (format == MeshFormat::PCD)
    return true;
  if (format != MeshFormat::PLY)
    return false;
  // The PLY header only: "element face N" with N > 0 makes it a mesh. Unreadable headers go to the
  // mesh reader, which says what is wrong.
  std::ifstream file(path, std::ios::binary);
  if (!file)
    return false;
  std::string line;
  bool faces = false, ended = false;
  for (int lines = 0; lines < 10000 && std::getline(file, line); ++lines) {
    if (!line.empty() && line.back() == '\r')
      line.pop_back();
    std::istringstream words(line);
    std::string keyword, element;
    long long count = 0;
    words >> keyword;
    if (keyword == "end_header") {
      ended = true;
      break;
    }
    if (keyword == "element" && (words >> element >> count) && element == "face" && count > 0)
      faces = true;
  }
  return ended && !faces;
}

const pcl::PCLPointField* findScalarField(const pcl::PCLPointCloud2& blob, const char* name)
{
  for (const auto& field : blob.fields)
    if (field.name == name && field.count == 1 &&
        (field.datatype == pcl::PCLPointField::FLOAT32 || field.datatype == pcl::PCLPointField::FLOAT64))
      return &field;
  return nullptr;
}

void writeScalar(pcl::PCLPointCloud2& blob, std::size_t point, const pcl::PCLPointField& field, double value)
{
  std::uint8_t* at = blob.data.data() + point * blob.point_step + field.offset;
  if (field.datatype == pcl::PCLPointField::FLOAT32) {
    const auto v = static_cast<float>(value);
    std::memcpy(at, &v, sizeof v);
  } else {
    std::memcpy(at, &value, sizeof value);
  }
}

const pcl::PCLPointField* findIntegerField(const pcl::PCLPointCloud2& blob, const char* name)
{
  for (const auto& field : blob.fields)
    if (field.name == name && field.count == 1 && field.datatype >= pcl::PCLPointField::INT8 &&
        field.datatype <= pcl::PCLPointField::UINT32)
      return &field;
  return nullptr;
}

namespace {

/** A PCD: every field kept in the blob; x/y/z (float32 or float64) and normals read by hand. */
void readPcdCloud(const std::string& path, CloudInput& input)
{
  pcl::PointCloud<pcl::PointNormal>& cloud = *input.cloud;
  input.from_pcd = true;
  readPointCloudBlob(path, input.blob, input.origin, input.orientation);
  // x/y/z may be float64 in a PCD; PCL's conversion wants float32: convert by hand.
  cloud.resize(static_cast<std::size_t>(input.blob.width) * input.blob.height);
  cloud.width = input.blob.width;
  cloud.height = input.blob.height;
  const pcl::PCLPointField* fields[6] = {
      findScalarField(input.blob, "x"),        findScalarField(input.blob, "y"),
      findScalarField(input.blob, "z"),        findScalarField(input.blob, "normal_x"),
      findScalarField(input.blob, "normal_y"), findScalarField(input.blob, "normal_z")};
  input.has_normals = fields[3] && fields[4] && fields[5];
  const auto value = [&](std::size_t i, int f) { return readPointField(input.blob, i, *fields[f]); };
  input.positions.resize(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i)
    input.positions[i] = Eigen::Vector3d(value(i, 0), value(i, 1), value(i, 2));
  std::vector<Eigen::Vector3d> clean(input.positions);
  input.gross_outliers = removeGrossOutliers(clean);
  Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), high = -low;
  for (const auto& x : clean)
    if (x.allFinite()) {
      low = low.cwiseMin(x);
      high = high.cwiseMax(x);
    }
  // An organised frame is kept in its own (sensor) frame, where its grid is a pinhole image, unless
  // it lies far from its origin (georeferenced), where float32 would lose its precision.
  const bool sensor_frame = input.blob.height > 1 && (0.5 * (low + high)).norm() < 1e4;
  if (low.allFinite() && !sensor_frame)
    input.offset = 0.5 * (low + high);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d x = clean[i] - input.offset;
    pcl::PointNormal& p = cloud[i];
    p.x = static_cast<float>(x.x());
    p.y = static_cast<float>(x.y());
    p.z = static_cast<float>(x.z());
    double nx = 0, ny = 0, nz = 0;
    if (input.has_normals) {
      nx = value(i, 3);
      ny = value(i, 4);
      nz = value(i, 5);
    }
    const bool normal_ok = std::isfinite(nx) && std::isfinite(ny) && std::isfinite(nz);
    p.normal_x = normal_ok ? static_cast<float>(nx) : 0.0f;
    p.normal_y = normal_ok ? static_cast<float>(ny) : 0.0f;
    p.normal_z = normal_ok ? static_cast<float>(nz) : 0.0f;
    p.curvature = 0.0f;
  }
  cloud.sensor_origin_ = input.origin;  // in the cloud's shifted frame, like its points
  cloud.sensor_origin_.head<3>() -= input.offset.cast<float>();
  cloud.sensor_orientation_ = input.orientation;
}

/** A face-less PLY: positions and normals. */
void readPlyCloud(const std::string& path, CloudInput& input)
{
  pcl::PointCloud<pcl::PointNormal>& cloud = *input.cloud;
  TriangleMesh mesh;
  readMesh(path, mesh);
  if (mesh.numFaces() > 0)
    throw Error("'" + path + "' is a mesh, not a cloud");
  input.has_normals = mesh.hasNormals();
  input.positions = mesh.vertices;
  std::vector<Eigen::Vector3d> clean(input.positions);
  input.gross_outliers = removeGrossOutliers(clean);
  cloud.resize(mesh.vertices.size());
  Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), high = -low;
  for (const auto& v : clean)
    if (v.allFinite()) {
      low = low.cwiseMin(v);
      high = high.cwiseMax(v);
    }
  if (low.allFinite())
    input.offset = 0.5 * (low + high);
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    pcl::PointNormal& p = cloud[i];
    const Eigen::Vector3d x = clean[i] - input.offset;
    p.x = static_cast<float>(x.x());
    p.y = static_cast<float>(x.y());
    p.z = static_cast<float>(x.z());
    const Eigen::Vector3d n = input.has_normals ? mesh.normals[i] : Eigen::Vector3d::Zero();
    p.normal_x = static_cast<float>(n.x());
    p.normal_y = static_cast<float>(n.y());
    p.normal_z = static_cast<float>(n.z());
    p.curvature = 0.0f;
  }
  cloud.width = static_cast<std::uint32_t>(cloud.size());
  cloud.height = 1;
}

}  // namespace

CloudInput loadCloudInput(const std::string& path)
{
  CloudInput input;
  input.cloud.reset(new pcl::PointCloud<pcl::PointNormal>);
  pcl::PointCloud<pcl::PointNormal>& cloud = *input.cloud;
  if (formatFromPath(path) == MeshFormat::PCD)
    readPcdCloud(path, input);
  else
    readPlyCloud(path, input);
  Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d high = -low;
  std::size_t finite = 0;
  for (const auto& p : cloud) {
    const Eigen::Vector3d x(p.x, p.y, p.z);
    if (!x.allFinite())
      continue;
    low = low.cwiseMin(x);
    high = high.cwiseMax(x);
    ++finite;
  }
  if (finite == 0)
    throw Error("'" + path + "' holds no finite point");
  cloud.is_dense = finite == cloud.size();
  input.scale = (high - low).maxCoeff();
  if (!(input.scale > 0.0) || !std::isfinite(input.scale))
    throw Error("'" + path + "' " + (finite == 1 ? std::string("holds a single finite point")
                                                  : "has " + std::to_string(finite) + " finite points, all at one place"));
  return input;
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
