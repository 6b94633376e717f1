// The former names of the cloud path's geometric repair, kept so that code written against them still
// builds (with a deprecation warning): use GeometricCloudRepair and <pcl_patchdict/cloud/geometric_cloud_repair.h>.
#pragma once

#include <pcl_patchdict/cloud/geometric_cloud_repair.h>

namespace pcl {
namespace patchdict {

template <typename PointInT, typename PointOutT = PointInT>
using GeometricCloudInpainter [[deprecated("renamed GeometricCloudRepair (it denoises and fills)")]] =
    GeometricCloudRepair<PointInT, PointOutT>;
using CloudDenoisingParameters [[deprecated("renamed CloudRepairParameters")]] = CloudRepairParameters;
using CloudDenoisingReport [[deprecated("renamed CloudRepairReport")]] = CloudRepairReport;

}  // namespace patchdict
}  // namespace pcl
