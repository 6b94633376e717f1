// SparsePatchCloudInpainter: the explicit instantiations for PCL's common point types (as PCL's own
// modules do); its type-free core, detail::denoiseCloud, is in denoise_cloud.cpp.
#include <pcl_patchdict/cloud/impl/sparse_patch_cloud_inpainter.hpp>
#include <pcl_patchdict/cloud/sparse_patch_cloud_inpainter.h>

namespace pcl {
namespace patchdict {

template class SparsePatchCloudInpainter<pcl::PointXYZ, pcl::PointXYZ>;
template class SparsePatchCloudInpainter<pcl::PointXYZ, pcl::PointNormal>;
template class SparsePatchCloudInpainter<pcl::PointNormal, pcl::PointNormal>;
template class SparsePatchCloudInpainter<pcl::PointNormal, pcl::PointXYZ>;
template class SparsePatchCloudInpainter<pcl::PointXYZRGB, pcl::PointXYZRGB>;
template class SparsePatchCloudInpainter<pcl::PointXYZRGB, pcl::PointXYZRGBNormal>;
template class SparsePatchCloudInpainter<pcl::PointXYZRGBNormal, pcl::PointXYZRGBNormal>;
template class SparsePatchCloudInpainter<pcl::PointXYZI, pcl::PointXYZI>;
// Kinect and other RGB-D grabbers' frames.
template class SparsePatchCloudInpainter<pcl::PointXYZRGBA, pcl::PointXYZRGBA>;
template class SparsePatchCloudInpainter<pcl::PointXYZRGBA, pcl::PointXYZRGBNormal>;

}  // namespace patchdict
}  // namespace pcl
