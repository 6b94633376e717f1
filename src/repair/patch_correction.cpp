// PatchCorrection (see patch_correction.h). Patches and dictionaries: Sarkar, Varanasi & Stricker,
// "Learning quadrangulated patches for 3D shape parameterization and completion", 3DV 2017,
// sections 3–5; masked OMP and K-SVD as in sparse_coding.h; the confidence-weighted point-to-plane
// combination instead of the paper's overwrite is ours (measured: overwriting loses; docs/design.md).
#include <pcl_patchdict/repair/patch_correction.h>

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/patches/height_maps.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/quads/patch_layout.h>
#include <pcl_patchdict/patches/patch_mesh_reconstruction.h>
#include <pcl_patchdict/core/vertex_normals.h>

#include "geometry/point_search.h"

#include <pcl/kdtree/kdtree_flann.h>

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

namespace pcl {
namespace patchdict {

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/** Bilinear height of an N×N patch column at frame coordinates (u, v); bin centres as in
  * extractMeshHeightMaps, clamped at the border bins. */
double bilinearHeight(const Eigen::Ref<const Eigen::VectorXd>& heights, int n, double side, double u, double v)
{
  const double gx = std::clamp((u + 0.5 * side) / side * n - 0.5, 0.0, static_cast<double>(n - 1));
  const double gy = std::clamp((v + 0.5 * side) / side * n - 0.5, 0.0, static_cast<double>(n - 1));
  const int i0 = std::min(static_cast<int>(gx), n - 2);  // n ≥ 2 (checked with the parameters)
  const int j0 = std::min(static_cast<int>(gy), n - 2);
  const double fx = gx - i0, fy = gy - j0;
  const auto h = [&](int i, int j) { return heights(static_cast<Eigen::Index>(j) * n + i); };
  return (1 - fy) * ((1 - fx) * h(i0, j0) + fx * h(i0 + 1, j0)) + fy * ((1 - fx) * h(i0, j0 + 1) + fx * h(i0 + 1, j0 + 1));
}


int threadCount(int requested) { return requested > 0 ? requested : omp_get_max_threads(); }

}  // namespace

void PatchCorrection::checkParameters(const PatchCorrectionParameters& p)
{
  if (!(p.quad_length >= 0.0) || !std::isfinite(p.quad_length))
    throw Error("the quad length must be ≥ 0 (0: automatic)");
  if (!(p.quad_length_factor > 0.0) || !std::isfinite(p.quad_length_factor))
    throw Error("the quad length factor must be > 0");
  if (!(p.patch_scale > 0.0) || !std::isfinite(p.patch_scale))
    throw Error("the patch scale must be > 0");
  if (!std::isfinite(p.bin_reach) || p.bin_reach < 0.0 || p.bin_reach > 8.0)
    throw Error("the bin reach must be in [0, 8]");
  if (p.overlap < 0 || p.sparsity < 1 || p.smoothing_iterations < 0)
    throw Error("overlap and smoothing iterations must be ≥ 0, sparsity ≥ 1");
  if (!(p.error_per_bin >= 0.0) || !std::isfinite(p.error_per_bin))
    throw Error("the error target must be ≥ 0");
  for (double term : {p.centre_sigma, p.observed_power, p.fit_scale, p.agreement_scale})
    if (!(term >= 0.0) || !std::isfinite(term))
      throw Error("confidence parameters must be ≥ 0");
  if (!(p.min_observed_fraction >= 0.0 && p.min_observed_fraction <= 1.0))
    throw Error("the minimum observed fraction must be in [0, 1]");
  if ((p.grid_size != 0 && (p.grid_size < 2 || p.grid_size > 256)) || p.self_similar_atoms < 1 ||
      p.self_similar_iterations < 1)
    throw Error("bad self-similar dictionary parameters");
}

PatchLayoutParameters PatchCorrection::layoutParameters(const PatchCorrectionParameters& p, double quad_length)
{
  PatchLayoutParameters layout;
  layout.quad_length = quad_length;
  layout.overlap = p.overlap;
  layout.smoothing_iterations = p.smoothing_iterations;
  layout.seed = p.seed;
  layout.num_threads = p.num_threads;
  return layout;
}

double PatchCorrection::quadLength(const TriangleMesh& normalised_mesh, const PatchCorrectionParameters& parameters)
{
  return parameters.quad_length > 0.0 ? parameters.quad_length
                                      : parameters.quad_length_factor * normalised_mesh.meanEdgeLength();
}

PatchSet PatchCorrection::trainingPatches(const TriangleMesh& clean_mesh, const PatchCorrectionParameters& parameters,
                                          int grid_size)
{
  // The observed patches of a fully observed mesh: the same layout, L and side as a repair's.
  auto mesh = std::make_shared<TriangleMesh>(clean_mesh);
  UnitCubeNormalization::fromMesh(*mesh).apply(*mesh);
  PatchCorrectionParameters training = parameters;
  training.grid_size = grid_size;
  PatchCorrection correction;
  correction.setEstimate(mesh);
  correction.setParameters(training);
  return correction.observedPatches();
}

PatchDictionary::ConstPtr PatchCorrection::learnSelfSimilar(const Eigen::MatrixXd& usable_heights,
                                                         const ObservationMask& usable_mask,
                                                         const PatchCorrectionParameters& p)
{
  if (usable_heights.cols() == 0)
    throw Error("no observed patch to learn a self-similar dictionary from");
  const std::size_t usable_count = static_cast<std::size_t>(usable_heights.cols());
  const Eigen::Index bins = usable_heights.rows();
  auto learned = std::make_shared<PatchDictionary>();
  DictionaryLearningOptions options;
  options.num_atoms = std::min<int>(p.self_similar_atoms, static_cast<int>(usable_count));
  options.sparsity = std::min(p.sparsity, options.num_atoms);
  options.iterations = p.self_similar_iterations;
  options.seed = p.seed + 1;
  if (p.self_similar_max_patches > 0 && usable_count > static_cast<std::size_t>(p.self_similar_max_patches)) {
    // An evenly spaced subset: K-SVD time grows with the patch count, the atoms hardly do.
    const Eigen::Index count = p.self_similar_max_patches;
    Eigen::MatrixXd subset(bins, count);
    ObservationMask subset_mask(bins, count);
    for (Eigen::Index i = 0; i < count; ++i) {
      const auto column = static_cast<Eigen::Index>(static_cast<double>(i) * static_cast<double>(usable_count) /
                                                    static_cast<double>(count));
      subset.col(i) = usable_heights.col(column);
      subset_mask.col(i) = usable_mask.col(column);
    }
    learned->learn(subset, subset_mask, options);
  } else {
    learned->learn(usable_heights, usable_mask, options);
  }
  return learned;
}

void PatchCorrection::checkInput() const
{
  checkParameters(parameters_);
  const PatchCorrectionParameters& p = parameters_;
  if (!estimate_ || estimate_->empty() || (estimate_->faces.empty() && !(layout_ && observed_surface_)))
    throw Error("patch correction: no estimate mesh (with faces) given");
  const TriangleMesh& estimate = *estimate_;
  if (!observed_faces_.empty() && observed_faces_.size() != estimate.numFaces())
    throw Error("patch correction: " + std::to_string(observed_faces_.size()) + " observed-face flags for " +
                std::to_string(estimate.numFaces()) + " faces");
  for (std::int32_t v : targets_)
    if (v < 0 || static_cast<std::size_t>(v) >= estimate.numVertices())
      throw Error("patch correction: target vertex " + std::to_string(v) + " is out of range");
  if (dictionary_) {
    if (dictionary_->empty())
      throw Error("the dictionary has no atoms");
    if (dictionary_->gridSize() < 2)
      throw Error("the dictionary's atoms are not N×N patches");
    if (p.grid_size != 0 && dictionary_->gridSize() != p.grid_size)
      throw Error("the dictionary has " + std::to_string(dictionary_->gridSize()) + "×" +
                  std::to_string(dictionary_->gridSize()) + " atoms, the patches are " + std::to_string(p.grid_size) +
                  "×" + std::to_string(p.grid_size));
  }
}

std::vector<PatchSet> PatchCorrection::observedPatchesAtScales(const std::vector<double>& patch_scales,
                                                               PatchCorrectionReport* report) const
{
  PatchCorrectionReport local_report;
  PatchCorrectionReport& r = report ? *report : local_report;
  checkInput();
  const PatchCorrectionParameters& p = parameters_;
  const TriangleMesh& estimate = *estimate_;
  r.mean_edge_length = estimate.meanEdgeLength();

  // 1. Layout on the estimate.
  auto t = Clock::now();
  const double quad_length = quadLength(estimate, p);
  r.quad_length = quad_length;
  PatchLayout computed;
  if (layout_) {
    if (std::abs(layout_->quad_length - quad_length) > 1e-12 * quad_length)
      throw Error("patch correction: the layout given was made at L = " + std::to_string(layout_->quad_length) +
                  ", the correction's L is " + std::to_string(quad_length));
  } else {
    computePatchLayout(estimate, layoutParameters(p, quad_length), computed);
  }
  const PatchLayout& layout = layout_ ? *layout_ : computed;
  r.patches = layout.seeds.size();
  r.seconds_layout = secondsSince(t);

  // 2. Height maps of the observed surface.
  t = Clock::now();
  std::shared_ptr<const TriangleMesh> surface;
  if (observed_surface_) {
    surface = observed_surface_;
  } else if (observed_faces_.empty()) {
    surface = estimate_;
  } else {
    auto observed = std::make_shared<TriangleMesh>();
    observed->vertices = estimate.vertices;
    for (std::size_t f = 0; f < estimate.numFaces(); ++f)
      if (observed_faces_[f])
        observed->faces.push_back(estimate.faces[f]);
    if (observed->faces.empty())
      throw Error("no face is observed: there is no surface to fit patches to");
    surface = observed;
  }
  if (observed_surface_ && observed_surface_->vertices.empty())
    throw Error("the observed surface is empty: there is no surface to fit patches to");
  const int grid = dictionary_ ? dictionary_->gridSize() : (p.grid_size > 0 ? p.grid_size : 16);
  r.grid_size = grid;
  HeightMapParameters heights;
  heights.grid_size = grid;
  heights.num_threads = p.num_threads;
  heights.bin_reach = p.bin_reach;
  std::vector<PatchSet> sets;
  for (double scale : patch_scales) {
    if (!(scale > 0.0) || !std::isfinite(scale))
      throw Error("the patch scale must be > 0");
    heights.radius = scale * quad_length / std::sqrt(2.0);
    sets.emplace_back();
    if (surface->faces.empty())  // a point cloud: binned heights
      extractCloudHeightMaps(surface->vertices, layout.seeds, layout.frames, heights, sets.back());
    else
      extractMeshHeightMaps(*surface, layout.seeds, layout.frames, heights, sets.back());
  }
  if (!sets.empty()) {
    r.patch_side = patch_scales.front() * quad_length;
    r.observed_fraction = sets.front().observedFraction();
  }
  r.seconds_patches = secondsSince(t);
  return sets;
}

PatchSet PatchCorrection::observedPatches(PatchCorrectionReport* report) const
{
  return std::move(observedPatchesAtScales({parameters_.patch_scale}, report).front());
}

namespace {

/** The patches observed enough to code (fraction ≥ min_observed_fraction and > 0), with their
  * heights and masks gathered; `fraction` per patch of the set. */
struct UsablePatches {
  std::vector<std::int32_t> index;  ///< into the patch set
  std::vector<double> fraction;     ///< observed fraction of every patch of the set
  Eigen::MatrixXd heights;
  ObservationMask mask;
};

UsablePatches usablePatches(const PatchSet& patches, double min_observed_fraction)
{
  UsablePatches out;
  const Eigen::Index bins = static_cast<Eigen::Index>(patches.grid_size) * patches.grid_size;
  out.fraction.assign(patches.numPatches(), 0.0);
  for (std::size_t k = 0; k < patches.numPatches(); ++k) {
    out.fraction[k] = static_cast<double>(patches.observed.col(static_cast<Eigen::Index>(k)).count()) /
                      static_cast<double>(bins);
    if (out.fraction[k] >= min_observed_fraction && out.fraction[k] > 0.0)
      out.index.push_back(static_cast<std::int32_t>(k));
  }
  out.heights.resize(bins, static_cast<Eigen::Index>(out.index.size()));
  out.mask.resize(bins, static_cast<Eigen::Index>(out.index.size()));
  for (std::size_t u = 0; u < out.index.size(); ++u) {
    out.heights.col(static_cast<Eigen::Index>(u)) = patches.heights.col(out.index[u]);
    out.mask.col(static_cast<Eigen::Index>(u)) = patches.observed.col(out.index[u]);
  }
  return out;
}

/** Sparse codes: masked OMP over the observed bins, stopping at `sparsity` atoms or, with an error
  * target, once the residual over each patch's observed bins is within ε rms (fully observed
  * patches are coded by Batch-OMP, the others by masked OMP). Returns the decoded patches; the
  * mean non-zeros per code and each patch's rms misfit over its observed bins alongside. */
Eigen::MatrixXd codeUsable(const PatchDictionary& dictionary, const UsablePatches& usable,
                           const PatchCorrectionParameters& p, int atoms, double& mean_atoms,
                           std::vector<double>& fit_rms)
{
  const Eigen::Index bins = usable.heights.rows();
  const std::size_t count = usable.index.size();
  SparseCodingParameters coding;
  coding.max_atoms = std::min<int>(p.sparsity, atoms);
  coding.max_squared_error_per_entry = p.error_per_bin * p.error_per_bin;  // rms ≤ ε over each patch's observed bins
  std::vector<Eigen::Index> full, partial;
  for (std::size_t u = 0; u < count; ++u)
    (usable.mask.col(static_cast<Eigen::Index>(u)).all() ? full : partial).push_back(static_cast<Eigen::Index>(u));
  Eigen::MatrixXd filled(bins, static_cast<Eigen::Index>(count));
  double nonzeros = 0.0;
  const auto code_columns = [&](const std::vector<Eigen::Index>& columns, bool masked) {
    if (columns.empty())
      return;
    Eigen::MatrixXd heights(bins, static_cast<Eigen::Index>(columns.size()));
    ObservationMask mask(bins, static_cast<Eigen::Index>(columns.size()));
    for (std::size_t i = 0; i < columns.size(); ++i) {
      heights.col(static_cast<Eigen::Index>(i)) = usable.heights.col(columns[i]);
      mask.col(static_cast<Eigen::Index>(i)) = usable.mask.col(columns[i]);
    }
    const PatchCodes codes = masked ? dictionary.encodeMasked(heights, mask, coding) : dictionary.encode(heights, coding);
    const Eigen::MatrixXd decoded = dictionary.decode(codes);
    for (std::size_t i = 0; i < columns.size(); ++i)
      filled.col(columns[i]) = decoded.col(static_cast<Eigen::Index>(i));
    nonzeros += static_cast<double>(codes.coefficients.nonZeros());
  };
  code_columns(full, false);
  code_columns(partial, true);
  mean_atoms = nonzeros / static_cast<double>(count);
  fit_rms.assign(count, 0.0);
  for (std::size_t u = 0; u < count; ++u) {
    const Eigen::Index c = static_cast<Eigen::Index>(u);
    double sum = 0.0;
    Eigen::Index observed = 0;
    for (Eigen::Index b = 0; b < bins; ++b)
      if (usable.mask(b, c)) {
        const double d = filled(b, c) - usable.heights(b, c);
        sum += d * d;
        ++observed;
      }
    fit_rms[u] = observed ? std::sqrt(sum / static_cast<double>(observed)) : 0.0;
  }
  return filled;
}

/** What every target's constraints are made from: the coded usable patches and the per-patch
  * parts of the confidence. */
struct ConstraintSource {
  ConstraintSource(const PatchSet& patches_, const std::vector<std::int32_t>& usable_, const Eigen::MatrixXd& filled_,
                   const PatchCorrectionParameters& p_)
      : patches(patches_), usable(usable_), filled(filled_), p(p_)
  {
  }
  const PatchSet& patches;
  const std::vector<std::int32_t>& usable;
  const Eigen::MatrixXd& filled;  ///< coded heights, one column per usable patch
  const PatchCorrectionParameters& p;
  int grid = 0;
  double side = 0.0, radius = 0.0, sigma = 0.0;
  std::vector<double> observed_weight, fit_divisor;  ///< per usable patch
};

/** The constraint of usable patch u on vertex v at x0 (normal n0), when its square holds x0. */
bool patchConstraint(const ConstraintSource& s, std::size_t u, std::int32_t v, const Eigen::Vector3d& x0,
                     const Eigen::Vector3d& n0, PointToPlaneConstraint& c)
{
  const PatchCorrectionParameters& p = s.p;
  const std::size_t k = static_cast<std::size_t>(s.usable[u]);
  const Eigen::Matrix3d& rotation = s.patches.rotations[k];
  Eigen::Vector3d local;
  if (!patchContains(s.patches.seeds[k], rotation, s.radius, x0, n0, &local))
    return false;
  const auto column = s.filled.col(static_cast<Eigen::Index>(u));
  const double h = bilinearHeight(column, s.grid, s.side, local.x(), local.y());
  c.vertex = v;
  c.point = s.patches.seeds[k] + rotation.transpose() * Eigen::Vector3d(local.x(), local.y(), h);
  Eigen::Vector3d normal_local = Eigen::Vector3d::UnitZ();
  if (p.surface_normals) {
    // Central differences over one bin: the tangent plane of the patch surface at p.
    const double step = s.side / s.grid;
    const double hx = (bilinearHeight(column, s.grid, s.side, local.x() + step, local.y()) -
                       bilinearHeight(column, s.grid, s.side, local.x() - step, local.y())) / (2.0 * step);
    const double hy = (bilinearHeight(column, s.grid, s.side, local.x(), local.y() + step) -
                       bilinearHeight(column, s.grid, s.side, local.x(), local.y() - step)) / (2.0 * step);
    normal_local = Eigen::Vector3d(-hx, -hy, 1.0).normalized();
  }
  c.normal = rotation.transpose() * normal_local;
  double w = 1.0;
  if (s.sigma > 0.0)
    w *= std::exp(-0.5 * (local.x() * local.x() + local.y() * local.y()) / (s.sigma * s.sigma));
  if (p.observed_power > 0.0)
    w *= s.observed_weight[u];
  if (p.fit_scale > 0.0)
    w /= s.fit_divisor[u];
  c.weight = w;
  return true;
}

/** Agreement with the weighted median of the patches' offsets (robust to a stray patch): each
  * weight × exp(−½ ((d − median) / tau)²). */
void weighByAgreement(std::vector<PointToPlaneConstraint>& list, const std::vector<double>& offsets, double tau)
{
  std::vector<std::size_t> order(list.size());
  for (std::size_t i = 0; i < order.size(); ++i)
    order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return offsets[a] < offsets[b]; });
  double sum_w = 0.0;
  for (const auto& c : list)
    sum_w += c.weight;
  double running = 0.0, median = offsets[order.back()];
  for (std::size_t i : order) {
    running += list[i].weight;
    if (running >= 0.5 * sum_w) {
      median = offsets[i];
      break;
    }
  }
  for (std::size_t i = 0; i < list.size(); ++i) {
    const double d = (offsets[i] - median) / tau;
    list[i].weight *= std::exp(-0.5 * d * d);
  }
}

}  // namespace

