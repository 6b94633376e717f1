// Hole filling in a depth image (see organized_hole_filling.h). A plane seen through a pinhole is
// affine in 1/z over the pixel grid, and disparity noise is even in 1/z, so the rim is fitted there.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/cloud/organized_hole_filling.h>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pcl {
namespace patchdict {

namespace {

struct RingPixel {
  std::size_t index;
  int step;  // 1 = touches the region (8-neighbourhood)
};

// A smooth surface q(u, v) ≈ 1/z over the ring: a quadric (or a plane for small rings), by
// iteratively reweighted least squares (Huber at 2.5 σ), weighted by 1/σ_q² where σ_q = σ(z)/z².
struct RimFit {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double radius = 1.0;
  bool quadric = false;
  Eigen::VectorXd c;
  double cost = 0.0;    // Σ w (r/σ)² at the end, w the robust weights
  double support = 0.0; // Σ w

  Eigen::VectorXd basis(double column, double row) const
  {
    const double u = (column - centre.x()) / radius, v = (row - centre.y()) / radius;
    Eigen::VectorXd b(quadric ? 6 : 3);
    b(0) = 1.0;
    b(1) = u;
    b(2) = v;
    if (quadric) {
      b(3) = u * u;
      b(4) = u * v;
      b(5) = v * v;
    }
    return b;
  }
  double operator()(double column, double row) const { return basis(column, row).dot(c); }
};

bool fitRim(const DepthImage& image, const DepthNoiseModel& noise, const std::vector<RingPixel>& ring, RimFit& fit)
{
  const std::size_t n = ring.size();
  const int m = fit.quadric ? 6 : 3;
  if (n < static_cast<std::size_t>(2 * m))
    return false;
  Eigen::MatrixXd A(n, m);
  Eigen::VectorXd q(n), prior(n), w = Eigen::VectorXd::Ones(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = ring[k].index;
    A.row(k) = fit.basis(static_cast<double>(i % image.width), static_cast<double>(i / image.width)).transpose();
    const double z = image.depth[i];
    q(k) = 1.0 / z;
    const double sigma_q = noise.coefficient > 0.0 ? noise.sigma(z) / (z * z) : 0.0;
    prior(k) = sigma_q > 0.0 ? 1.0 / (sigma_q * sigma_q) : 1.0;
  }
  Eigen::VectorXd scale(n);  // σ_q per pixel (or a robust common scale without a noise model)
  for (int iteration = 0; iteration < 5; ++iteration) {
    const Eigen::VectorXd weights = prior.cwiseProduct(w);
    const Eigen::MatrixXd Aw = A.array().colwise() * weights.array().sqrt();
    const Eigen::VectorXd qw = q.cwiseProduct(weights.cwiseSqrt());
    fit.c = Aw.colPivHouseholderQr().solve(qw);
    if (!fit.c.allFinite())
      return false;
    const Eigen::VectorXd r = q - A * fit.c;
    if (noise.coefficient > 0.0) {
      scale = prior.cwiseSqrt().cwiseInverse();
    } else {
      std::vector<double> a(n);
      for (std::size_t k = 0; k < n; ++k)
        a[k] = std::abs(r(k));
      std::nth_element(a.begin(), a.begin() + static_cast<std::ptrdiff_t>(n / 2), a.end());
      scale.setConstant(std::max(1.4826 * a[n / 2], 1e-12 * q.cwiseAbs().maxCoeff()));
    }
    for (std::size_t k = 0; k < n; ++k) {  // Huber, then Tukey's biweight (another surface in the ring goes)
      const double t = std::abs(r(k)) / scale(k);
      w(k) = iteration < 2 ? (t <= 2.5 ? 1.0 : 2.5 / t) : (t < 4.685 ? std::pow(1.0 - (t / 4.685) * (t / 4.685), 2) : 0.0);
    }
    if (w.sum() < 2.0 * m)
      return false;
  }
  const Eigen::VectorXd r = q - A * fit.c;
  fit.cost = (w.array() * (r.array() / scale.array()).square()).sum();
  fit.support = w.sum();
  return true;
}

// Harmonic interpolation of the rim's misfit into the region: Δe = 0 on the region's pixels, e the
// misfit at the measured 4-neighbours. Returns one value per region pixel (in region order). `label`
// holds region ids on unmeasured pixels (and ring marks on measured ones).
Eigen::VectorXd harmonicMisfit(const DepthImage& image, const RimFit& fit, const std::vector<std::size_t>& region,
                               const std::vector<int>& label, int id)
{
  const std::size_t W = image.width, n = region.size();
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::VectorXd b = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n));
  // region indices are sorted: position by binary search
  const auto position = [&](std::size_t i) {
    return static_cast<Eigen::Index>(std::lower_bound(region.begin(), region.end(), i) - region.begin());
  };
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = region[k];
    const std::size_t neighbours[4] = {i - 1, i + 1, i - W, i + W};  // enclosed: never on the border
    double diagonal = 0.0;
    for (const std::size_t j : neighbours) {
      if (!image.valid[j] && label[j] == id) {
        entries.emplace_back(static_cast<Eigen::Index>(k), position(j), -1.0);
        diagonal += 1.0;
      } else if (image.valid[j]) {
        b(static_cast<Eigen::Index>(k)) += 1.0 / image.depth[j] - fit(static_cast<double>(j % W), static_cast<double>(j / W));
        diagonal += 1.0;
      }
    }
    entries.emplace_back(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k), std::max(diagonal, 1.0));
  }
  Eigen::SparseMatrix<double> L(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  L.setFromTriplets(entries.begin(), entries.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(L);
  if (solver.info() != Eigen::Success)
    return Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n));
  Eigen::VectorXd e = solver.solve(b);
  if (!e.allFinite())
    e.setZero();
  return e;
}


