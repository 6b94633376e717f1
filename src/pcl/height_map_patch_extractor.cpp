// HeightMapPatchExtractor: its type-free core (the seeds with a usable frame through the core's
// height maps, the others NaN) and the explicit instantiations for PCL's common point types.
#include <pcl_patchdict/pcl/height_map_patch_extractor.h>
#include <pcl_patchdict/pcl/impl/height_map_patch_extractor.hpp>

#include <limits>

namespace pcl {
namespace patchdict {
namespace detail {

bool heightMapHistograms(const TriangleMesh* mesh, const std::vector<Eigen::Vector3d>& points,
                         const std::vector<Eigen::Vector3d>& seeds, const std::vector<Eigen::Matrix3d>& frames,
                         const HeightMapParameters& parameters, std::vector<float>& out)
{
  // The seeds with a position and a frame; each frame checked under its own seed's index.
  std::vector<Eigen::Vector3d> valid_seeds;
  std::vector<Eigen::Matrix3d> valid_frames;
  std::vector<std::size_t> slots;
  for (std::size_t s = 0; s < seeds.size() && s < frames.size(); ++s) {
    if (!seeds[s].allFinite() || !frames[s].allFinite())
      continue;
    checkHeightMapFrame(frames[s], s);
    valid_seeds.push_back(seeds[s]);
    valid_frames.push_back(frames[s]);
    slots.push_back(s);
  }
  PatchSet patches;
  if (mesh)
    extractMeshHeightMaps(*mesh, valid_seeds, valid_frames, parameters, patches);
  else
    extractCloudHeightMaps(points, valid_seeds, valid_frames, parameters, patches);

  const auto bins = static_cast<std::size_t>(parameters.grid_size) * static_cast<std::size_t>(parameters.grid_size);
  out.assign(seeds.size() * bins, std::numeric_limits<float>::quiet_NaN());
  bool dense = slots.size() == seeds.size();
  for (std::size_t k = 0; k < slots.size(); ++k) {
    float* histogram = out.data() + slots[k] * bins;
    const auto column = static_cast<Eigen::Index>(k);
    for (std::size_t b = 0; b < bins; ++b) {
      const auto row = static_cast<Eigen::Index>(b);
      if (patches.observed(row, column))
        histogram[b] = static_cast<float>(patches.heights(row, column));
      else
        dense = false;
    }
  }
  return dense;
}

}  // namespace detail

template class HeightMapPatchExtractor<pcl::PointXYZ, pcl::Histogram<256>>;
template class HeightMapPatchExtractor<pcl::PointNormal, pcl::Histogram<256>>;
template class HeightMapPatchExtractor<pcl::PointXYZRGBNormal, pcl::Histogram<256>>;

}  // namespace patchdict
}  // namespace pcl
