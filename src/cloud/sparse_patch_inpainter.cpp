// SparsePatchInpainter: the explicit instantiations for PCL's common point types (the same pairs
// as GeometricCloudRepair, its base).
#include <pcl_patchdict/cloud/impl/sparse_patch_inpainter.hpp>
#include <pcl_patchdict/cloud/sparse_patch_inpainter.h>

namespace pcl {
namespace patchdict {

template class SparsePatchInpainter<pcl::PointXYZ, pcl::PointXYZ>;
template class SparsePatchInpainter<pcl::PointXYZ, pcl::PointNormal>;
template class SparsePatchInpainter<pcl::PointNormal, pcl::PointNormal>;
template class SparsePatchInpainter<pcl::PointNormal, pcl::PointXYZ>;
template class SparsePatchInpainter<pcl::PointXYZRGB, pcl::PointXYZRGB>;
template class SparsePatchInpainter<pcl::PointXYZRGB, pcl::PointXYZRGBNormal>;
template class SparsePatchInpainter<pcl::PointXYZRGBNormal, pcl::PointXYZRGBNormal>;
template class SparsePatchInpainter<pcl::PointXYZI, pcl::PointXYZI>;
template class SparsePatchInpainter<pcl::PointXYZRGBA, pcl::PointXYZRGBA>;
template class SparsePatchInpainter<pcl::PointXYZRGBA, pcl::PointXYZRGBNormal>;

}  // namespace patchdict
}  // namespace pcl