enum class Verdict { Filled, TooLarge, NotOneSurface };

// Whether the rim (ring step 1) lies on the fitted surface: at most rim_outlier_share of its pixels
// beyond τ(z), none beyond 4 τ(z).
bool rimFits(const DepthImage& image, const DepthNoiseModel& noise, const OrganizedFillParameters& parameters,
             const std::vector<RingPixel>& ring, const RimFit& fit)
{
  const std::size_t W = image.width;
  std::size_t beyond = 0, rim = 0;
  for (const RingPixel& p : ring) {
    if (p.step != 1)
      continue;
    const double z = image.depth[p.index];
    const double q = fit(static_cast<double>(p.index % W), static_cast<double>(p.index / W));
    const double misfit = q > 0.0 ? std::abs(1.0 / q - z) : std::numeric_limits<double>::infinity();
    const double tau = std::max(parameters.rim_noise_factor * noise.sigma(z), parameters.rim_relative_depth * z);
    if (!(misfit <= 4.0 * tau))
      return false;
    beyond += misfit > tau ? 1 : 0;
    ++rim;
  }
  return static_cast<double>(beyond) <= parameters.rim_outlier_share * static_cast<double>(rim);
}

// The ring's surface: the plane, or the quadric when its three more terms pay for themselves (the
// weighted misfit drops by more than curvature_evidence × BIC's 3 ln n; on a flat surface a fitted
// curvature is noise) — the first of the two, in that order of preference, that the rim lies on.
bool rimOnOneSurface(const DepthImage& image, const DepthNoiseModel& noise, const OrganizedFillParameters& parameters,
                     const std::vector<RingPixel>& ring, RimFit& fit, bool quadric)
{
  RimFit plane = fit, curved = fit;
  plane.quadric = false;
  curved.quadric = true;
  const bool plane_ok = fitRim(image, noise, ring, plane);
  const bool curved_ok = quadric && fitRim(image, noise, ring, curved);
  const bool prefer_curved = curved_ok && (!plane_ok || plane.cost - curved.cost > parameters.curvature_evidence * 3.0 * std::log(std::max(curved.support, 2.0)));
  for (const RimFit* candidate : {prefer_curved ? &curved : &plane, prefer_curved ? &plane : &curved}) {
    if (!(candidate == &plane ? plane_ok : curved_ok) || !rimFits(image, noise, parameters, ring, *candidate))
      continue;
    fit = *candidate;
    return true;
  }
  return false;
}

