// `pcl_patchdict denoise CLOUD -o OUT` for point clouds (.pcd, or .ply without faces):
// SparsePatchCloudInpainter (statistical pre-filter, local quadric patches, residual outliers).
// A PCD keeps every field it has (colour, intensity, labels…) and its organisation; a PLY cloud
// keeps positions and normals. Lengths are in units of the cloud's largest bounding-box side.
#include "cli.h"
#include "cloud_input.h"

#include <pcl_patchdict/mesh_io.h>
#include <pcl_patchdict/sparse_patch_cloud_inpainter.h>

#include <pcl/common/io.h>
#include <pcl/conversions.h>

#include <cstdio>
#include <cstring>
#include <iostream>
#include <limits>

namespace pcl {
namespace patchdict {
namespace cli {

namespace {

const char* const kCloudUsage =
    "pcl_patchdict denoise CLOUD.pcd|CLOUD.ply -o OUT.pcd|OUT.ply [--noise S] [--bandwidth H] [--no-outlier-filter] "
    "[--outlier-neighbours K] [--outlier-std M] [--residual-outliers F] [--json]";

// Offset and type of a named field of one value (float32 / float64), or nullptr.
const pcl::PCLPointField* findField(const pcl::PCLPointCloud2& blob, const char* name)
{
  for (const auto& field : blob.fields)
    if (field.name == name && field.count == 1 &&
        (field.datatype == pcl::PCLPointField::FLOAT32 || field.datatype == pcl::PCLPointField::FLOAT64))
      return &field;
  return nullptr;
}

void writeValue(pcl::PCLPointCloud2& blob, std::size_t point, const pcl::PCLPointField& field, double value)
{
  std::uint8_t* at = blob.data.data() + point * blob.point_step + field.offset;
  if (field.datatype == pcl::PCLPointField::FLOAT32) {
    const auto v = static_cast<float>(value);
    std::memcpy(at, &v, sizeof v);
  } else {
    std::memcpy(at, &value, sizeof value);
  }
}

}  // namespace

int runCloudDenoise(const std::vector<std::string>& raw)
{
  auto values = commonValueOptions();
  values.insert({"output", "noise", "bandwidth", "outlier-neighbours", "outlier-std", "residual-outliers"});
  auto flags = commonFlagOptions();
  flags.insert("no-outlier-filter");
  const Arguments args(raw, values, flags);
  args.expectPositionals(1, 1, kCloudUsage);
  if (!args.has("output"))
    throw UsageError("usage: " + std::string(kCloudUsage));
  applyCommonOptions(args);
  const bool quiet = args.has("quiet") || args.has("json");
  const std::string in_path = args.positionals()[0];
  const std::string out_path = args.get("output");
  checkOutputPath(out_path, in_path);
  const MeshFormat out_format = formatFromPath(out_path);
  if (out_format != MeshFormat::PCD && out_format != MeshFormat::PLY)
    throw Error("output '" + out_path + "' must be a cloud file (.pcd, or .ply written without faces)");
  CloudDenoisingParameters parameters;
  parameters.outlier_filter = !args.has("no-outlier-filter");
  parameters.outlier_neighbours = static_cast<int>(args.getInt("outlier-neighbours", 50, 1, 1000));
  parameters.outlier_std = args.getDouble("outlier-std", 1.0, 0.0, 1e6);
  parameters.residual_outlier_factor = args.getDouble("residual-outliers", 4.0, 0.0, 1e6);
  const double noise = args.getDouble("noise", 0.0, 0.0, 1.0);
  const double bandwidth = args.getDouble("bandwidth", 0.0, 0.0, 1.0);

  StageTimer timer(quiet);
  timer.start("load");
  CloudInput input = loadCloudInput(in_path);
  const pcl::PointCloud<pcl::PointNormal>::Ptr& cloud = input.cloud;
  const double scale = input.scale;  // largest bounding-box side: the unit of --noise and --bandwidth
  parameters.noise_sigma = noise * scale;
  parameters.bandwidth = bandwidth * scale;
  note(quiet, "  " + std::to_string(cloud->size()) + " points" +
                  (cloud->height > 1 ? " (organised " + std::to_string(cloud->width) + " x " +
                                           std::to_string(cloud->height) + ")"
                                     : std::string()) +
                  (input.has_normals ? ", with normals" : ""));

  timer.start("denoise");
  // Normals are computed (and oriented) only when the output keeps them: the input had them.
  pcl::PointCloud<pcl::PointNormal> denoised;
  CloudDenoisingReport report;
  pcl::Indices kept;
  if (input.has_normals) {
    SparsePatchCloudInpainter<pcl::PointNormal, pcl::PointNormal> inpainter;
    inpainter.setInputCloud(cloud);
    inpainter.setParameters(parameters);
    inpainter.process(denoised);
    report = inpainter.getReport();
    kept = inpainter.getKeptIndices();
  } else {
    SparsePatchCloudInpainter<pcl::PointNormal, pcl::PointXYZ> inpainter;
    inpainter.setInputCloud(cloud);
    inpainter.setParameters(parameters);
    pcl::PointCloud<pcl::PointXYZ> positions;
    inpainter.process(positions);
    pcl::copyPointCloud(positions, denoised);
    report = inpainter.getReport();
    kept = inpainter.getKeptIndices();
  }
  const std::size_t removed = report.outlier_filter_removed + report.residual_removed + report.unfit_removed;
  char line[240];
  std::snprintf(line, sizeof line,
                "  spacing %.4g, noise sigma %.4g (%s, %.2f x spacing), patch bandwidth %.2f x spacing; "
                "removed %zu outliers (%zu pre-filter, %zu off their patch, %zu without neighbours)",
                report.mean_spacing / scale, report.noise_sigma / scale, report.noise_estimated ? "estimated" : "given",
                report.noise_sigma / report.mean_spacing, report.bandwidth / report.mean_spacing, removed,
                report.outlier_filter_removed, report.residual_removed, report.unfit_removed);
  note(quiet, line);

  timer.start("write");
  if (out_format == MeshFormat::PCD && input.from_pcd) {
    // Every field carried: the input's records, with positions (and normals, if it has them) replaced.
    pcl::PCLPointCloud2 out;
    const pcl::PCLPointField* fx = findField(input.blob, "x");
    const pcl::PCLPointField* fy = findField(input.blob, "y");
    const pcl::PCLPointField* fz = findField(input.blob, "z");
    const pcl::PCLPointField* fnx = input.has_normals ? findField(input.blob, "normal_x") : nullptr;
    const pcl::PCLPointField* fny = input.has_normals ? findField(input.blob, "normal_y") : nullptr;
    const pcl::PCLPointField* fnz = input.has_normals ? findField(input.blob, "normal_z") : nullptr;
    const bool organised = denoised.height > 1;
    if (organised) {
      out = input.blob;
      for (std::size_t i = 0; i < denoised.size(); ++i) {
        const pcl::PointNormal& p = denoised[i];
        writeValue(out, i, *fx, p.x);
        writeValue(out, i, *fy, p.y);
        writeValue(out, i, *fz, p.z);
        if (fnx && fny && fnz) {
          writeValue(out, i, *fnx, p.normal_x);
          writeValue(out, i, *fny, p.normal_y);
          writeValue(out, i, *fnz, p.normal_z);
        }
      }
      out.is_dense = denoised.is_dense;
    } else {
      out.header = input.blob.header;
      out.fields = input.blob.fields;
      out.point_step = input.blob.point_step;
      out.is_bigendian = input.blob.is_bigendian;
      out.height = 1;
      out.width = static_cast<std::uint32_t>(kept.size());
      out.row_step = out.point_step * out.width;
      out.data.resize(static_cast<std::size_t>(out.row_step));
      for (std::size_t i = 0; i < kept.size(); ++i) {
        std::memcpy(out.data.data() + i * out.point_step,
                    input.blob.data.data() + static_cast<std::size_t>(kept[i]) * input.blob.point_step, out.point_step);
        const pcl::PointNormal& p = denoised[i];
        writeValue(out, i, *fx, p.x);
        writeValue(out, i, *fy, p.y);
        writeValue(out, i, *fz, p.z);
        if (fnx && fny && fnz) {
          writeValue(out, i, *fnx, p.normal_x);
          writeValue(out, i, *fny, p.normal_y);
          writeValue(out, i, *fnz, p.normal_z);
        }
      }
      out.is_dense = true;
    }
    writePointCloudBlob(out_path, out, input.origin, input.orientation);
  } else if (out_format == MeshFormat::PCD) {
    pcl::PCLPointCloud2 out;
    if (input.has_normals) {
      pcl::toPCLPointCloud2(denoised, out);
    } else {
      pcl::PointCloud<pcl::PointXYZ> positions;
      pcl::copyPointCloud(denoised, positions);
      pcl::toPCLPointCloud2(positions, out);
    }
    writePointCloudBlob(out_path, out, input.origin, input.orientation);
  } else {
    TriangleMesh out;  // vertices only: a PLY cloud
    for (const auto& p : denoised) {
      if (!std::isfinite(p.x))
        continue;
      out.vertices.emplace_back(p.x, p.y, p.z);
      if (input.has_normals)
        out.normals.emplace_back(p.normal_x, p.normal_y, p.normal_z);
    }
    writeMesh(out_path, out);
  }
  timer.stop();

  if (args.has("json")) {
    JsonObject json;
    json.add("command", "denoise").add("kind", "cloud").add("input", in_path).add("output", out_path);
    json.add("points_in", report.input_points).add("nonfinite_points", report.nonfinite_points);
    json.add("points_out", report.output_points).add("moved", report.output_points);
    json.add("added", std::size_t{0});
    json.add("removed_as_outliers", removed);
    json.add("removed_by_prefilter", report.outlier_filter_removed)
        .add("removed_off_patch", report.residual_removed)
        .add("removed_without_neighbours", report.unfit_removed);
    json.add("organised", cloud->height > 1).add("width", static_cast<std::size_t>(cloud->width))
        .add("height", static_cast<std::size_t>(cloud->height));
    json.add("spacing", report.mean_spacing / scale);
    json.add("noise_sigma", report.noise_sigma / scale).add("noise_estimated", report.noise_estimated);
    json.add("noise_sigma_over_spacing", report.noise_sigma / report.mean_spacing);
    json.add("bandwidth", report.bandwidth / scale).add("bandwidth_over_spacing", report.bandwidth / report.mean_spacing);
    json.add("mean_displacement", report.mean_displacement / scale);
    std::vector<JsonObject> risks;
    for (const auto& candidate : report.bandwidth_risks) {
      JsonObject r;
      r.add("bandwidth_over_spacing", candidate.factor).add("risk", candidate.risk / (scale * scale));
      r.add("mean_squared_residual", candidate.mean_squared_residual / (scale * scale));
      r.add("mean_leverage", candidate.mean_leverage);
      risks.push_back(r);
    }
    json.add("bandwidth_risks", risks);
    JsonObject stages;
    stages.add("search", report.seconds_search).add("outliers", report.seconds_outliers)
        .add("noise", report.seconds_noise).add("fit", report.seconds_fit).add("normals", report.seconds_normals);
    json.add("denoise_stages", stages).add("seconds", timer.json());
    std::cout << json.str() << '\n';
  } else if (!quiet) {
    std::printf("denoised %zu of %zu points (%zu outliers removed) -> %s\n", report.output_points,
                report.input_points, removed, out_path.c_str());
  }
  return 0;
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
