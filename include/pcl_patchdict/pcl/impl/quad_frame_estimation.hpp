// QuadFrameEstimation<PointInT> (see quad_frame_estimation.h): the typed shell around
// detail::estimateQuadFrames — points in, seeds and frames out.
#pragma once

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/pcl/conversions.h>
#include <pcl_patchdict/pcl/quad_frame_estimation.h>
#include <pcl_patchdict/pcl/reference_frame.h>

#include <pcl/type_traits.h>

#include <cmath>
#include <string>

namespace pcl {
namespace patchdict {

template <typename PointInT>
void QuadFrameEstimation<PointInT>::readCloud(TriangleMesh& surface)
{
  if (!this->initCompute())  // PCLBase: the indices (all points when none were given)
    throw Error("QuadFrameEstimation: the input cloud or its indices are not usable");
  surface = TriangleMesh();
  bool normals = pcl::traits::has_normal_v<PointInT>;
  for (const auto index : *indices_) {
    if (index < 0 || static_cast<std::size_t>(index) >= input_->size())
      throw Error("QuadFrameEstimation: index " + std::to_string(index) + " is outside the input cloud of " +
                  std::to_string(input_->size()) + " points");
    const PointInT& p = (*input_)[static_cast<std::size_t>(index)];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      continue;
    surface.vertices.emplace_back(p.x, p.y, p.z);
    if constexpr (pcl::traits::has_normal_v<PointInT>) {
      const Eigen::Vector3d n(p.normal_x, p.normal_y, p.normal_z);
      normals = normals && n.allFinite() && n.squaredNorm() > 0.0;
      surface.normals.push_back(n);
    }
  }
  if (!normals)
    surface.normals.clear();  // estimated and oriented instead
  this->deinitCompute();
}

template <typename PointInT>
void QuadFrameEstimation<PointInT>::compute(PointCloudSeeds& seeds, PointCloudLRF& frames)
{
  TriangleMesh surface;
  if (mesh_) {
    fromPolygonMesh(*mesh_, surface);
  } else {
    if (!input_)
      throw Error("QuadFrameEstimation: no input (setInputCloud or setInputPolygonMesh)");
    readCloud(surface);
  }
  detail::estimateQuadFrames(surface, parameters_, layout_, report_);

  seeds.clear();
  seeds.resize(layout_.seeds.size());
  for (std::size_t s = 0; s < layout_.seeds.size(); ++s) {
    pcl::PointNormal& out = seeds[s];
    out.getVector3fMap() = layout_.seeds[s].cast<float>();
    out.getNormalVector3fMap() = layout_.frames[s].row(2).transpose().cast<float>();
    out.curvature = 0.f;
  }
  seeds.width = static_cast<std::uint32_t>(seeds.size());
  seeds.height = 1;
  seeds.is_dense = true;
  frames = toReferenceFrames(layout_.frames);
  if (!mesh_) {
    seeds.header = input_->header;
    frames.header = input_->header;
  }
}

template <typename PointInT>
void QuadFrameEstimation<PointInT>::getCoarseMesh(pcl::PolygonMesh& mesh) const
{
  toPolygonMesh(layout_.coarse, mesh);
}

}  // namespace patchdict
}  // namespace pcl