// One enclosed region (sorted pixel indices): its ring, the one-surface test, the fill on the rays.
Verdict fillRegion(const DepthImage& image, const DepthNoiseModel& noise, const OrganizedFillParameters& parameters,
                   const std::vector<std::size_t>& region, const std::vector<int>& label, int id,
                   std::vector<int>& ring_mark, std::vector<std::pair<std::size_t, Eigen::Vector3d>>& hole)
{
  const std::size_t W = image.width, H = image.height;
  std::vector<std::size_t> frontier;
  // The ring: measured pixels within `steps` 8-neighbour steps of the region.
  RimFit fit;
  for (const std::size_t i : region)
    fit.centre += Eigen::Vector2d(static_cast<double>(i % W), static_cast<double>(i / W));
  fit.centre /= static_cast<double>(region.size());
  const double radius = std::sqrt(static_cast<double>(region.size()) / M_PI);
  fit.radius = std::max(1.0, radius);
  const int steps = parameters.fit_ring > 0 ? parameters.fit_ring : std::clamp(static_cast<int>(std::lround(radius)), 2, 6);
  std::vector<RingPixel> ring;
  frontier = region;
  for (int step = 1; step <= steps; ++step) {
    std::vector<std::size_t> next;
    for (const std::size_t i : frontier) {
      const std::size_t column = i % W, row = i / W;
      for (std::size_t r = row ? row - 1 : 0; r <= std::min(H - 1, row + 1); ++r)
        for (std::size_t c = column ? column - 1 : 0; c <= std::min(W - 1, column + 1); ++c) {
          const std::size_t j = r * W + c;
          if (image.valid[j] && ring_mark[j] != id) {
            ring_mark[j] = id;
            ring.push_back({j, step});
            next.push_back(j);
          }
        }
    }
    frontier.swap(next);
  }
  // Rim geometry: its width in space bounds the hole.
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  std::size_t rim_count = 0;
  for (const RingPixel& p : ring)
    if (p.step == 1) {
      centroid += image.camera.pointAt(static_cast<double>(p.index % W), static_cast<double>(p.index / W), image.depth[p.index]);
      ++rim_count;
    }
  centroid /= static_cast<double>(std::max<std::size_t>(1, rim_count));
  double reach = 0.0, z_low = std::numeric_limits<double>::infinity(), z_high = 0.0;
  for (const RingPixel& p : ring)
    if (p.step == 1) {
      const double z = image.depth[p.index];
      reach = std::max(reach, (image.camera.pointAt(static_cast<double>(p.index % W), static_cast<double>(p.index / W), z) - centroid).norm());
      z_low = std::min(z_low, z);
      z_high = std::max(z_high, z);
    }
  if (parameters.max_hole_diameter > 0.0 && 2.0 * reach > parameters.max_hole_diameter)
    return Verdict::TooLarge;
  // The ring as found, or its inner two steps when a wider ring reaches another surface.
  const bool quadric = ring.size() >= 30 && region.size() >= 12;
  if (!rimOnOneSurface(image, noise, parameters, ring, fit, quadric)) {
    std::vector<RingPixel> inner;
    for (const RingPixel& p : ring)
      if (p.step <= 2)
        inner.push_back(p);
    if (steps <= 2 || !rimOnOneSurface(image, noise, parameters, inner, fit, inner.size() >= 30 && region.size() >= 12))
      return Verdict::NotOneSurface;
  }
  const auto tolerance = [&](double z) {
    return std::max(parameters.rim_noise_factor * noise.sigma(z), parameters.rim_relative_depth * z);
  };
  const Eigen::VectorXd correction = parameters.rim_correction ? harmonicMisfit(image, fit, region, label, id)
                                                               : Eigen::VectorXd::Zero(static_cast<Eigen::Index>(region.size()));
  // The fill stays within the rim's depths widened by their span and the tolerance (a quadric
  // extrapolated over a large region must not run off).
  const double slack = (z_high - z_low) + 3.0 * tolerance(z_high);
  bool sane = true;
  for (std::size_t k = 0; k < region.size() && sane; ++k) {
    const std::size_t i = region[k];
    const double column = static_cast<double>(i % W), row = static_cast<double>(i / W);
    const double q = fit(column, row) + correction(static_cast<Eigen::Index>(k));
    const double z = 1.0 / q;
    sane = q > 0.0 && std::isfinite(z) && z >= z_low - slack && z <= z_high + slack;
    hole.emplace_back(i, image.camera.pointAt(column, row, z));
  }
  return sane ? Verdict::Filled : Verdict::NotOneSurface;
}

}  // namespace

