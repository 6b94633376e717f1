// `pcl_patchdict denoise CLOUD -o OUT` for point clouds (.pcd, or .ply without faces):
// GeometricCloudRepair (statistical pre-filter, local quadric patches, residual outliers).
// A PCD keeps every field it has (colour, intensity, labels…) and its organisation; a PLY cloud
// keeps positions and normals. Lengths are in units of the cloud's largest bounding-box side.
#include "cli.h"
#include "cloud_input.h"
#include "options.h"
#include "ring_scan.h"

#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict/cloud/geometric_cloud_repair.h>
#include <pcl_patchdict/cloud/sparse_patch_inpainter.h>
#include <pcl_patchdict/io/patch_dictionary_io.h>
#include <pcl_patchdict/io/sensor_model_io.h>

#include <pcl/common/io.h>
#include <pcl/conversions.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <limits>
#include <type_traits>

namespace pcl {
namespace patchdict {
namespace cli {

namespace {

using Inpainter = GeometricCloudRepair<pcl::PointNormal, pcl::PointNormal>;

/** The command line of a cloud repair, read and checked before the input is. */
struct CloudRepairLine {
  bool fill = false, quiet = false;
  std::string in_path, out_path;
  MeshFormat out_format = MeshFormat::Unknown;
  CloudRepairParameters parameters;
  double noise = 0.0, bandwidth = 0.0;  ///< in the units of --absolute's choice
  // fill-holes only (denoise keeps the library's defaults):
  CloudCompletionParameters completion;  ///< max_hole_diameter in those units; 0: each fill's own bound
  OrganizedFillParameters organized;
  std::string height_field = "auto";
  std::string patches = "measured";  ///< --patch-decision: measured or always
  std::size_t max_checked_points = NonlocalPatchOptions().max_checked_points;  ///< --max-checked-points
  SensorModel sensor_model;          ///< --sensor-model: the frames' saved sensor model (kind None: none)
  /// The bound the report names: the one given, or Poisson's own (CloudHoleCompletion's 0.15 × the
  /// largest side when max_hole_diameter is 0).
  double reportedMaxHoleDiameter() const
  {
    return completion.max_hole_diameter > 0.0 ? completion.max_hole_diameter : 0.15;
  }
};

/** What the inpainter made, with the input record of every output point. */
struct CloudRepairResult {
  Inpainter::Mode mode = Inpainter::Mode::Denoise;
  double scale = 1.0;  ///< the unit of the lengths given and reported
  pcl::PointCloud<pcl::PointNormal> denoised;
  CloudRepairReport report;
  pcl::Indices records;  ///< the input record of every output point (kept, then added)
  pcl::Indices filled;   ///< a depth image's filled pixels
  CloudPatchReport patches;  ///< the patch stage of an unorganised fill
  CloudPatchReport denoise_patches;  ///< …and of the denoising
  NonlocalPatchReport nonlocal_patches;  ///< the denoising's non-local stage
  std::size_t removed() const
  {
    return report.outlier_filter_removed + report.residual_removed + report.unfit_removed;
  }
};

// 1. The command line.
CloudRepairLine readCloudRepairLine(const Arguments& args, bool fill)
{
  if (args.has("no-outlier-filter")) {
    args.refuse("outlier-neighbours", "tunes the outlier pre-filter, which --no-outlier-filter turns off");
    args.refuse("outlier-std", "tunes the outlier pre-filter, which --no-outlier-filter turns off");
  }
  CloudRepairLine line;
  line.fill = fill;
  line.quiet = args.quiet();
  line.in_path = args.positionals()[0];
  line.out_path = args.get("output");
  checkOutputPath(line.out_path, line.in_path);
  line.out_format = formatFromPath(line.out_path);
  if (line.out_format != MeshFormat::PCD && line.out_format != MeshFormat::PLY)
    throw Error("output '" + line.out_path + "' must be a cloud file (.pcd, or .ply written without faces)");
  CloudRepairParameters& parameters = line.parameters;
  parameters.outlier_filter = !args.has("no-outlier-filter");
  parameters.outlier_neighbours = static_cast<int>(args.getInt("outlier-neighbours"));
  parameters.outlier_std = args.getDouble("outlier-std");
  parameters.residual_outlier_factor = args.getDouble("residual-outliers");
  line.noise = args.getDouble("noise");
  line.bandwidth = args.getDouble("bandwidth");
  if (fill) {
    // Not given: each fill's own bound (Poisson's gaps 0.15 × the largest side, a depth image's
    // max_hole_pixels, a height field's 150 spacings).
    line.completion.max_hole_diameter = args.getDouble("max-hole-diameter", 0.0);
    line.completion.rim_width = args.getDouble("rim-width");
    line.organized.max_hole_pixels = static_cast<std::size_t>(args.getInt("max-hole-pixels"));
    line.organized.fit_ring = static_cast<int>(args.getInt("fit-ring"));
    line.height_field = args.getWord("height-field");
  }
  line.patches = args.getWord("patch-decision");
  line.max_checked_points = static_cast<std::size_t>(args.getInt("max-checked-points"));
  if (args.has("sensor-model"))
    line.sensor_model = loadSensorModel(args.get("sensor-model"));  // checked before the input is read
  return line;
}

// 2. The repair: the inpainter (with or without normals), its completion and fill settings.
CloudRepairResult repairCloud(const Arguments& args, const CloudRepairLine& line, const CloudInput& input)
{
  const pcl::PointCloud<pcl::PointNormal>::Ptr& cloud = input.cloud;
  CloudRepairResult result;
  // Lengths (--noise, --bandwidth, --max-hole-diameter, and the report's) are in units of the largest
  // bounding-box side, or the cloud's own with --absolute.
  result.scale = args.has("absolute") ? 1.0 : input.scale;
  const double scale = result.scale;
  CloudRepairParameters parameters = line.parameters;
  parameters.noise_sigma = line.noise * scale;
  parameters.bandwidth = line.bandwidth * scale;
  result.mode = !line.fill ? Inpainter::Mode::Denoise
                : args.has("denoise") ? Inpainter::Mode::DenoiseAndComplete
                                      : Inpainter::Mode::Complete;
  PatchDictionary::ConstPtr dictionary;
  if (args.has("dict"))
    dictionary = loadPatchDictionary(args.get("dict"));
  // An unorganised spinning-LiDAR scan with a ring field is repaired on its beams × azimuth grid.
  RingScan ring_scan;
  const bool by_ring = readRingScan(input, ring_scan);
  const auto run = [&](auto& inpainter, auto& out) {
    auto& base = inpainter.getGeometricRepair();
    inpainter.setInputCloud(by_ring ? ring_scan.organised : cloud);
    base.setParameters(parameters);
    // An unorganised PCD whose VIEWPOINT is not the default one was seen from there.
    if (cloud->height <= 1 && input.from_pcd && !by_ring &&
        (!input.origin.head<3>().isZero() || !input.orientation.isApprox(Eigen::Quaternionf::Identity())))
      base.setViewpoint((input.origin.head<3>().cast<double>() - input.offset).eval());
    inpainter.setMode(static_cast<typename std::decay_t<decltype(inpainter)>::Mode>(static_cast<int>(result.mode)));
    CloudCompletionParameters completion = line.completion;
    completion.max_hole_diameter *= scale;
    base.setCompletionParameters(completion);
    base.setOrganizedFillParameters(line.organized);
    using Choice = typename std::decay_t<decltype(base)>::HeightField;
    base.setHeightField(line.height_field == "yes"  ? Choice::Always
                        : line.height_field == "no" ? Choice::Never
                                                    : Choice::Auto);
    if (line.sensor_model.kind != SensorModel::Kind::None)
      base.setSensorModel(line.sensor_model);
    inpainter.setDictionary(dictionary);
    NonlocalPatchOptions nonlocal = inpainter.getNonlocalPatchOptions();
    nonlocal.max_checked_points = line.max_checked_points;
    inpainter.setNonlocalPatchOptions(nonlocal);
    inpainter.setPatchDecision(args.has("no-patches")                 ? PatchDecision::Never
                               : line.patches == "always" ? PatchDecision::Always
                                                                     : PatchDecision::Auto);
    inpainter.process(out);
    result.report = inpainter.getReport();
    result.patches = inpainter.getPatchReport();
    result.denoise_patches = inpainter.getDenoisingPatchReport();
    result.nonlocal_patches = inpainter.getNonlocalPatchReport();
    result.records = inpainter.getKeptIndices();
    result.records.insert(result.records.end(), inpainter.getAddedSources().begin(), inpainter.getAddedSources().end());
    if (inpainter.getReport().depth_image || inpainter.getReport().range_image)
      result.filled = inpainter.getAddedSources();
  };
  // Normals are computed (and oriented) only when the output keeps them: the input had them.
  if (input.has_normals) {
    SparsePatchInpainter<pcl::PointNormal, pcl::PointNormal> inpainter;
    run(inpainter, result.denoised);
  } else {
    SparsePatchInpainter<pcl::PointNormal, pcl::PointXYZ> inpainter;
    pcl::PointCloud<pcl::PointXYZ> positions;
    run(inpainter, positions);
    pcl::copyPointCloud(positions, result.denoised);
  }
  if (by_ring) {
    if (!result.report.range_image)  // readRingScan fitted the grid: this would be a bug, not bad input
      throw Error("the scan's ring grid was not repaired as a range image");
    const pcl::PointCloud<pcl::PointNormal> grid = result.denoised;
    scatterRingRepair(ring_scan, input, grid, result.filled, result.denoised, result.records);
    result.report.points_added = result.records.size() - cloud->size();
    result.report.output_points = cloud->size();  // every input point, then the filled pixels
    result.report.input_points = cloud->size();
    result.filled.clear();
  }
  return result;
}

// 3. The notes on stderr.
void noteCloudRepair(const CloudRepairLine& line, const CloudRepairResult& result)
{
  const CloudRepairReport& report = result.report;
  const double scale = result.scale;
  const bool quiet = line.quiet, fill = line.fill;
  char text[240];
  std::snprintf(text, sizeof text,
                "  spacing %.4g, noise sigma %.4g (%s, %.2f x spacing), patch bandwidth %.2f x spacing; "
                "removed %zu outliers (%zu pre-filter, %zu off their patch, %zu without neighbours)",
                report.mean_spacing / scale, report.noise_sigma / scale, report.noise_estimated ? "estimated" : "given",
                report.noise_sigma / report.mean_spacing, report.bandwidth / report.mean_spacing, result.removed(),
                report.outlier_filter_removed, report.residual_removed, report.unfit_removed);
  note(quiet, text);
  if (fill && report.depth_image) {
    const OrganizedFillReport& f = report.organized_fill;
    std::snprintf(text, sizeof text,
                  "  depth image: %zu regions without depth; %zu holes filled (%zu pixels), %zu at depth "
                  "discontinuities, %zu open to the border, %zu too large; %zu fills in seen space dropped",
                  f.regions, f.holes_filled, f.pixels_filled, f.not_one_surface, f.touching_border, f.too_large,
                  f.free_space_dropped);
    note(quiet, text);
  } else if (fill && report.range_image) {
    const RangeFillReport& f = report.range_fill;
    std::snprintf(text, sizeof text,
                  "  range image (%zu beams x %zu columns): %zu regions without a return; %zu holes filled (%zu pixels), "
                  "%zu at range discontinuities, %zu at grazing incidence, %zu open to the first or last beam, %zu too large",
                  report.spinning.height, report.spinning.width, f.regions, f.holes_filled, f.pixels_filled,
                  f.not_one_surface, f.grazing, f.touching_border, f.too_large);
    note(quiet, text);
  } else if (fill && report.height_field_used) {
    const HeightFieldFillReport& h = report.height_field;
    std::snprintf(text, sizeof text,
                  "  height field (cell %.3g): %zu empty regions; %zu holes filled with %zu points, %zu open to the "
                  "outside, %zu sampling gaps, %zu too large",
                  h.cell_size / scale, h.empty_components, h.holes_filled, h.points_added, h.rejected_border,
                  h.rejected_too_small, h.rejected_too_big);
    note(quiet, text);
  } else if (fill) {
    const CloudCompletionReport& c = report.completion;
    std::snprintf(text, sizeof text,
                  "  Poisson depth %d: %zu gaps, %zu holes filled (%zu by implicits, %zu by splines), %zu from Poisson, "
                  "%zu wider than %.3g left open; %zu points added (lattice %.3g)",
                  c.poisson_depth, c.gaps, c.holes_filled, c.holes_implicit, c.holes_filled - c.holes_implicit,
                  c.holes_from_poisson, c.holes_too_large, line.reportedMaxHoleDiameter(),
                  c.points_added, c.lattice_spacing / scale);
    note(quiet, text);
  }
}

// 4b. A range image's filled pixels keep their own records (ring, time…); a float intensity field is
// interpolated from the measured pixels around them (interpolateAtFilledPixels, as the library does).
void interpolateIntensity(pcl::PCLPointCloud2& blob, const CloudInput& input, const CloudRepairResult& result)
{
  const pcl::PCLPointField* field = findScalarField(blob, "intensity");
  if (!field || !result.report.range_image)
    return;
  const std::size_t n = std::size_t(blob.width) * blob.height;
  std::vector<char> measured(n, 0);
  std::vector<double> values(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = (*input.cloud)[i];
    measured[i] = isReturn(Eigen::Vector3d(p.x, p.y, p.z));
    values[i] = readPointField(blob, i, *field);
  }
  const std::vector<std::size_t> filled(result.filled.begin(), result.filled.end());
  interpolateAtFilledPixels(values, measured, blob.width, blob.height, result.report.spinning.wraps, filled);
  for (const std::size_t i : filled)
    writeScalar(blob, i, *field, values[i]);
}

// 4a. A PCD read from a PCD: every field carried, the input's records with positions (and normals,
// if it has them) replaced.
void writeCarriedPcd(const CloudRepairLine& line, const CloudInput& input, const CloudRepairResult& result,
                     std::size_t unchanged)
{
  const pcl::PointCloud<pcl::PointNormal>& denoised = result.denoised;
  const pcl::PointCloud<pcl::PointNormal>& cloud = *input.cloud;
  const pcl::Indices& records = result.records;
  pcl::PCLPointCloud2 out;
  const pcl::PCLPointField* fx = findScalarField(input.blob, "x");
  const pcl::PCLPointField* fy = findScalarField(input.blob, "y");
  const pcl::PCLPointField* fz = findScalarField(input.blob, "z");
  const pcl::PCLPointField* fnx = input.has_normals ? findScalarField(input.blob, "normal_x") : nullptr;
  const pcl::PCLPointField* fny = input.has_normals ? findScalarField(input.blob, "normal_y") : nullptr;
  const pcl::PCLPointField* fnz = input.has_normals ? findScalarField(input.blob, "normal_z") : nullptr;
  const auto writePoint = [&](pcl::PCLPointCloud2& blob, std::size_t i, const pcl::PointNormal& p) {
    writeScalar(blob, i, *fx, p.x + input.offset.x());
    writeScalar(blob, i, *fy, p.y + input.offset.y());
    writeScalar(blob, i, *fz, p.z + input.offset.z());
    if (fnx && fny && fnz) {
      writeScalar(blob, i, *fnx, p.normal_x);
      writeScalar(blob, i, *fny, p.normal_y);
      writeScalar(blob, i, *fnz, p.normal_z);
    }
  };
  const bool organised = denoised.height > 1;
  if (organised) {
    out = input.blob;
    // Complete keeps every measured record as read: only filled pixels and dropped points change.
    std::vector<char> changed(denoised.size(), result.mode != Inpainter::Mode::Complete);
    for (const auto i : result.filled)
      changed[static_cast<std::size_t>(i)] = 1;
    for (std::size_t i = 0; i < denoised.size(); ++i)
      if (changed[i] || !std::isfinite(denoised[i].x))
        writePoint(out, i, denoised[i]);
    interpolateIntensity(out, input, result);
    out.is_dense = denoised.is_dense;
  } else {
    out.header = input.blob.header;
    out.fields = input.blob.fields;
    out.point_step = input.blob.point_step;
    out.is_bigendian = input.blob.is_bigendian;
    // Gross outliers (finite, but no measurement) are not carried even where the input is kept.
    std::vector<std::size_t> rows;
    for (std::size_t i = 0; i < records.size(); ++i)
      if (i >= unchanged || std::isfinite(cloud[static_cast<std::size_t>(records[i])].x) ||
          !input.positions[static_cast<std::size_t>(records[i])].allFinite())
        rows.push_back(i);
    out.height = 1;
    out.width = static_cast<std::uint32_t>(rows.size());
    out.row_step = out.point_step * out.width;
    out.data.resize(static_cast<std::size_t>(out.row_step));
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const std::size_t i = rows[k];
      std::memcpy(out.data.data() + k * out.point_step,
                  input.blob.data.data() + static_cast<std::size_t>(records[i]) * input.blob.point_step, out.point_step);
      if (i >= unchanged)  // Complete keeps the input's records as they are
        writePoint(out, k, denoised[i]);
    }
    out.is_dense = denoised.is_dense;
  }
  writePointCloudBlob(line.out_path, out, input.origin, input.orientation);
}

// 4. The output: a PCD with every field of a PCD input, a PCD of positions (and normals), or a
// PLY cloud.
void writeCloudOutput(const CloudRepairLine& line, const CloudInput& input, const CloudRepairResult& result)
{
  const pcl::PointCloud<pcl::PointNormal>& denoised = result.denoised;
  const pcl::PointCloud<pcl::PointNormal>& cloud = *input.cloud;
  const pcl::Indices& records = result.records;
  // Complete mode: the first output points are the input's, to be written exactly as read.
  const std::size_t unchanged = result.mode == Inpainter::Mode::Complete ? result.report.output_points : 0;
  const auto position = [&](std::size_t i) {
    if (i < unchanged && !std::isfinite(cloud[static_cast<std::size_t>(records[i])].x))
      return Eigen::Vector3d(Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN()));  // NaN or a gross outlier
    return i < unchanged ? input.positions[static_cast<std::size_t>(records[i])]
                         : Eigen::Vector3d(Eigen::Vector3d(denoised[i].x, denoised[i].y, denoised[i].z) + input.offset);
  };
  if (line.out_format == MeshFormat::PCD && input.from_pcd) {
    writeCarriedPcd(line, input, result, unchanged);
  } else if (line.out_format == MeshFormat::PCD) {
    pcl::PCLPointCloud2 out;
    pcl::PointCloud<pcl::PointNormal> placed(denoised);
    for (std::size_t i = 0; i < placed.size(); ++i)
      placed[i].getVector3fMap() = position(i).cast<float>();
    if (input.has_normals) {
      pcl::toPCLPointCloud2(placed, out);
    } else {
      pcl::PointCloud<pcl::PointXYZ> positions;
      pcl::copyPointCloud(placed, positions);
      pcl::toPCLPointCloud2(positions, out);
    }
    writePointCloudBlob(line.out_path, out, input.origin, input.orientation);
  } else {
    TriangleMesh out;  // vertices only: a PLY cloud (NaN points are not written)
    for (std::size_t i = 0; i < denoised.size(); ++i) {
      const pcl::PointNormal& p = denoised[i];
      const Eigen::Vector3d x = position(i);
      if (!x.allFinite())
        continue;
      out.vertices.push_back(x);
      if (input.has_normals)
        out.normals.emplace_back(p.normal_x, p.normal_y, p.normal_z);
    }
    writeMesh(line.out_path, out);
  }
}

// 5a. An organised frame processed as a depth image: its camera, noise law, fill and free space.
JsonObject depthImageJson(const CloudRepairResult& result, bool fill)
{
  const CloudRepairReport& report = result.report;
  JsonObject image, camera, law;
  camera.add("fx", report.camera.fx).add("fy", report.camera.fy).add("cx", report.camera.cx)
      .add("cy", report.camera.cy).add("rms_pixels", report.camera.rms_pixels);
  law.add("coefficient", report.depth_noise.coefficient).add("exponent", report.depth_noise.exponent)
      .add("exponent_fitted", report.depth_noise.exponent_fitted).add("samples", report.depth_noise.samples)
      .add("depth_low", report.depth_noise.depth_low).add("depth_high", report.depth_noise.depth_high);
  image.add("camera", camera).add("noise_law", law).add("off_ray_points", report.off_ray_points)
      .add("free_space_reverted", report.free_space_reverted);
  if (report.depth_denoised_in_image) {
    const DepthDenoisingReport& d = report.depth_denoising;
    JsonObject denoising;
    denoising.add("radius_near_pixels", d.radius_near).add("radius_far_pixels", d.radius_far)
        .add("depth_near", d.depth_near).add("depth_far", d.depth_far).add("moved", d.moved)
        .add("left", d.left).add("clamped", d.clamped).add("rms_shift_sigmas", d.rms_shift_sigmas)
        .add("seconds", d.seconds);
    image.add("denoising", denoising);
  }
  if (fill) {
    const OrganizedFillReport& f = report.organized_fill;
    JsonObject holes;
    holes.add("regions", f.regions).add("filled", f.holes_filled).add("touching_border", f.touching_border)
        .add("too_large", f.too_large).add("not_one_surface", f.not_one_surface)
        .add("pixels_filled", f.pixels_filled).add("free_space_dropped", f.free_space_dropped);
    const std::vector<long long> pixels(result.filled.begin(), result.filled.end());
    holes.add("filled_pixels", pixels);
    image.add("holes", holes);
  }
  return image;
}

JsonObject rangeImageJson(const CloudRepairResult& result, bool fill)
{
  const CloudRepairReport& report = result.report;
  const SpinningSensorModel& s = report.spinning;
  const RangeNoiseModel& n = report.range_noise;
  JsonObject image, sensor, law;
  sensor.add("beams", s.height).add("columns", s.width).add("wraps", s.wraps)
      .add("azimuth_step_degrees", s.azimuth_step * 180.0 / 3.14159265358979323846)
      .add("rms_degrees", s.rms_radians * 180.0 / 3.14159265358979323846);
  law.add("coefficient", n.coefficient).add("exponent", n.exponent).add("exponent_fitted", n.exponent_fitted)
      .add("quantum", n.quantum).add("samples", n.samples).add("range_low", n.range_low).add("range_high", n.range_high);
  image.add("sensor", sensor).add("noise_law", law).add("sensor_model_given", report.sensor_model_given)
      .add("off_ray_points", report.off_ray_points).add("seconds_sensor_model", report.seconds_sensor_model);
  if (result.mode != Inpainter::Mode::Complete) {
    const RangeDenoisingReport& d = report.range_denoising;
    JsonObject denoising;
    denoising.add("moved", d.moved).add("left", d.left).add("clamped", d.clamped)
        .add("free_space_clamped", d.free_space_clamped).add("rms_shift_sigmas", d.rms_shift_sigmas)
        .add("seconds", d.seconds);
    image.add("denoising", denoising);
  }
  if (fill) {
    const RangeFillReport& f = report.range_fill;
    JsonObject holes;
    holes.add("regions", f.regions).add("filled", f.holes_filled).add("touching_border", f.touching_border)
        .add("too_large", f.too_large).add("not_one_surface", f.not_one_surface)
        .add("grazing", f.grazing).add("pixels_filled", f.pixels_filled).add("free_space_dropped", f.free_space_dropped).add("seconds", report.completion.seconds_fill);
    image.add("holes", holes);
  }
  return image;
}

// 5. --json: a patch stage (lengths in the report's unit), then the whole report.
JsonObject patchStageJson(const CloudPatchReport& p, double scale)
{
  JsonObject patches;
  patches.add("decision", toString(p.outcome)).add("reason", p.reason);
  if (p.hole_diameter > 0.0)
    patches.add("holes", p.holes).add("hole_diameter", p.hole_diameter / scale);
  patches.add("gain", p.gain).add("dictionary_rms", p.dictionary_rms / scale)
      .add("smooth_rms", p.biharmonic_rms / scale).add("test_patches", p.test_patches)
      .add("self_similar", p.self_similar).add("quad_length", p.quad_length / scale)
      .add("patch_side", p.patch_side / scale).add("grid", p.grid_size).add("patches", p.patches)
      .add("patches_used", p.patches_used).add("moved", p.moved_points)
      .add("mean_correction", p.mean_correction / scale);
  if (p.base_error > 0.0)
    patches.add("base_error", p.base_error / scale).add("patch_error", p.patch_error / scale);
  patches.add("seconds_layout", p.seconds_layout)
      .add("seconds_check", p.seconds_check).add("seconds_patches", p.seconds_patches);
  return patches;
}

JsonObject nonlocalStageJson(const NonlocalPatchReport& p, double scale)
{
  JsonObject stage;
  stage.add("decision", toString(p.outcome)).add("reason", p.reason)
      .add("base_error", p.base_error / scale).add("patch_error", p.patch_error / scale).add("z", p.z)
      .add("scored_points", p.scored_points).add("moved", p.moved_points)
      .add("median_neighbours", p.median_neighbours).add("own_share", p.own_share)
      .add("mean_correction", p.mean_correction / scale)
      .add("seconds_check", p.seconds_check).add("seconds_apply", p.seconds_apply);
  return stage;
}

JsonObject cloudRepairJson(const CloudRepairLine& line, const CloudInput& input, const CloudRepairResult& result,
                           const StageTimer& timer)
{
  const CloudRepairReport& report = result.report;
  const double scale = result.scale;
  const bool fill = line.fill;
  const pcl::PointCloud<pcl::PointNormal>& cloud = *input.cloud;
  JsonObject json;
  json.add("command", fill ? "fill-holes" : "denoise").add("kind", "cloud").add("input", line.in_path).add("output", line.out_path);
  json.add("points_in", report.input_points).add("nonfinite_points", report.nonfinite_points);
  json.add("points_out", report.output_points + report.points_added)
      .add("moved", result.mode == Inpainter::Mode::Complete ? std::size_t{0} : report.output_points);
  json.add("added", report.points_added);
  if (fill) {
    const CloudCompletionReport& c = report.completion;
    JsonObject holes;
    holes.add("gaps", c.gaps).add("filled", c.holes_filled).add("too_large", c.holes_too_large)
        .add("implicit", c.holes_implicit).add("from_poisson", c.holes_from_poisson).add("max_hole_diameter", line.reportedMaxHoleDiameter())
        .add("poisson_depth", c.poisson_depth).add("poisson_faces", c.poisson_faces)
        .add("lattice_spacing", c.lattice_spacing / scale).add("density", c.density * scale * scale);
    json.add("holes", holes);
  }
  if (report.height_field_used) {
    const HeightFieldFillReport& h = report.height_field;
    JsonObject field;
    field.add("spacing", h.spacing / scale).add("cell", h.cell_size / scale)
        .add("raster_width", h.raster_width).add("raster_height", h.raster_height)
        .add("empty_components", h.empty_components).add("filled", h.holes_filled)
        .add("open_to_outside", h.rejected_border).add("too_large", h.rejected_too_big)
        .add("sampling_gaps", h.rejected_too_small).add("without_rim", h.rejected_no_rim)
        .add("points_added", h.points_added).add("seconds", h.seconds);
    json.add("height_field", field);
  }
  if (report.depth_image)
    json.add("depth_image", depthImageJson(result, fill));
  if (report.range_image)
    json.add("range_image", rangeImageJson(result, fill));
  if (!report.depth_image && !report.range_image) {
    if (fill)
      json.add("patches", patchStageJson(result.patches, scale));
    if (result.mode != Inpainter::Mode::Complete) {
      json.add("denoise_patches", patchStageJson(result.denoise_patches, scale));
      json.add("nonlocal_patches", nonlocalStageJson(result.nonlocal_patches, scale));
    }
  }
  if (fill && !report.depth_image)
    json.add("free_space_dropped", report.free_space_dropped);
  json.add("removed_as_outliers", result.removed());
  json.add("removed_by_prefilter", report.outlier_filter_removed)
      .add("removed_off_patch", report.residual_removed)
      .add("removed_without_neighbours", report.unfit_removed);
  json.add("organised", cloud.height > 1).add("width", static_cast<std::size_t>(cloud.width))
      .add("height", static_cast<std::size_t>(cloud.height));
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
  if (fill)
    stages.add("poisson", report.completion.seconds_poisson).add("gaps", report.completion.seconds_gaps)
        .add("fill", report.completion.seconds_fill);
  json.add("denoise_stages", stages).add("seconds", timer.json());
  return json;
}

}  // namespace

// denoise (fill = false) or fill-holes (fill = true) on a cloud.
int runCloudRepair(const std::vector<std::string>& raw, bool fill)
{
  const Arguments args = readCommandLine(raw, commandSpec(fill ? "fill-holes" : "denoise", "cloud"));
  const CloudRepairLine line = readCloudRepairLine(args, fill);

  StageTimer timer(line.quiet);
  timer.start("load");
  const CloudInput input = loadCloudInput(line.in_path);  // an unreadable input is reported first
  if (args.has("self-similar") && (args.has("dict") || args.has("no-patches")))
    throw UsageError("--self-similar excludes --dict and --no-patches");
  if (args.has("dict") && args.has("no-patches"))
    throw UsageError("--dict excludes --no-patches");
  if (args.has("no-patches") && args.has("patch-decision"))
    throw UsageError("--no-patches excludes --patch-decision");
  const pcl::PointCloud<pcl::PointNormal>::Ptr& cloud = input.cloud;
  note(line.quiet, "  " + std::to_string(cloud->size()) + " points" +
                       (cloud->height > 1 ? " (organised " + std::to_string(cloud->width) + " x " +
                                                std::to_string(cloud->height) + ")"
                                          : std::string()) +
                       (input.has_normals ? ", with normals" : ""));

  timer.start("denoise");
  const CloudRepairResult result = repairCloud(args, line, input);
  noteCloudRepair(line, result);

  timer.start("write");
  writeCloudOutput(line, input, result);
  timer.stop();

  const CloudRepairReport& report = result.report;
  if (args.has("json")) {
    std::cout << cloudRepairJson(line, input, result, timer).str() << '\n';
  } else if (!line.quiet) {
    if (fill)
      std::printf("filled %zu holes with %zu points; %zu points kept of %zu (%zu outliers removed) -> %s\n",
                  report.completion.holes_filled + report.completion.holes_from_poisson, report.points_added,
                  report.output_points, report.input_points, result.removed(), line.out_path.c_str());
    else
      std::printf("denoised %zu of %zu points (%zu outliers removed) -> %s\n", report.output_points,
                  report.input_points, result.removed(), line.out_path.c_str());
  }
  return 0;
}

int runCloudDenoise(const std::vector<std::string>& raw) { return runCloudRepair(raw, false); }
int runCloudFillHoles(const std::vector<std::string>& raw) { return runCloudRepair(raw, true); }

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
