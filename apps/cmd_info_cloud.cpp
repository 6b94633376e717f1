// `pcl_patchdict info CLOUD`: what a cloud user needs to know before repairing it — organisation,
// finite points, spacing, and for a depth image its camera and its noise law σ(z) = a·z^p.
#include "cli.h"
#include "cloud_input.h"

#include <pcl_patchdict/cloud/depth_image.h>
#include <pcl_patchdict/cloud/gross_outliers.h>
#include <pcl_patchdict/cloud/height_field_hole_filling.h>

#include <pcl/kdtree/kdtree_flann.h>

#include <algorithm>
#include <cstdio>
#include <iostream>

namespace pcl {
namespace patchdict {
namespace cli {

namespace {

// Median distance to the nearest other point over up to 20000 evenly spaced finite points.
double medianSpacing(const pcl::PointCloud<pcl::PointNormal>::Ptr& cloud)
{
  auto finite = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  for (const auto& p : *cloud)
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))
      finite->push_back(p);
  if (finite->size() < 2)
    return 0.0;
  pcl::KdTreeFLANN<pcl::PointNormal> tree;
  tree.setInputCloud(finite);
  std::vector<double> nearest;
  pcl::Indices found;
  std::vector<float> squared;
  const std::size_t stride = std::max<std::size_t>(1, finite->size() / 20000);
  for (std::size_t i = 0; i < finite->size(); i += stride)
    if (tree.nearestKSearch((*finite)[i], 2, found, squared) == 2)
      nearest.push_back(std::sqrt(static_cast<double>(squared[1])));
  std::nth_element(nearest.begin(), nearest.begin() + static_cast<std::ptrdiff_t>(nearest.size() / 2), nearest.end());
  return nearest[nearest.size() / 2];
}

}  // namespace

int runCloudInfo(const Arguments& args)
{
  const std::string path = args.positionals()[0];
  const CloudInput input = loadCloudInput(path);
  const auto& cloud = *input.cloud;
  std::vector<Eigen::Vector3d> points(cloud.size());
  std::size_t finite = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    points[i] = Eigen::Vector3d(cloud[i].x, cloud[i].y, cloud[i].z);
    finite += points[i].allFinite() ? 1 : 0;
  }
  const std::vector<std::size_t> first = firstCopies(points);
  std::size_t copies = 0;
  for (std::size_t i = 0; i < first.size(); ++i)
    copies += first[i] != i ? 1 : 0;
  const bool organised = cloud.height > 1;
  const DepthImage image = organised ? makeDepthImage(points, cloud.width, cloud.height) : DepthImage{};
  const DepthNoiseModel law = image.camera.valid ? estimateDepthNoise(image) : DepthNoiseModel{};
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const bool height_field = !organised && isHeightFieldCloud(points, &up);
  const double spacing = medianSpacing(input.cloud);
  JsonObject json;
  json.add("command", "info").add("input", path).add("kind", "cloud").add("points", cloud.size())
      .add("finite_points", finite).add("gross_outliers", input.gross_outliers).add("exact_copies", copies)
      .add("organised", organised).add("width", static_cast<std::size_t>(cloud.width))
      .add("height", static_cast<std::size_t>(cloud.height)).add("has_normals", input.has_normals)
      .add("bbox_largest_side", input.scale).add("spacing", spacing);
  JsonObject viewpoint;
  viewpoint.add("x", static_cast<double>(input.origin.x())).add("y", static_cast<double>(input.origin.y()))
      .add("z", static_cast<double>(input.origin.z())).add("qw", static_cast<double>(input.orientation.w()))
      .add("qx", static_cast<double>(input.orientation.x())).add("qy", static_cast<double>(input.orientation.y()))
      .add("qz", static_cast<double>(input.orientation.z()));
  json.add("viewpoint", viewpoint).add("height_field", height_field);
  std::string summary = std::to_string(cloud.size()) + " points, " + std::to_string(finite) + " finite" +
                        (organised ? ", organised " + std::to_string(cloud.width) + " x " + std::to_string(cloud.height)
                                   : ", unorganised") +
                        (input.gross_outliers ? ", " + std::to_string(input.gross_outliers) + " gross outliers" : "") +
                        (copies ? ", " + std::to_string(copies) + " exact copies" : "");
  char line[400];
  std::snprintf(line, sizeof line, "\n  spacing %.4g (median nearest neighbour)%s", spacing,
                height_field ? ", 2.5-D (a height field over its dominant plane)" : "");
  summary += line;
  if (image.camera.valid) {
    JsonObject camera, noise;
    camera.add("fx", image.camera.fx).add("fy", image.camera.fy).add("cx", image.camera.cx).add("cy", image.camera.cy)
        .add("rms_pixels", image.camera.rms_pixels).add("off_ray_points", image.camera.off_ray);
    const double low = law.depth_low, high = law.depth_high;
    noise.add("coefficient", law.coefficient).add("exponent", law.exponent).add("exponent_fitted", law.exponent_fitted)
        .add("samples", law.samples).add("depth_low", low).add("depth_high", high)
        .add("sigma_at_depth_low", law.sigma(low)).add("sigma_at_depth_high", law.sigma(high))
        .add("spacing_at_depth_low", image.camera.pixelSpacing(low))
        .add("spacing_at_depth_high", image.camera.pixelSpacing(high));
    json.add("camera", camera).add("depth_noise", noise);
    std::snprintf(line, sizeof line,
                  "\n  depth image: camera f %.1f x %.1f, centre (%.1f, %.1f), %zu points off their rays"
                  "\n  depth %.3g to %.3g (5th-95th percentile): pixel spacing %.3g to %.3g, noise %.3g to %.3g"
                  " (sigma = %.3g z^%.2f, %s)",
                  image.camera.fx, image.camera.fy, image.camera.cx, image.camera.cy, image.camera.off_ray, low, high,
                  image.camera.pixelSpacing(low), image.camera.pixelSpacing(high), law.sigma(low), law.sigma(high),
                  law.coefficient, law.exponent, law.exponent_fitted ? "exponent fitted" : "exponent 2 assumed");
    summary += line;
  } else if (organised) {
    summary += "\n  its grid is no pinhole image: repaired as an unorganised cloud";
  }
  if (args.has("json"))
    std::cout << json.str() << '\n';
  else
    std::cout << path << " (cloud)\n  " << summary << '\n';
  return 0;
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
