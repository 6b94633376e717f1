// Conversions between TriangleMesh and PCL's types: pcl::PolygonMesh and pcl::PointCloud<PointT>.
// The PCL boundary of the core's plain mesh (positions float32 in PCL, double in the core).
#pragma once

#include <pcl_patchdict/core/triangle_mesh.h>

#include <pcl/PCLPointCloud2.h>
#include <pcl/PolygonMesh.h>
#include <pcl/point_cloud.h>

#include <cstddef>

#include <vector>

namespace pcl {
namespace patchdict {

/** \brief Convert to a pcl::PolygonMesh (cloud fields x y z as float32, plus normal_x.. when present). */
void toPolygonMesh(const TriangleMesh& mesh, pcl::PolygonMesh& out);
/** \brief Convert from a pcl::PolygonMesh. Polygons with more than 3 vertices are fan-triangulated;
  * throws pcl::patchdict::Error if the cloud has no x/y/z fields or a face index is out of range. */
void fromPolygonMesh(const pcl::PolygonMesh& in, TriangleMesh& mesh);

/** \brief Field `field` (count 1, any of PCL's numeric types) of point `point` of a blob, as double
  * (exact for every integer type up to 32 bits); NaN for a datatype PCL does not define. */
double readPointField(const pcl::PCLPointCloud2& blob, std::size_t point, const pcl::PCLPointField& field);

/** \brief Copy the vertices (and normals, when PointT has them) into a cloud. */
template <typename PointT>
void toPointCloud(const TriangleMesh& mesh, pcl::PointCloud<PointT>& cloud);
/** \brief A face-less mesh from the cloud's finite points (and normals, when PointT has them).
  * \param[out] index_map optional: for each mesh vertex, the index of the point it came from. */
template <typename PointT>
void fromPointCloud(const pcl::PointCloud<PointT>& cloud, TriangleMesh& mesh,
                    std::vector<int>* index_map = nullptr);

}  // namespace patchdict
}  // namespace pcl

#include <pcl_patchdict/pcl/impl/conversions.hpp>
