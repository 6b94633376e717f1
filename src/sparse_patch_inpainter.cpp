// SparsePatchInpainter, missing-vertex mode (see sparse_patch_inpainter.h).
// Patches and dictionaries: Sarkar, Varanasi & Stricker, "Learning quadrangulated patches for 3D
// shape parameterization and completion", 3DV 2017, sections 3–5. The base solve is least-squares
// meshes (Sorkine & Cohen-Or, SMI 2004); masked OMP and K-SVD as in sparse_coding.h.
#include <pcl_patchdict/sparse_patch_inpainter.h>

#include <pcl_patchdict/error.h>
#include <pcl_patchdict/height_map_patch_extractor.h>
#include <pcl_patchdict/mesh_topology.h>
#include <pcl_patchdict/normalization.h>

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <unordered_map>

namespace pcl {
namespace patchdict {

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/** Seeds bucketed in a uniform grid of cell `cell` for ball queries. */
class SeedGrid {
public:
  SeedGrid(const std::vector<Eigen::Vector3d>& points, double cell) : points_(points), cell_(cell)
  {
    for (std::size_t i = 0; i < points.size(); ++i)
      cells_[key(cellOf(points[i]))].push_back(static_cast<std::int32_t>(i));
  }
  /** Indices of the points within `radius` (≤ cell) of q, increasing. */
  void query(const Eigen::Vector3d& q, double radius, std::vector<std::int32_t>& out) const
  {
    out.clear();
    const Eigen::Vector3i c = cellOf(q);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = cells_.find(key(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == cells_.end())
            continue;
          for (std::int32_t i : it->second)
            if ((points_[static_cast<std::size_t>(i)] - q).squaredNorm() <= radius * radius)
              out.push_back(i);
        }
    std::sort(out.begin(), out.end());
  }

private:
  Eigen::Vector3i cellOf(const Eigen::Vector3d& p) const
  {
    return Eigen::Vector3i(static_cast<int>(std::floor(p.x() / cell_)), static_cast<int>(std::floor(p.y() / cell_)),
                           static_cast<int>(std::floor(p.z() / cell_)));
  }
  static std::int64_t key(const Eigen::Vector3i& c)
  {
    return ((static_cast<std::int64_t>(c.x()) & 0x1FFFFF) << 42) | ((static_cast<std::int64_t>(c.y()) & 0x1FFFFF) << 21) |
           (static_cast<std::int64_t>(c.z()) & 0x1FFFFF);
  }
  const std::vector<Eigen::Vector3d>& points_;
  double cell_;
  std::unordered_map<std::int64_t, std::vector<std::int32_t>> cells_;
};

/** Bilinear height of an N×N patch column at frame coordinates (u, v); bin centres as in
  * HeightMapPatchExtractor, clamped at the border bins. */
double bilinearHeight(const Eigen::Ref<const Eigen::VectorXd>& heights, int n, double side, double u, double v)
{
  const double gx = std::clamp((u + 0.5 * side) / side * n - 0.5, 0.0, static_cast<double>(n - 1));
  const double gy = std::clamp((v + 0.5 * side) / side * n - 0.5, 0.0, static_cast<double>(n - 1));
  const int i0 = std::min(static_cast<int>(gx), n - 2 < 0 ? 0 : n - 2);
  const int j0 = std::min(static_cast<int>(gy), n - 2 < 0 ? 0 : n - 2);
  const double fx = gx - i0, fy = gy - j0;
  const auto h = [&](int i, int j) { return heights(static_cast<Eigen::Index>(j) * n + i); };
  return (1 - fy) * ((1 - fx) * h(i0, j0) + fx * h(i0 + 1, j0)) + fy * ((1 - fx) * h(i0, j0 + 1) + fx * h(i0 + 1, j0 + 1));
}

/** Weighted OMP of one signal: min ‖W^½ (x − D a)‖² with at most `sparsity` atoms, greedy
  * selection by normalised correlation of the weighted atoms (Pati, Rezaiifar & Krishnaprasad
  * 1993, with weights as in masked OMP). Returns D a over every bin. */
Eigen::VectorXd weightedOMP(const Eigen::MatrixXd& atoms, const Eigen::VectorXd& signal, const Eigen::VectorXd& weights,
                            int sparsity)
{
  const Eigen::VectorXd root = weights.cwiseSqrt();
  const Eigen::MatrixXd weighted = root.asDiagonal() * atoms;
  const Eigen::VectorXd norms = weighted.colwise().norm().transpose();
  const Eigen::VectorXd target = root.cwiseProduct(signal);
  Eigen::VectorXd residual = target;
  std::vector<Eigen::Index> chosen;
  Eigen::VectorXd coefficients;
  const double tiny = 1e-12 * std::max(1.0, norms.maxCoeff());
  for (int t = 0; t < sparsity && t < atoms.cols(); ++t) {
    const Eigen::VectorXd correlation = weighted.transpose() * residual;
    Eigen::Index best = -1;
    double best_value = 0.0;
    for (Eigen::Index k = 0; k < atoms.cols(); ++k) {
      if (norms(k) <= tiny || std::find(chosen.begin(), chosen.end(), k) != chosen.end())
        continue;
      const double value = std::abs(correlation(k)) / norms(k);
      if (value > best_value) {
        best_value = value;
        best = k;
      }
    }
    if (best < 0 || best_value <= 1e-15 * std::max(1.0, target.norm()))
      break;
    chosen.push_back(best);
    Eigen::MatrixXd selected(weighted.rows(), static_cast<Eigen::Index>(chosen.size()));
    for (std::size_t i = 0; i < chosen.size(); ++i)
      selected.col(static_cast<Eigen::Index>(i)) = weighted.col(chosen[i]);
    coefficients = selected.colPivHouseholderQr().solve(target);
    residual = target - selected * coefficients;
  }
  Eigen::VectorXd out = Eigen::VectorXd::Zero(atoms.rows());
  for (std::size_t i = 0; i < chosen.size(); ++i)
    out += coefficients(static_cast<Eigen::Index>(i)) * atoms.col(chosen[i]);
  return out;
}

PatchLayoutParameters layoutParameters(const SparsePatchInpainter::Parameters& p, double quad_length)
{
  PatchLayoutParameters layout;
  layout.quad_length = quad_length;
  layout.overlap = p.overlap;
  layout.seed = p.seed;
  layout.num_threads = p.num_threads;
  return layout;
}

void checkParameters(const SparsePatchInpainter::Parameters& p)
{
  if (!(p.quad_length >= 0.0) || !std::isfinite(p.quad_length))
    throw Error("the quad length must be ≥ 0 (0: automatic)");
  if (!(p.quad_length_factor > 0.0) || !std::isfinite(p.quad_length_factor))
    throw Error("the quad length factor must be > 0");
  if (!(p.patch_scale > 0.0) || !std::isfinite(p.patch_scale))
    throw Error("the patch scale must be > 0");
  if (p.overlap < 0 || p.sparsity < 1)
    throw Error("overlap must be ≥ 0 and sparsity ≥ 1");
  if (!(p.constraint_weight >= 0.0) || !std::isfinite(p.constraint_weight))
    throw Error("the constraint weight μ must be ≥ 0");
  if ((p.grid_size != 0 && (p.grid_size < 2 || p.grid_size > 256)) || p.self_similar_atoms < 1 ||
      p.self_similar_iterations < 1)
    throw Error("bad self-similar dictionary parameters");
}

}  // namespace

double SparsePatchInpainter::automaticQuadLength(const TriangleMesh& normalised_mesh, const Parameters& parameters)
{
  return parameters.quad_length > 0.0 ? parameters.quad_length
                                      : parameters.quad_length_factor * normalised_mesh.meanEdgeLength();
}

PatchSet SparsePatchInpainter::trainingPatches(const TriangleMesh& clean_mesh, const Parameters& parameters,
                                               int grid_size)
{
  checkParameters(parameters);
  TriangleMesh mesh = clean_mesh;
  UnitCubeNormalization::fromMesh(mesh).apply(mesh);
  const double quad_length = automaticQuadLength(mesh, parameters);
  PatchLayout layout;
  computePatchLayout(mesh, layoutParameters(parameters, quad_length), layout);
  HeightMapPatchExtractor extractor;
  extractor.setSeeds(layout.seeds, layout.frames);
  extractor.setInputMesh(mesh);
  extractor.setRadius(parameters.patch_scale * quad_length / std::sqrt(2.0));
  extractor.setGridSize(grid_size);
  extractor.setNumberOfThreads(parameters.num_threads);
  PatchSet patches;
  extractor.compute(patches);
  return patches;
}

void SparsePatchInpainter::process(TriangleMesh& out, Report* report) const
{
  Report local_report;
  Report& r = report ? *report : local_report;
  r = Report();
  const Parameters& p = parameters_;
  checkParameters(p);
  if (!input_ || input_->empty())
    throw Error("no input mesh");
  const TriangleMesh& input = *input_;
  const std::size_t n = input.numVertices();
  if (input.faces.empty())
    throw Error("the input has no faces: missing vertices need the mesh's connectivity");
  for (const Face& f : input.faces)
    for (std::int32_t v : f)
      if (v < 0 || static_cast<std::size_t>(v) >= n)
        throw Error("a face refers to vertex " + std::to_string(v) + ", the mesh has " + std::to_string(n));
  if (missing_.empty())
    throw Error("no missing vertex given");
  std::vector<bool> is_missing(n, false);
  for (int v : missing_) {
    if (v < 0 || static_cast<std::size_t>(v) >= n)
      throw Error("missing vertex " + std::to_string(v) + " is out of range: the mesh has " + std::to_string(n) +
                  " vertices");
    if (is_missing[static_cast<std::size_t>(v)])
      throw Error("missing vertex " + std::to_string(v) + " is listed twice");
    is_missing[static_cast<std::size_t>(v)] = true;
  }
  if (missing_.size() == n)
    throw Error("every vertex is missing: nothing to interpolate from");
  if (use_patches_ && dictionary_) {
    if (dictionary_->empty())
      throw Error("the dictionary has no atoms");
    if (dictionary_->gridSize() < 2)
      throw Error("the dictionary's atoms are not N×N patches");
    if (p.grid_size != 0 && dictionary_->gridSize() != p.grid_size)
      throw Error("the dictionary has " + std::to_string(dictionary_->gridSize()) + "×" +
                  std::to_string(dictionary_->gridSize()) + " atoms, the patches are " + std::to_string(p.grid_size) +
                  "×" + std::to_string(p.grid_size));
  }
  r.missing_vertices = missing_.size();

  // Normalise by the known vertices only (the missing ones' input positions mean nothing).
  TriangleMesh known_cloud;
  for (std::size_t v = 0; v < n; ++v)
    if (!is_missing[v]) {
      if (!input.vertices[v].allFinite())
        throw Error("known vertex " + std::to_string(v) + " has a non-finite position");
      known_cloud.vertices.push_back(input.vertices[v]);
    }
  const UnitCubeNormalization normalization = UnitCubeNormalization::fromMesh(known_cloud);

  TriangleMesh work;
  work.faces = input.faces;
  work.vertices.resize(n);
  std::vector<bool> in_face(n, false);
  for (const Face& f : input.faces)
    for (std::int32_t v : f)
      in_face[static_cast<std::size_t>(v)] = true;
  std::vector<bool> is_free(n, false);
  for (std::size_t v = 0; v < n; ++v) {
    is_free[v] = is_missing[v] && in_face[v];
    if (is_missing[v] && !in_face[v])
      ++r.isolated_missing;
    work.vertices[v] = is_missing[v] ? Eigen::Vector3d::Zero() : normalization.apply(input.vertices[v]);
  }

  // 1. First guess: the least-squares bi-Laplacian.
  auto t = Clock::now();
  const PatchConstrainedSolver solver(work, is_free);
  solver.solve(work.vertices);
  const std::vector<Eigen::Vector3d> first_guess = work.vertices;
  r.seconds_first_guess = secondsSince(t);
  r.mean_edge_length = work.meanEdgeLength();

  if (use_patches_ && solver.numFree() > 0) {
    r.used_patches = true;
    // 2. Layout on the first guess.
    t = Clock::now();
    const double quad_length = automaticQuadLength(work, p);
    r.quad_length = quad_length;
    PatchLayout layout;
    computePatchLayout(work, layoutParameters(p, quad_length), layout);
    r.patches = layout.seeds.size();
    r.seconds_layout = secondsSince(t);

    // 3. Patches of the observed surface: faces whose three vertices are known.
    t = Clock::now();
    TriangleMesh observed;
    observed.vertices = work.vertices;
    for (const Face& f : work.faces)
      if (!is_missing[static_cast<std::size_t>(f[0])] && !is_missing[static_cast<std::size_t>(f[1])] &&
          !is_missing[static_cast<std::size_t>(f[2])])
        observed.faces.push_back(f);
    if (observed.faces.empty())
      throw Error("no face has its three vertices known: there is no observed surface to fit patches to");
    const int grid = dictionary_ ? dictionary_->gridSize() : (p.grid_size > 0 ? p.grid_size : 16);
    const double side = p.patch_scale * quad_length;
    const double radius = side / std::sqrt(2.0);
    r.patch_side = side;
    r.grid_size = grid;
    HeightMapPatchExtractor extractor;
    extractor.setSeeds(layout.seeds, layout.frames);
    extractor.setInputMesh(observed);
    extractor.setRadius(radius);
    extractor.setGridSize(grid);
    extractor.setNumberOfThreads(p.num_threads);
    PatchSet patches;
    extractor.compute(patches);
    r.observed_fraction = patches.observedFraction();
    const Eigen::Index bins = static_cast<Eigen::Index>(grid) * grid;
    std::vector<std::int32_t> usable;  // patches with enough observed bins
    std::vector<double> fraction(patches.numPatches(), 0.0);
    for (std::size_t k = 0; k < patches.numPatches(); ++k) {
      fraction[k] = static_cast<double>(patches.observed.col(static_cast<Eigen::Index>(k)).count()) /
                    static_cast<double>(bins);
      if (fraction[k] >= p.min_observed_fraction && fraction[k] > 0.0)
        usable.push_back(static_cast<std::int32_t>(k));
    }
    r.patches_used = usable.size();
    PatchSet guess_patches;  // the first guess over the hidden bins (λ > 0 only)
    if (p.first_guess_weight > 0.0) {
      HeightMapPatchExtractor guess_extractor = extractor;
      guess_extractor.setInputMesh(work);
      guess_extractor.compute(guess_patches);
    }
    Eigen::MatrixXd usable_heights(bins, static_cast<Eigen::Index>(usable.size()));
    ObservationMask usable_mask(bins, static_cast<Eigen::Index>(usable.size()));
    for (std::size_t u = 0; u < usable.size(); ++u) {
      usable_heights.col(static_cast<Eigen::Index>(u)) = patches.heights.col(usable[u]);
      usable_mask.col(static_cast<Eigen::Index>(u)) = patches.observed.col(usable[u]);
    }
    r.seconds_patches = secondsSince(t);

    // Dictionary: given, or self-similar from the observed patches (masked K-SVD).
    t = Clock::now();
    PatchDictionary::ConstPtr dictionary = dictionary_;
    if (!dictionary) {
      if (usable.empty())
        throw Error("no patch is observed enough to learn a self-similar dictionary from");
      auto learned = std::make_shared<PatchDictionary>();
      learned->setNumAtoms(std::min<int>(p.self_similar_atoms, static_cast<int>(usable.size())));
      learned->setSparsity(std::min(p.sparsity, learned->getNumAtoms()));
      learned->setIterations(p.self_similar_iterations);
      learned->setSeed(p.seed + 1);
      if (p.self_similar_max_patches > 0 && usable.size() > static_cast<std::size_t>(p.self_similar_max_patches)) {
        // An evenly spaced subset: K-SVD time grows with the patch count, the atoms hardly do.
        const Eigen::Index count = p.self_similar_max_patches;
        Eigen::MatrixXd subset(bins, count);
        ObservationMask subset_mask(bins, count);
        for (Eigen::Index i = 0; i < count; ++i) {
          const auto column = static_cast<Eigen::Index>(static_cast<double>(i) * static_cast<double>(usable.size()) /
                                                        static_cast<double>(count));
          subset.col(i) = usable_heights.col(column);
          subset_mask.col(i) = usable_mask.col(column);
        }
        learned->learn(subset, subset_mask);
      } else {
        learned->learn(usable_heights, usable_mask);
      }
      dictionary = learned;
      r.self_similar = true;
    }
    r.atoms = static_cast<int>(dictionary->atoms().cols());
    r.seconds_dictionary = secondsSince(t);

    // Masked OMP fills the unobserved bins; the fit residual is measured on the observed ones.
    t = Clock::now();
    Eigen::MatrixXd filled;
    std::vector<double> fit_rms(usable.size(), 0.0);
    if (!usable.empty()) {
      SparseCodingParameters coding;
      coding.max_atoms = std::min<int>(p.sparsity, r.atoms);
      if (p.first_guess_weight > 0.0) {
        // Observed bins weigh 1, the first guess over the hidden ones λ (bins neither covers: 0).
        filled.resize(bins, static_cast<Eigen::Index>(usable.size()));
        const Eigen::MatrixXd& atoms = dictionary->atoms();
        const bool remove_mean = dictionary->getRemoveMean();
#pragma omp parallel for schedule(dynamic, 16) num_threads(p.num_threads > 0 ? p.num_threads : omp_get_max_threads())
        for (std::ptrdiff_t u = 0; u < static_cast<std::ptrdiff_t>(usable.size()); ++u) {
          const Eigen::Index c = static_cast<Eigen::Index>(u);
          const Eigen::Index k = usable[static_cast<std::size_t>(u)];
          Eigen::VectorXd signal = usable_heights.col(c), weights = Eigen::VectorXd::Zero(bins);
          for (Eigen::Index b = 0; b < bins; ++b)
            if (usable_mask(b, c))
              weights(b) = 1.0;
            else if (guess_patches.observed(b, k)) {
              weights(b) = p.first_guess_weight;
              signal(b) = guess_patches.heights(b, k);
            }
          double mean = 0.0;
          if (remove_mean) {
            mean = weights.dot(signal) / std::max(weights.sum(), 1e-300);
            signal.array() -= mean;
          }
          filled.col(c) = weightedOMP(atoms, signal, weights, coding.max_atoms).array() + mean;
        }
      } else {
        const PatchCodes codes = dictionary->encodeMasked(usable_heights, usable_mask, coding);
        filled = dictionary->decode(codes);
      }
      for (std::size_t u = 0; u < usable.size(); ++u) {
        const Eigen::Index c = static_cast<Eigen::Index>(u);
        double sum = 0.0;
        Eigen::Index count = 0;
        for (Eigen::Index b = 0; b < bins; ++b)
          if (usable_mask(b, c)) {
            const double d = filled(b, c) - usable_heights(b, c);
            sum += d * d;
            ++count;
          }
        fit_rms[u] = count ? std::sqrt(sum / static_cast<double>(count)) : 0.0;
      }
    }
    r.seconds_coding = secondsSince(t);

    // 4. Constraints on each free vertex from the patches whose square holds it.
    t = Clock::now();
    std::vector<Eigen::Vector3d> usable_seeds(usable.size());
    for (std::size_t u = 0; u < usable.size(); ++u)
      usable_seeds[u] = patches.seeds[static_cast<std::size_t>(usable[u])];
    const SeedGrid seed_grid(usable_seeds, radius);
    const double edge = std::max(r.mean_edge_length, 1e-12);
    const double sigma = p.centre_sigma * 0.5 * side;
    const std::vector<std::int32_t>& free_vertices = solver.freeVertices();
    std::vector<std::vector<PointToPlaneConstraint>> per_vertex(free_vertices.size());
#pragma omp parallel for schedule(dynamic, 64) num_threads(p.num_threads > 0 ? p.num_threads : omp_get_max_threads())
    for (std::ptrdiff_t fi = 0; fi < static_cast<std::ptrdiff_t>(free_vertices.size()); ++fi) {
      const std::int32_t v = free_vertices[static_cast<std::size_t>(fi)];
      const Eigen::Vector3d x0 = first_guess[static_cast<std::size_t>(v)];
      std::vector<std::int32_t> near;
      seed_grid.query(x0, radius, near);
      std::vector<PointToPlaneConstraint>& list = per_vertex[static_cast<std::size_t>(fi)];
      std::vector<double> offsets;  // d = n·(x0 − p): the correction each patch asks for
      for (std::int32_t u : near) {
        const std::size_t k = static_cast<std::size_t>(usable[static_cast<std::size_t>(u)]);
        const Eigen::Matrix3d& rotation = patches.rotations[k];
        const Eigen::Vector3d local = rotation * (x0 - patches.seeds[k]);
        if (std::abs(local.x()) > 0.5 * side || std::abs(local.y()) > 0.5 * side || std::abs(local.z()) > radius)
          continue;
        const double h = bilinearHeight(filled.col(static_cast<Eigen::Index>(u)), grid, side, local.x(), local.y());
        PointToPlaneConstraint c;
        c.vertex = v;
        c.point = patches.seeds[k] + rotation.transpose() * Eigen::Vector3d(local.x(), local.y(), h);
        Eigen::Vector3d normal_local = Eigen::Vector3d::UnitZ();
        if (p.surface_normals) {
          // Central differences over one bin: the tangent plane of the patch surface at p.
          const double step = side / grid;
          const auto column = filled.col(static_cast<Eigen::Index>(u));
          const double hx = (bilinearHeight(column, grid, side, local.x() + step, local.y()) -
                             bilinearHeight(column, grid, side, local.x() - step, local.y())) / (2.0 * step);
          const double hy = (bilinearHeight(column, grid, side, local.x(), local.y() + step) -
                             bilinearHeight(column, grid, side, local.x(), local.y() - step)) / (2.0 * step);
          normal_local = Eigen::Vector3d(-hx, -hy, 1.0).normalized();
        }
        c.normal = rotation.transpose() * normal_local;
        double w = 1.0;
        if (sigma > 0.0)
          w *= std::exp(-0.5 * (local.x() * local.x() + local.y() * local.y()) / (sigma * sigma));
        if (p.observed_power > 0.0)
          w *= std::pow(fraction[k], p.observed_power);
        if (p.fit_scale > 0.0) {
          const double q = fit_rms[static_cast<std::size_t>(u)] / (p.fit_scale * edge);
          w /= 1.0 + q * q;
        }
        c.weight = w;
        offsets.push_back(c.normal.dot(x0 - c.point));
        list.push_back(c);
      }
      if (p.agreement_scale > 0.0 && list.size() > 1) {
        double sum_w = 0.0, mean = 0.0;
        for (std::size_t i = 0; i < list.size(); ++i) {
          sum_w += list[i].weight;
          mean += list[i].weight * offsets[i];
        }
        mean = sum_w > 0.0 ? mean / sum_w : 0.0;
        const double tau = p.agreement_scale * edge;
        for (std::size_t i = 0; i < list.size(); ++i) {
          const double d = (offsets[i] - mean) / tau;
          list[i].weight *= std::exp(-0.5 * d * d);
        }
      }
    }
    std::vector<PointToPlaneConstraint> constraints;
    for (const auto& list : per_vertex) {
      if (!list.empty())
        ++r.constrained_vertices;
      constraints.insert(constraints.end(), list.begin(), list.end());
    }
    r.constraints = constraints.size();

    // 5. One joint solve, the bi-Laplacian energy plus the weighted constraints.
    solver.solve(work.vertices, constraints, p.constraint_weight);
    double correction = 0.0;
    for (std::int32_t v : free_vertices)
      correction += (work.vertices[static_cast<std::size_t>(v)] - first_guess[static_cast<std::size_t>(v)]).norm();
    r.mean_correction = free_vertices.empty() ? 0.0 : correction / static_cast<double>(free_vertices.size());
    r.seconds_solve = secondsSince(t);
  }

  // Output: the input with the free vertices replaced; everything else copied bit for bit.
  out = input;
  for (std::size_t v = 0; v < n; ++v)
    if (is_free[v])
      out.vertices[v] = normalization.invert(work.vertices[v]);
  if (out.hasNormals())
    out.normals.clear();  // the repaired vertices' normals would be stale
}

}  // namespace patchdict
}  // namespace pcl