void PatchCorrection::compute(std::vector<std::vector<PointToPlaneConstraint>>& constraints,
                              PatchCorrectionReport* report) const
{
  PatchCorrectionReport local_report;
  PatchCorrectionReport& r = report ? *report : local_report;
  r = PatchCorrectionReport();
  checkInput();
  const PatchCorrectionParameters& p = parameters_;
  const TriangleMesh& estimate = *estimate_;
  constraints.assign(targets_.size(), {});
  r.mean_edge_length = estimate.meanEdgeLength();
  if (targets_.empty())
    return;
  const PatchSet patches = observedPatches(&r);
  const UsablePatches usable = usablePatches(patches, p.min_observed_fraction);
  r.patches_used = usable.index.size();
  if (usable.index.empty())
    return;  // nothing observed near enough: no constraint

  // Dictionary: given, or self-similar from the observed patches (masked K-SVD).
  auto t = Clock::now();
  PatchDictionary::ConstPtr dictionary = dictionary_;
  if (!dictionary) {
    dictionary = learnSelfSimilar(usable.heights, usable.mask, p);
    r.self_similar = true;
  }
  r.atoms = static_cast<int>(dictionary->atoms().cols());
  r.seconds_dictionary = secondsSince(t);
  t = Clock::now();
  std::vector<double> fit_rms;
  const Eigen::MatrixXd filled = codeUsable(*dictionary, usable, p, r.atoms, r.mean_atoms, fit_rms);
  r.seconds_coding = secondsSince(t);

  // 3. Constraints on each target from the patches whose square holds it.
  t = Clock::now();
  std::vector<Eigen::Vector3d> usable_seeds(usable.index.size());
  for (std::size_t u = 0; u < usable.index.size(); ++u)
    usable_seeds[u] = patches.seeds[static_cast<std::size_t>(usable.index[u])];
  // The reconstruction's search: FLANN in float with a widened radius, then the exact test.
  const detail::PointSearch seed_tree(usable_seeds);
  const float search_radius = detail::floatSearchRadius(patches.radius);
  const double edge = std::max(r.mean_edge_length, 1e-12);
  ConstraintSource source(patches, usable.index, filled, p);
  source.grid = patches.grid_size;
  source.side = patches.side();
  source.radius = patches.radius;
  source.sigma = p.centre_sigma * 0.5 * source.side;
  // The per-patch parts of the confidence (observed fraction, fit), once per patch, not per target.
  source.observed_weight.assign(usable.index.size(), 1.0);
  source.fit_divisor.assign(usable.index.size(), 1.0);
  for (std::size_t u = 0; u < usable.index.size(); ++u) {
    if (p.observed_power > 0.0)
      source.observed_weight[u] = std::pow(usable.fraction[static_cast<std::size_t>(usable.index[u])], p.observed_power);
    if (p.fit_scale > 0.0) {
      const double q = fit_rms[u] / (p.fit_scale * edge);
      source.fit_divisor[u] = 1.0 + q * q;
    }
  }
  // A target facing away from a patch's Z is on another sheet (a thin wall's far side): the
  // patch sampled the sheet facing it (the same membership test as the reconstruction's).
  const std::vector<Eigen::Vector3d> normals =
      estimate.faces.empty() ? (estimate.hasNormals() ? estimate.normals
                                                      : std::vector<Eigen::Vector3d>(estimate.numVertices(),
                                                                                      Eigen::Vector3d::Zero()))
                             : computeVertexNormals(estimate);
#pragma omp parallel for schedule(dynamic, 64) num_threads(threadCount(p.num_threads))
  for (std::ptrdiff_t ti = 0; ti < static_cast<std::ptrdiff_t>(targets_.size()); ++ti) {
    const std::int32_t v = targets_[static_cast<std::size_t>(ti)];
    const Eigen::Vector3d x0 = estimate.vertices[static_cast<std::size_t>(v)];
    std::vector<int> near;
    std::vector<float> squared_distances;
    seed_tree.within(x0, search_radius, near, squared_distances);
    std::sort(near.begin(), near.end());  // FLANN's order is not specified
    std::vector<PointToPlaneConstraint>& list = constraints[static_cast<std::size_t>(ti)];
    std::vector<double> offsets;  // d = n·(x0 − p): the correction each patch asks for
    for (const int u : near) {
      PointToPlaneConstraint c;
      if (!patchConstraint(source, static_cast<std::size_t>(u), v, x0, normals[static_cast<std::size_t>(v)], c))
        continue;
      offsets.push_back(c.normal.dot(x0 - c.point));
      list.push_back(c);
    }
    if (p.agreement_scale > 0.0 && list.size() > 1)
      weighByAgreement(list, offsets, p.agreement_scale * edge);
  }
  for (const auto& list : constraints) {
    if (!list.empty())
      ++r.constrained_vertices;
    r.constraints += list.size();
  }
  r.seconds_constraints = secondsSince(t);
}

}  // namespace patchdict
}  // namespace pcl
