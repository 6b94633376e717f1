// GeometricCloudRepair: the explicit instantiations for PCL's common point types (as PCL's own
// modules do); its type-free core, detail::denoiseCloud, is in denoise_cloud.cpp.
#include <pcl_patchdict/cloud/impl/geometric_cloud_repair.hpp>
#include <pcl_patchdict/cloud/geometric_cloud_repair.h>

namespace pcl {
namespace patchdict {

template class GeometricCloudRepair<pcl::PointXYZ, pcl::PointXYZ>;
template class GeometricCloudRepair<pcl::PointXYZ, pcl::PointNormal>;
template class GeometricCloudRepair<pcl::PointNormal, pcl::PointNormal>;
template class GeometricCloudRepair<pcl::PointNormal, pcl::PointXYZ>;
template class GeometricCloudRepair<pcl::PointXYZRGB, pcl::PointXYZRGB>;
template class GeometricCloudRepair<pcl::PointXYZRGB, pcl::PointXYZRGBNormal>;
template class GeometricCloudRepair<pcl::PointXYZRGBNormal, pcl::PointXYZRGBNormal>;
template class GeometricCloudRepair<pcl::PointXYZI, pcl::PointXYZI>;
// Kinect and other RGB-D grabbers' frames.
template class GeometricCloudRepair<pcl::PointXYZRGBA, pcl::PointXYZRGBA>;
template class GeometricCloudRepair<pcl::PointXYZRGBA, pcl::PointXYZRGBNormal>;

}  // namespace patchdict
}  // namespace pcl