void fillOrganizedHoles(const DepthImage& image, const DepthNoiseModel& noise, const OrganizedFillParameters& parameters,
                        std::vector<std::size_t>& pixels, std::vector<Eigen::Vector3d>& positions,
                        OrganizedFillReport& report)
{
  if (!image.camera.valid)
    throw Error("organised hole filling: the cloud's pixel grid is no pinhole image");
  if (!(parameters.rim_noise_factor >= 0.0) || !(parameters.rim_relative_depth >= 0.0) ||
      !(parameters.rim_outlier_share >= 0.0 && parameters.rim_outlier_share <= 1.0) ||
      !(parameters.max_hole_diameter >= 0.0) || !(parameters.free_space_spacing >= 0.0) ||
      !(parameters.free_space_relative >= 0.0) || parameters.fit_ring < 0 || parameters.fit_ring > 64 ||
      !std::isfinite(parameters.rim_noise_factor + parameters.rim_relative_depth + parameters.free_space_spacing +
                     parameters.free_space_relative))
    throw Error("organised hole filling: parameters must be finite and ≥ 0 (rim_outlier_share ≤ 1, fit_ring ≤ 64)");
  const std::size_t W = image.width, H = image.height;
  const FreeSpaceTest free_space(image, parameters.free_space_spacing, parameters.free_space_relative);
  // Region ids on the unmeasured pixels, ring marks (the id of the region whose ring last took the
  // pixel) on the measured ones: one array, as the two never share a pixel.
  std::vector<int> label(W * H, 0);
  std::vector<int>& ring_mark = label;
  std::vector<std::pair<std::size_t, Eigen::Vector3d>> filled;
  std::vector<std::size_t> region;
  int id = 0;
  for (std::size_t seed = 0; seed < W * H; ++seed) {
    if (image.valid[seed] || label[seed])
      continue;
    ++id;
    ++report.regions;
    region.assign(1, seed);
    label[seed] = id;
    bool border = false;
    for (std::size_t k = 0; k < region.size(); ++k) {  // 4-connected flood fill
      const std::size_t i = region[k], column = i % W, row = i / W;
      border = border || column == 0 || row == 0 || column + 1 == W || row + 1 == H;
      const auto visit = [&](std::size_t j) {
        if (!image.valid[j] && !label[j]) {
          label[j] = id;
          region.push_back(j);
        }
      };
      if (column > 0) visit(i - 1);
      if (column + 1 < W) visit(i + 1);
      if (row > 0) visit(i - W);
      if (row + 1 < H) visit(i + W);
    }
    if (border) {
      ++report.touching_border;
      continue;
    }
    if (region.size() > parameters.max_hole_pixels) {
      ++report.too_large;
      continue;
    }
    std::sort(region.begin(), region.end());
    std::vector<std::pair<std::size_t, Eigen::Vector3d>> hole;
    const Verdict verdict = fillRegion(image, noise, parameters, region, label, id, ring_mark, hole);
    if (verdict == Verdict::TooLarge) {
      ++report.too_large;
      continue;
    }
    if (verdict == Verdict::NotOneSurface) {
      ++report.not_one_surface;
      continue;
    }
    ++report.holes_filled;
    for (const auto& [i, p] : hole) {
      if (free_space.violates(p)) {
        ++report.free_space_dropped;
        continue;
      }
      filled.emplace_back(i, p);
    }
  }
  std::sort(filled.begin(), filled.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [i, p] : filled) {
    pixels.push_back(i);
    positions.push_back(p);
  }
  report.pixels_filled += filled.size();
}

}  // namespace patchdict
}  // namespace pcl
