// GeometricCloudInpainter: the explicit instantiations for PCL's common point types (as PCL's own
// modules do); its type-free core, detail::denoiseCloud, is in denoise_cloud.cpp.
#include <pcl_patchdict/cloud/impl/geometric_cloud_inpainter.hpp>
#include <pcl_patchdict/cloud/geometric_cloud_inpainter.h>

namespace pcl {
namespace patchdict {

template class GeometricCloudInpainter<pcl::PointXYZ, pcl::PointXYZ>;
template class GeometricCloudInpainter<pcl::PointXYZ, pcl::PointNormal>;
template class GeometricCloudInpainter<pcl::PointNormal, pcl::PointNormal>;
template class GeometricCloudInpainter<pcl::PointNormal, pcl::PointXYZ>;
template class GeometricCloudInpainter<pcl::PointXYZRGB, pcl::PointXYZRGB>;
template class GeometricCloudInpainter<pcl::PointXYZRGB, pcl::PointXYZRGBNormal>;
template class GeometricCloudInpainter<pcl::PointXYZRGBNormal, pcl::PointXYZRGBNormal>;
template class GeometricCloudInpainter<pcl::PointXYZI, pcl::PointXYZI>;
// Kinect and other RGB-D grabbers' frames.
template class GeometricCloudInpainter<pcl::PointXYZRGBA, pcl::PointXYZRGBA>;
template class GeometricCloudInpainter<pcl::PointXYZRGBA, pcl::PointXYZRGBNormal>;

}  // namespace patchdict
}  // namespace pcl
