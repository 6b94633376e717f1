// detail::denoiseCloud, stage 4 (see denoise_cloud.cpp): the orientation of the patches' normals.
#include "cloud/denoise_cloud_stages.h"

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/geometry/coarse_mesh_estimation.h>

#include <pcl/search/kdtree.h>

#include <deque>
#include <memory>

namespace pcl {
namespace patchdict {
namespace denoise_detail {

namespace {

/// Points without an input normal (NaN or zero in a cloud that has some), and no viewpoint: oriented
/// outwards from the oriented ones, breadth first over 16 nearest neighbours, each agreeing with the
/// neighbour it was reached from.
void orientFromNeighbours(Orientation& o, std::vector<char>& oriented)
{
  const std::size_t nq = o.queries.size();
  std::vector<std::ptrdiff_t> query_of(o.points.size(), -1);
  for (std::size_t q = 0; q < nq; ++q)
    query_of[o.queries[q]] = static_cast<std::ptrdiff_t>(q);
  std::deque<std::size_t> frontier;
  for (std::size_t q = 0; q < nq; ++q)
    if (oriented[q])
      frontier.push_back(q);
  pcl::Indices found;
  std::vector<float> squared;
  while (!frontier.empty()) {
    const std::size_t from = frontier.front();
    frontier.pop_front();
    o.knn(o.queries[from], 16, found, squared);
    for (const auto j : found) {
      const std::ptrdiff_t other = query_of[static_cast<std::size_t>(j)];
      if (other < 0 || !o.kept[static_cast<std::size_t>(other)] || oriented[static_cast<std::size_t>(other)])
        continue;
      const auto to = static_cast<std::size_t>(other);
      if (o.out_normals[to].dot(o.out_normals[from]) < 0.0) {
        o.out_normals[to] = -o.out_normals[to];
        ++o.report.normals_flipped;
      }
      oriented[to] = 1;
      frontier.push_back(to);
    }
  }
}

/// Each normal towards its input normal or the viewpoint; the others from their neighbours.
void orientFromReferences(Orientation& o, bool any_input_normal, const Eigen::Vector3d* viewpoint)
{
  const std::size_t nq = o.queries.size();
  o.report.normal_orientation = any_input_normal ? "input normals" : "viewpoint";
  std::vector<char> oriented(nq, 0);
  for (std::size_t q = 0; q < nq; ++q) {
    if (!o.kept[q])
      continue;
    const bool has_input = any_input_normal && !o.normals[o.queries[q]].isZero();
    if (!has_input && !viewpoint)
      continue;  // no normal of its own: from its neighbours, below
    const Eigen::Vector3d reference =
        has_input ? o.normals[o.queries[q]] : Eigen::Vector3d(*viewpoint - o.positions[q]);
    if (o.out_normals[q].dot(reference) < 0.0) {
      o.out_normals[q] = -o.out_normals[q];
      ++o.report.normals_flipped;
    }
    oriented[q] = 1;
  }
  orientFromNeighbours(o, oriented);
}

/// No reference at all: consistently by Hoppe et al.'s propagation over the kept points' 8-NN graph.
void orientByPropagation(Orientation& o, int threads)
{
  const std::size_t nq = o.queries.size();
  o.report.normal_orientation = "propagation";
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  std::vector<std::size_t> owner;
  for (std::size_t q = 0; q < nq; ++q)
    if (o.kept[q]) {
      cloud->push_back(pcl::PointXYZ(static_cast<float>(o.positions[q].x()), static_cast<float>(o.positions[q].y()),
                                     static_cast<float>(o.positions[q].z())));
      owner.push_back(q);
    }
  if (owner.empty())
    return;
  pcl::search::KdTree<pcl::PointXYZ> tree(true);
  tree.setInputCloud(cloud);
  constexpr int kGraph = 8;
  std::vector<std::vector<int>> graph(owner.size());
#pragma omp parallel num_threads(threads)
  {
    pcl::Indices found;
    std::vector<float> squared;
#pragma omp for schedule(dynamic, 1024)
    for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(owner.size()); ++i) {
      tree.nearestKSearch((*cloud)[static_cast<std::size_t>(i)], kGraph + 1, found, squared);
      for (const auto j : found)
        if (j != static_cast<int>(i) && graph[static_cast<std::size_t>(i)].size() < kGraph)
          graph[static_cast<std::size_t>(i)].push_back(j);
    }
  }
  std::vector<Eigen::Vector3d> oriented(owner.size());
  for (std::size_t i = 0; i < owner.size(); ++i)
    oriented[i] = o.out_normals[owner[i]];
  o.report.normals_flipped = propagateNormalOrientation(*cloud, graph, oriented);
  for (std::size_t i = 0; i < owner.size(); ++i)
    o.out_normals[owner[i]] = oriented[i];
}

}  // namespace

void orientNormals(Orientation& o, const Eigen::Vector3d* viewpoint, int threads)
{
  bool any_input_normal = false;
  for (std::size_t q = 0; q < o.queries.size() && !any_input_normal; ++q)
    any_input_normal = o.kept[q] && !o.normals.empty() && !o.normals[o.queries[q]].isZero();
  if (any_input_normal || viewpoint)
    orientFromReferences(o, any_input_normal, viewpoint);
  else
    orientByPropagation(o, threads);
}

}  // namespace denoise_detail
}  // namespace patchdict
}  // namespace pcl
