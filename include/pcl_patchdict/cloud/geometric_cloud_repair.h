// GeometricCloudRepair — the geometric base of the cloud path (pcl::CloudSurfaceProcessing, shaped like
// pcl::MovingLeastSquares): local quadrics, spline and implicit fills, depth images; no patches.
#pragma once

#include <pcl_patchdict/cloud/cloud_hole_completion.h>
#include <pcl_patchdict/cloud/depth_image_denoising.h>
#include <pcl_patchdict/cloud/height_field_hole_filling.h>
#include <pcl_patchdict/cloud/local_quadric_projection.h>
#include <pcl_patchdict/cloud/organized_hole_filling.h>
#include <pcl_patchdict/cloud/range_image_repair.h>
#include <pcl_patchdict/cloud/sensor_model.h>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/search.h>
#include <pcl/surface/processing.h>

#include <Eigen/Core>

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace pcl {
namespace patchdict {

/** Parameters of the cloud path (lengths absolute, in the cloud's own units; 0 = automatic). */
struct CloudRepairParameters {
  /// Statistical pre-filter (as pcl::StatisticalOutlierRemoval): a point whose mean distance to its
  /// outlier_neighbours nearest is above mean + outlier_std × stddev of that over all points, and
  /// above 2.5 × the mean (so a regular grid keeps its rim and corners), goes.
  bool outlier_filter = true;
  int outlier_neighbours = 50;
  double outlier_std = 1.0;
  /// σ of the noise along the normals; 0 = estimated: 1.4826 × median |leave-one-out residual| of
  /// local quadrics at bandwidth 3 s (frame and fit without the point), over up to noise_sample
  /// evenly spaced points, divided by √(1 + their mean leverage) (the prediction's own variance).
  /// The bandwidth's risk is estimated over the same sample.
  double noise_sigma = 0.0;
  int noise_sample = 8000;
  /// h of the local patches; 0 = chosen among bandwidth_candidates × s (s the mean
  /// nearest-neighbour spacing) by Stein's unbiased risk estimate over the noise sample.
  double bandwidth = 0.0;
  std::vector<double> bandwidth_candidates{2.0, 2.5, 3.0, 3.5, 4.0, 5.0, 6.0, 7.0, 8.0, 10.0};
  /// Weight of the degrees-of-freedom term of the risk (Stein's: 1). The fit is not linear in the
  /// data — its PCA frame moves with the noise — and with 1 the risk chooses too narrow a bandwidth
  /// (docs/real_sensor_scans.md, "Figures behind the defaults").
  double leverage_weight = 2.0;
  /// A point farther than this × σ from its patch's height fit without it (its frame kept) is an
  /// outlier the pre-filter missed and is removed (0 keeps every fitted
  /// point), and never closer than two spacings s (clean samples of a curved or faceted surface
  /// have heavy-tailed residuals). Gaussian inliers beyond 4σ: 0.006 %.
  double residual_outlier_factor = 4.0;
  int min_neighbours = 8;  ///< fewer usable neighbours within the support: tried at 2h, 4h, then removed
  int max_neighbours = 192;
  int num_threads = 0;
};

struct CloudRepairReport {
  std::size_t input_points = 0;        ///< points processed (the indices, or the whole cloud)
  std::size_t nonfinite_points = 0;    ///< NaN/Inf positions (left as NaN in an organised output)
  std::size_t outlier_filter_removed = 0;  ///< by the statistical pre-filter
  std::size_t residual_removed = 0;    ///< farther than residual_outlier_factor × σ from their patch
  std::size_t unfit_removed = 0;       ///< too few neighbours for a patch
  std::size_t output_points = 0;       ///< finite points written
  double mean_spacing = 0.0;           ///< s, of the points kept by the pre-filter
  double noise_sigma = 0.0;            ///< σ used
  bool noise_estimated = false;
  double bandwidth = 0.0;              ///< h used
  /// Depth law (denoiseCloud given PointScales): σ_i and s_i per point, h_i = bandwidth_factor × s_i;
  /// noise_sigma and bandwidth are then the medians of σ_i and h_i, mean_spacing the mean s_i.
  bool depth_law = false;
  double bandwidth_factor = 0.0;       ///< h / s
  /// Depth law, automatic h: correlation of the noise heights at 0.5, 1, … 6 spacings (bins of half
  /// a spacing), and κ, the mean correlation-weighted neighbour count at the chosen h that
  /// multiplies the leverage in the risk (1 for white noise).
  std::vector<double> noise_correlation;
  double correlation_sum = 0.0;
  struct BandwidthRisk {
    double factor = 0.0;           ///< h / s
    double risk = 0.0;             ///< estimated mean squared height error
    double mean_squared_residual = 0.0, mean_leverage = 0.0;
  };
  std::vector<BandwidthRisk> bandwidth_risks;  ///< one per candidate tried
  double mean_displacement = 0.0;      ///< mean |moved − input| over the output points
  bool normals_computed = false;       ///< the output type has normals (they are the patches')
  std::string normal_orientation;      ///< "input normals", "viewpoint" or "propagation"
  std::size_t normals_flipped = 0;
  double seconds_search = 0.0, seconds_outliers = 0.0, seconds_noise = 0.0, seconds_fit = 0.0,
         seconds_normals = 0.0;
  std::size_t points_added = 0;        ///< completion: new points (after the kept ones)
  CloudCompletionReport completion;    ///< what the completion did (Complete modes)
  /// An organised input whose pixel grid is a pinhole image is processed as a depth image: the
  /// camera fitted to it, its noise law, the in-place fill, and the free-space test (depth_image.h).
  bool depth_image = false;
  PinholeCamera camera;
  DepthNoiseModel depth_noise;
  OrganizedFillReport organized_fill;
  /// An unorganised 2.5-D cloud (isHeightFieldCloud) completed over its plane (Complete modes).
  bool height_field_used = false;
  HeightFieldFillReport height_field;
  std::size_t duplicate_points = 0;     ///< exact copies of an earlier point: they follow it
  std::size_t gross_outliers = 0;       ///< finite points no sensor measured (removeGrossOutliers): NaN
  std::size_t off_ray_points = 0;       ///< finite points far from their pixel's ray: not points (NaN)
  std::size_t free_space_reverted = 0;
  /// Denoise modes on a depth image: denoised in image space (denoiseDepthImage), and how.
  bool depth_denoised_in_image = false;
  DepthDenoisingReport depth_denoising;
  /// Unorganised input with a viewpoint (setViewpoint): new points it saw through, dropped.
  std::size_t free_space_dropped = 0;  ///< denoised points the sensor saw through: kept as measured
  /// An organised input whose grid is a spinning LiDAR's (rows = beams, columns = azimuth steps) is
  /// processed as a range image (range_image.h): denoised along the beams, filled in place.
  bool range_image = false;
  SpinningSensorModel spinning;
  RangeNoiseModel range_noise;
  RangeFillReport range_fill;
  RangeDenoisingReport range_denoising;
  /// The sensor model came from setSensorModel (true) or was estimated from this cloud.
  bool sensor_model_given = false;
  double seconds_sensor_model = 0.0;   ///< fitting the model and building the image
};

namespace detail {
/** Per-query scales of a sensor with a known noise law (an organised depth image): σ_i of the noise
  * along the view at the point's depth, and s_i the spacing of its pixels there. */
struct PointScales {
  std::vector<double> sigma, spacing;
};
using KnnSearch = std::function<void(std::size_t query, int k, pcl::Indices& indices, std::vector<float>& squared)>;

/** The type-free core of GeometricCloudRepair: positions (NaN = not a point), optional input
  * normals (empty, or one per point; zero = none), the queries to process, searches over the
  * positions. Fills kept flags (one per query), positions and normals (one per query). */
void denoiseCloud(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                  const std::vector<std::size_t>& queries, const KnnSearch& knn,
                  const RadiusNeighbourSearch& radius, const CloudRepairParameters& parameters,
                  bool want_normals, const Eigen::Vector3d* viewpoint, std::vector<char>& kept,
                  std::vector<Eigen::Vector3d>& out_positions, std::vector<Eigen::Vector3d>& out_normals,
                  CloudRepairReport& report, const PointScales* scales = nullptr);

struct CloudRun;  // performProcessing's state between its stages (impl/geometric_cloud_repair.hpp)
struct DepthRun;  // processDepthImage's (impl/geometric_cloud_repair_depth_image.hpp)
}  // namespace detail

/** \brief Denoises a point cloud with local height-field patches (the cloud variant of
  * denoiseWithPatches; docs/design.md, the point-cloud path):
  *
  *  1. statistical pre-filter of gross outliers (on by default, counted in the report);
  *  2. s = mean nearest-neighbour spacing; σ estimated from leave-one-out patch residuals (or given);
  *  3. every point's patch: its neighbours within 2h, Gaussian-weighted (h from σ and s), in their
  *     PCA frame, fitted with a quadric height field (fitLocalQuadrics); the point moves along the
  *     normal onto it, and points left farther than 4σ from their own patch are removed;
  *  4. output normals (when PointOutT has them) are the patches' normals, oriented like the input's
  *     normals, towards the viewpoint (setViewpoint, or the sensor origin of an organised cloud), or
  *     else consistently by Hoppe et al.'s propagation (outward for a closed shape);
  *  5. Complete modes: completeCloudHoles adds points in the holes (the gaps of the Poisson surface
  *     no wider than the maximum hole diameter) at the input's density; their other fields are
  *     copied from the nearest input point. Poisson's caps over wider openings never become points.
  *
  * Other fields (colour, intensity, labels…) are carried from the input point to the moved one.
  * In Denoise mode an organised input (height > 1, whole: no indices or all of them in order) keeps
  * its width and height: removed and non-finite points become NaN (is_dense false); otherwise the
  * kept points come in input (index) order, followed by the new ones in the Complete modes.
  *
  * Measured against PCL's StatisticalOutlierRemoval + MovingLeastSquares at its best radius on the
  * harness's noisy clouds: see README "Point clouds". Deterministic for a given input and
  * parameters, whatever the thread count. Throws pcl::patchdict::Error for bad input or parameters
  * (fewer than 100 finite points, non-finite parameters, ...). */
template <typename PointInT, typename PointOutT = PointInT>
class GeometricCloudRepair : public pcl::CloudSurfaceProcessing<PointInT, PointOutT> {
public:
  using Ptr = std::shared_ptr<GeometricCloudRepair<PointInT, PointOutT>>;
  using ConstPtr = std::shared_ptr<const GeometricCloudRepair<PointInT, PointOutT>>;
  using PointCloudIn = pcl::PointCloud<PointInT>;
  using PointCloudOut = pcl::PointCloud<PointOutT>;
  using KdTreePtr = typename pcl::search::Search<PointInT>::Ptr;

  /** Denoise: every kept point moved onto its patch. Complete: the output is the processed input
    * unchanged and whole (fields, NaN points and outliers included: outliers are only kept out of
    * the surface the holes are filled from), followed by the new points. DenoiseAndComplete: the
    * denoised points, then the new ones filled from them. */
  enum class Mode { Denoise, Complete, DenoiseAndComplete };

  GeometricCloudRepair() = default;

  void setMode(Mode mode) { mode_ = mode; }
  Mode getMode() const { return mode_; }
  void setCompletionParameters(const CloudCompletionParameters& parameters) { completion_ = parameters; }
  const CloudCompletionParameters& getCompletionParameters() const { return completion_; }
  /** Holes wider than this stay open (absolute units; 0: 0.15 × the cloud's largest bbox side). */
  void setMaxHoleDiameter(double diameter) { completion_.max_hole_diameter = diameter; }

  /** Search over the input cloud (default: a pcl::search::KdTree made for it). */
  void setSearchMethod(const KdTreePtr& tree) { tree_ = tree; }
  KdTreePtr getSearchMethod() const { return tree_; }

  void setParameters(const CloudRepairParameters& parameters) { parameters_ = parameters; }
  const CloudRepairParameters& getParameters() const { return parameters_; }
  void setOutlierFilter(bool enabled) { parameters_.outlier_filter = enabled; }
  void setOutlierFilterParameters(int neighbours, double std_mul)
  {
    parameters_.outlier_neighbours = neighbours;
    parameters_.outlier_std = std_mul;
  }
  /** σ of the noise along the normals, in the cloud's units (0: estimated). */
  void setNoiseSigma(double sigma) { parameters_.noise_sigma = sigma; }
  /** h of the patches, in the cloud's units (0: from σ and the spacing). */
  void setBandwidth(double bandwidth) { parameters_.bandwidth = bandwidth; }
  void setResidualOutlierFactor(double factor) { parameters_.residual_outlier_factor = factor; }
  void setNumberOfThreads(int threads) { parameters_.num_threads = threads; }
  /** Where the sensor was: output normals point towards it. */
  void setViewpoint(const Eigen::Vector3d& viewpoint)
  {
    viewpoint_ = viewpoint;
    has_viewpoint_ = true;
  }
  /** Whether an organised input keeps its width × height (default true). A whole organised input
    * whose grid is a pinhole image (a Kinect or stereo frame) is then processed as a depth image:
    * points move along their pixels' rays, holes are NaN regions enclosed by one surface, filled in
    * place, and no point is left in space the sensor saw through (README "Real sensor scans"). */
  void setKeepOrganized(bool keep) { keep_organized_ = keep; }
  /** Unorganised clouds in the Complete modes: Auto completes a 2.5-D cloud (isHeightFieldCloud:
    * aerial LiDAR, terrain) as a height field over its dominant plane, at its density, and any other
    * through Poisson's gaps (completeCloudHoles); Always and Never force one of the two. */
  enum class HeightField { Auto, Always, Never };
  void setHeightField(HeightField choice) { height_field_ = choice; }
  HeightField getHeightField() const { return height_field_; }
  /** The height-field fill (its max_hole_diameter: the completion's, when set; its up direction:
    * the cloud's dominant one under Auto). */
  void setHeightFieldFillParameters(const HeightFieldFillParameters& parameters) { height_field_fill_ = parameters; }
  /** Depth images are denoised in image space with the sensor's noise law (denoiseDepthImage: robust
    * local planes in 1/z over the pixel grid), unless this is off or σ or h is given (then: the
    * patches of the unorganised path, each point still moved along its ray). Default on. */
  void setDepthImageDenoising(bool enabled) { depth_image_denoising_ = enabled; }
  void setDepthDenoisingParameters(const DepthDenoisingParameters& parameters) { depth_denoising_ = parameters; }
  /** The sensor of the frames to come (a stream: estimated once, e.g. from the first frame's
    * getSensorModel(), or loaded with loadSensorModel). An organised input is then processed on this
    * model — no camera or beams are fitted, no noise law estimated — and a frame whose grid does not
    * fit it (another size, or its points off the model's rays) makes process() throw Error instead
    * of being misrepaired. */
  void setSensorModel(const SensorModel& model)
  {
    sensor_model_ = model;
    rays_ = model.kind == SensorModel::Kind::Spinning && model.spinning.valid ? spinningRays(model.spinning) : nullptr;
  }
  void clearSensorModel() { setSensorModel(SensorModel{}); }
  /** The sensor model of the last organised input processed (given, or estimated from it); kind None
    * when the last input was not organised or neither model fits it. */
  const SensorModel& getSensorModel() const { return used_sensor_model_; }
  /** The spinning-LiDAR path's fill and denoising (their max_hole_diameter: the completion's, when set). */
  void setRangeFillParameters(const RangeFillParameters& parameters) { range_fill_ = parameters; }
  const RangeFillParameters& getRangeFillParameters() const { return range_fill_; }
  void setRangeDenoisingParameters(const RangeDenoisingParameters& parameters) { range_denoising_ = parameters; }
  const RangeDenoisingParameters& getRangeDenoisingParameters() const { return range_denoising_; }
  /** The in-place fill of organised inputs (its max_hole_diameter: the completion's, when set). */
  void setOrganizedFillParameters(const OrganizedFillParameters& parameters) { organized_fill_ = parameters; }
  const OrganizedFillParameters& getOrganizedFillParameters() const { return organized_fill_; }

  /** What the last process() did. */
  const CloudRepairReport& getReport() const { return report_; }
  /** Input index of every kept input point of the last output, in output order (to carry data of
    * your own along; an organised output keeps the input's layout, and these are its kept cells).
    * Added points follow the kept ones in an unorganised output; getAddedSources() names, for each,
    * the input point its other fields (colour…) were copied from. In an organised output processed
    * as a depth image, getAddedSources() lists the filled pixels (each keeps its own fields: a
    * Kinect pixel without depth still has its colour). */
  const pcl::Indices& getKeptIndices() const { return kept_indices_; }
  const pcl::Indices& getAddedSources() const { return added_sources_; }

protected:
  void performProcessing(PointCloudOut& output) override;
  /** The organised path: denoise along the rays, fill in place, free-space test (depth_image.h).
    * Points and normals in the sensor's frame; x_output = R·x + o. */
  void processDepthImage(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals,
                         const DepthImage& image, const Eigen::Matrix3d& R, const Eigen::Vector3d& o,
                         PointCloudOut& output);

  /** The spinning-LiDAR path: denoise along the beams, fill in place (range_image_repair.h). Points
    * in the sensor's frame; x_output = R·x + o. */
  void processRangeImage(const std::vector<Eigen::Vector3d>& points, const RangeImage& image,
                         const RangeNoiseModel& noise, const Eigen::Matrix3d& R, const Eigen::Vector3d& o,
                         PointCloudOut& output);

private:
  // performProcessing's stages, in order.
  void readInput(detail::CloudRun& run);
  bool processAsDepthImage(const detail::CloudRun& run, PointCloudOut& output);
  bool processOnSensorModel(const detail::CloudRun& run, PointCloudOut& output);
  bool processAsRangeImage(const detail::CloudRun& run, PointCloudOut& output);
  void mergeCopies(detail::CloudRun& run);
  typename PointCloudIn::ConstPtr searchedCloud(const detail::CloudRun& run) const;
  void denoiseRun(detail::CloudRun& run, const detail::KnnSearch& knn, const RadiusNeighbourSearch& radius);
  void completeRun(detail::CloudRun& run);
  void followCopies(detail::CloudRun& run);
  void writeOutput(const detail::CloudRun& run, PointCloudOut& output);
  // processDepthImage's.
  void denoiseDepthInImage(detail::DepthRun& run);
  void denoiseDepthWithPatches(detail::DepthRun& run, const std::vector<Eigen::Vector3d>& normals);
  void fillDepthHoles(detail::DepthRun& run);
  void writeDepthOutput(const detail::DepthRun& run, const Eigen::Matrix3d& R, const Eigen::Vector3d& o,
                        PointCloudOut& output);
  void interpolateFilledIntensity(const detail::DepthRun& run, bool wraps, PointCloudOut& output) const;
  /** Position (and normal, if the type has one) of an output point; its other fields are copied. */
  static void place(PointOutT& out, const Eigen::Vector3d& position, const Eigen::Vector3d& normal);

  using pcl::CloudSurfaceProcessing<PointInT, PointOutT>::input_;
  using pcl::CloudSurfaceProcessing<PointInT, PointOutT>::indices_;

  KdTreePtr tree_;
  Mode mode_ = Mode::Denoise;
  CloudRepairParameters parameters_;
  CloudCompletionParameters completion_;
  OrganizedFillParameters organized_fill_;
  bool depth_image_denoising_ = true;
  DepthDenoisingParameters depth_denoising_;
  HeightField height_field_ = HeightField::Auto;
  HeightFieldFillParameters height_field_fill_;
  Eigen::Vector3d viewpoint_ = Eigen::Vector3d::Zero();
  bool has_viewpoint_ = false;
  bool keep_organized_ = true;
  SensorModel sensor_model_, used_sensor_model_;
  std::shared_ptr<const SpinningRays> rays_;  // the given spinning model's rays, computed once
  bool sensorModelGiven() const { return sensor_model_.kind != SensorModel::Kind::None; }
  RangeFillParameters range_fill_;
  RangeDenoisingParameters range_denoising_;
  CloudRepairReport report_;
  pcl::Indices kept_indices_, added_sources_;
};

}  // namespace patchdict
}  // namespace pcl

#ifdef PCL_NO_PRECOMPILE
#include <pcl_patchdict/cloud/impl/geometric_cloud_repair.hpp>
#endif
