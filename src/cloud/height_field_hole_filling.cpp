// Height-field hole filling (see height_field_hole_filling.h); the detection of the holes is in
// height_field_hole_detection.cpp.
//
// Pipeline: robust centring and outlier rejection → up frame → spacing s (median 4-NN distance on a
// subsample, grid hash) → plane raster at ~2.5 s → the outside of the data's footprint (the empty
// cells a square probe reaches from beyond the raster: the complement of a morphological closing of
// the occupied cells, Serra 1982) → 4-connected components of the other empty cells, kept when
// mostly enclosed (a narrow mouth to the outside is tolerated) and of plausible size → per hole, a
// robust quadric fitted to the rim (seeded on the lowest point per cell, then IRLS with Tukey's
// biweight; Holland & Welsch, "Robust regression using iteratively reweighted least-squares", 1977)
// plus a thin-plate spline through the pooled rim residuals (Duchon 1977), so the fill meets the rim
// it leaves — the "trend + residual interpolation" scheme of universal kriging / DTM gap filling —
// sampled on a lattice of step ~s where no input point is within 0.75 s in the plane.
#include "cloud/height_field_raster.h"

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/cloud/height_field_hole_filling.h>
#include <pcl_patchdict/geometry/thin_plate_spline.h>

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace pcl {
namespace patchdict {

namespace {

using namespace height_field_detail;

/// Robust quadric h ≈ q(u, v) in coordinates centred on `origin` and scaled by `scale` (a plane
/// below 12 points). Seeded by least squares through the lowest rim point of each raster cell (the
/// ground under trees and roofs: the lowest-point seed of progressive TIN densification, Axelsson
/// 2000), then IRLS with Tukey's biweight (c = 4.685 σ, σ = 1.4826 MAD floored at `noise_floor`):
/// redescending, it settles on the surface the seed is near and gives outliers weight 0.
struct Quadric {
  Vec2 origin = Vec2::Zero();
  double scale = 1.0;
  Eigen::Matrix<double, 6, 1> c = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 1> basis(const Vec2& x) const
  {
    const Vec2 y = (x - origin) / scale;
    Eigen::Matrix<double, 6, 1> b;
    b << 1.0, y.x(), y.y(), y.x() * y.x(), y.x() * y.y(), y.y() * y.y();
    return b;
  }
  double operator()(const Vec2& x) const { return c.dot(basis(x)); }
};

void solveWeighted(const std::vector<Vec3>& pts, const std::vector<double>& w, int terms, Quadric& q)
{
  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(terms, terms);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(terms);
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const Eigen::VectorXd b = q.basis(pts[k].head<2>()).head(terms);
    normal.noalias() += w[k] * b * b.transpose();
    rhs.noalias() += w[k] * pts[k].z() * b;
  }
  normal.diagonal().array() += 1e-9 * (1.0 + normal.diagonal().maxCoeff());
  q.c.setZero();
  q.c.head(terms) = normal.ldlt().solve(rhs);
}

std::vector<double> fitRobustQuadric(const std::vector<Vec3>& rim, const std::vector<Vec3>& seeds,
                                     double noise_floor, Quadric& q)
{
  const std::size_t n = rim.size();
  solveWeighted(seeds, std::vector<double>(seeds.size(), 1.0), seeds.size() >= 12 ? 6 : 3, q);
  const int terms = n >= 12 ? 6 : 3;
  std::vector<double> w(n, 1.0), residual(n), absolute(n);
  for (int round = 0; round < 8; ++round) {
    if (round > 0)
      solveWeighted(rim, w, terms, q);
    for (std::size_t k = 0; k < n; ++k) {
      residual[k] = rim[k].z() - q(rim[k].head<2>());
      absolute[k] = std::abs(residual[k]);
    }
    const double sigma = std::max(noise_floor, 1.4826 * quantile(absolute, 0.5));
    for (std::size_t k = 0; k < n; ++k) {
      const double t = std::abs(residual[k]) / (4.685 * sigma);
      w[k] = t < 1.0 ? (1.0 - t * t) * (1.0 - t * t) : 0.0;
    }
  }
  return w;
}

/// Thin-plate spline through the inlier rim residuals, pooled (median) into square cells grown
/// until at most max_sites remain. False when there are too few sites or the fit fails.
bool fitResidualSpline(const std::vector<Vec3>& rim, const std::vector<double>& w, const Quadric& q,
                       double cell, std::size_t max_sites, double smoothing, ThinPlateSpline& tps)
{
  std::vector<std::size_t> inliers;
  for (std::size_t k = 0; k < rim.size(); ++k)
    if (w[k] > 0.1)
      inliers.push_back(k);
  std::vector<std::pair<std::int64_t, std::size_t>> keyed(inliers.size());
  std::vector<Vec2> sites;
  std::vector<double> values;
  for (int attempt = 0; attempt < 40; ++attempt, cell *= 1.3) {
    for (std::size_t m = 0; m < inliers.size(); ++m) {
      const Vec2 x = (rim[inliers[m]].head<2>() - q.origin) / cell;
      keyed[m] = {(static_cast<std::int64_t>(std::floor(x.x())) + (1 << 20)) * (std::int64_t(1) << 22) +
                      static_cast<std::int64_t>(std::floor(x.y())) + (1 << 20), inliers[m]};
    }
    std::sort(keyed.begin(), keyed.end());
    sites.clear();
    values.clear();
    std::vector<double> group;
    for (std::size_t a = 0, b = 0; a < keyed.size(); a = b) {
      Vec2 mean = Vec2::Zero();
      group.clear();
      for (b = a; b < keyed.size() && keyed[b].first == keyed[a].first; ++b) {
        mean += rim[keyed[b].second].head<2>();
        group.push_back(rim[keyed[b].second].z() - q(rim[keyed[b].second].head<2>()));
      }
      sites.push_back(mean / static_cast<double>(b - a));
      values.push_back(quantile(group, 0.5));
    }
    if (sites.size() <= max_sites)
      break;
  }
  if (sites.size() < 6 || sites.size() > max_sites)
    return false;
  try {
    tps.fit(sites, values, smoothing);
  } catch (const Error&) {
    return false;
  }
  return true;
}

struct Settings {
  double s, cell, lattice, clearance, rim_width, min_radius, max_diameter, smoothing;
  std::size_t max_sites;
};

/// Distance in the plane from x to the nearest input point, searching `reach` cells around its
/// cell (capped at reach × cell).
double planeDistance(const Raster& r, const std::vector<Vec3>& local, const Vec2& x, std::size_t reach)
{
  double best = static_cast<double>(reach) * r.cell;
  r.around(x, static_cast<std::ptrdiff_t>(reach), [&](std::ptrdiff_t, std::ptrdiff_t, std::size_t c) {
    for (std::uint32_t k = r.start[c]; k < r.start[c + 1]; ++k)
      best = std::min(best, (local[r.order[k]].head<2>() - x).norm());
  });
  return best;
}

/// Cells within Chebyshev distance `reach` of the component (itself excluded), each once, sorted;
/// the component's cells get mark `stamp`, the ring's `stamp + 1`.
std::vector<std::uint32_t> dilation(const Raster& r, const std::vector<std::uint32_t>& cells, std::size_t reach,
                                    std::vector<std::uint32_t>& mark, std::uint32_t stamp)
{
  std::vector<std::uint32_t> ring;
  for (const std::uint32_t c : cells)
    mark[c] = stamp;
  for (const std::uint32_t c : cells)
    r.around(c % r.nx, c / r.nx, static_cast<std::ptrdiff_t>(reach), [&](std::ptrdiff_t, std::ptrdiff_t, std::size_t d) {
      if (mark[d] != stamp && mark[d] != stamp + 1) {
        mark[d] = stamp + 1;
        ring.push_back(static_cast<std::uint32_t>(d));
      }
    });
  std::sort(ring.begin(), ring.end());
  return ring;
}

/// Lattice points (global lattice of step `lattice`, anchored at the frame's origin) in cell c with
/// no input point within the clearance.
template <class Accept = bool (*)(const Vec2&)>
void latticeInCell(const Raster& r, const std::vector<Vec3>& local, std::size_t c, const Settings& st,
                   std::vector<Vec2>& out, Accept accept = [](const Vec2&) { return true; })
{
  const double ua = r.u0 + static_cast<double>(c % r.nx) * r.cell, va = r.v0 + static_cast<double>(c / r.nx) * r.cell;
  for (double b = std::ceil(va / st.lattice); b * st.lattice < va + r.cell; b += 1.0)
    for (double a = std::ceil(ua / st.lattice); a * st.lattice < ua + r.cell; a += 1.0) {
      const Vec2 x(a * st.lattice, b * st.lattice);
      if (accept(x) && planeDistance(r, local, x, 1) >= st.clearance)
        out.push_back(x);
    }
}

/// Whether x lies within half a cell of a cell marked `stamp` (the hole's empty cells): the fill
/// reaches into the occupied cells around a hole only as far as the hole's edge can lie.
bool nearCells(const Raster& r, const Vec2& x, const std::vector<std::uint32_t>& mark, std::uint32_t stamp)
{
  bool near = false;
  r.around(x, 1, [&](std::ptrdiff_t i, std::ptrdiff_t j, std::size_t c) {
    const Vec2 lo(r.u0 + static_cast<double>(i) * r.cell, r.v0 + static_cast<double>(j) * r.cell);
    near |= mark[c] == stamp && (lo - x).cwiseMax(x - lo - Vec2::Constant(r.cell)).cwiseMax(0.0).norm() <= 0.5 * r.cell;
  });
  return near;
}

enum class Outcome { filled, too_small, no_rim };

/// Fills one enclosed component: lattice over its cells and the occupied cells touching it
/// (unclaimed), heights from the rim's robust quadric + residual spline.
Outcome fillHole(const Raster& r, const std::vector<Vec3>& local, const std::vector<std::uint32_t>& cells,
                 const Settings& st, std::vector<std::uint32_t>& mark, std::uint32_t stamp,
                 std::vector<char>& claimed, std::vector<Vec3>& out_local, std::vector<std::size_t>& out_source)
{
  const auto reach = static_cast<std::size_t>(std::max(2.0, std::ceil(st.rim_width / r.cell)));
  const std::vector<std::uint32_t> ring = dilation(r, cells, reach, mark, stamp);
  std::vector<Vec2> lattice;
  for (const std::uint32_t c : cells)
    if (!claimed[c])
      latticeInCell(r, local, c, st, lattice);
  const std::size_t deep = lattice.size();
  const auto search = static_cast<std::size_t>(std::max(1.0, std::ceil(st.min_radius / r.cell)));
  double widest = 0.0;
  for (std::size_t m = 0; m < deep && widest < st.min_radius; ++m)
    widest = std::max(widest, planeDistance(r, local, lattice[m], search));
  if (widest < st.min_radius)
    return Outcome::too_small;
  std::vector<Vec3> rim, seeds;
  std::vector<std::uint32_t> rim_index;
  for (const std::uint32_t c : ring)
    for (std::uint32_t k = r.start[c]; k < r.start[c + 1]; ++k) {
      rim.push_back(local[r.order[k]]);
      rim_index.push_back(r.order[k]);
      if (k == r.start[c] || rim.back().z() < seeds.back().z())
        (k == r.start[c] ? seeds.emplace_back() : seeds.back()) = rim.back();
    }
  if (rim.size() < 4)
    return Outcome::no_rim;
  for (const std::uint32_t c : ring) {  // the occupied cells touching the hole: fill their gaps too
    bool touches = false;
    r.around(c % r.nx, c / r.nx, 1, [&](std::ptrdiff_t, std::ptrdiff_t, std::size_t d) { touches |= mark[d] == stamp; });
    if (touches && !claimed[c] && r.count(c) > 0)
      latticeInCell(r, local, c, st, lattice, [&](const Vec2& x) { return nearCells(r, x, mark, stamp); });
    if (touches)
      claimed[c] = 1;
  }
  for (const std::uint32_t c : cells)
    claimed[c] = 1;
  Quadric q;
  Vec2 lo = rim[0].head<2>(), hi = lo;
  for (const Vec3& p : rim) {
    lo = lo.cwiseMin(p.head<2>());
    hi = hi.cwiseMax(p.head<2>());
  }
  q.origin = 0.5 * (lo + hi);
  q.scale = std::max(0.5 * (hi - lo).maxCoeff(), st.s);
  const std::vector<double> w = fitRobustQuadric(rim, seeds, 0.05 * st.s, q);
  ThinPlateSpline tps;
  const bool spline = fitResidualSpline(rim, w, q, st.s, st.max_sites, st.smoothing, tps);
  for (const Vec2& x : lattice) {
    std::size_t best = 0;
    double best_d = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < rim.size(); ++k) {
      const double d = (rim[k].head<2>() - x).squaredNorm();
      if (d < best_d) {
        best_d = d;
        best = k;
      }
    }
    out_local.emplace_back(x.x(), x.y(), q(x) + (spline ? tps(x) : 0.0));
    out_source.push_back(rim_index[best]);
  }
  return Outcome::filled;
}

void checkParameters(const HeightFieldFillParameters& p)
{
  const std::pair<double, const char*> positive[] = {
      {p.detection_cell_factor, "detection_cell_factor"}, {p.max_hole_diameter_factor, "max_hole_diameter_factor"},
      {p.lattice_factor, "lattice_factor"}, {p.clearance_factor, "clearance_factor"}, {p.rim_width_factor, "rim_width_factor"}};
  const std::pair<double, const char*> non_negative[] = {
      {p.spacing, "spacing"}, {p.max_hole_diameter, "max_hole_diameter"}, {p.rim_smoothing, "rim_smoothing"},
      {p.min_hole_diameter_factor, "min_hole_diameter_factor"}, {p.outside_probe_factor, "outside_probe_factor"},
      {p.max_open_share, "max_open_share"}};
  for (const auto& [v, name] : positive)
    if (!std::isfinite(v) || !(v > 0.0))
      throw Error(std::string("height-field fill: ") + name + " must be finite and > 0");
  for (const auto& [v, name] : non_negative)
    if (!std::isfinite(v) || !(v >= 0.0))
      throw Error(std::string("height-field fill: ") + name + " must be finite and >= 0");
  if (!p.up.allFinite())
    throw Error("height-field fill: the up direction must be finite");
  if (p.clearance_factor >= p.detection_cell_factor)
    throw Error("height-field fill: clearance_factor must be smaller than detection_cell_factor");
  if (p.max_spline_sites < 6 || p.max_spline_sites > 5000)
    throw Error("height-field fill: max_spline_sites must lie in 6…5000");
  if (p.max_raster_cells < 16)
    throw Error("height-field fill: max_raster_cells must be at least 16");
}

}  // namespace

void fillHeightFieldHoles(const std::vector<Eigen::Vector3d>& points, const HeightFieldFillParameters& parameters,
                          std::vector<Eigen::Vector3d>& added, std::vector<std::size_t>& added_source,
                          HeightFieldFillReport& report)
{
  const auto t0 = std::chrono::steady_clock::now();
  checkParameters(parameters);
  added.clear();
  added_source.clear();
  report = HeightFieldFillReport();
  auto finish = [&] {
    report.points_added = added.size();
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  const Bulk bulk = robustBulk(points);
  report.points_used = bulk.kept.size();
  report.points_ignored = points.size() - bulk.kept.size();
  if (points.size() >= (std::size_t(1) << 32))
    throw Error("height-field fill: at most 2^32 − 1 points");
  const bool automatic_up = !(parameters.up.norm() > 0.0);
  report.up = automatic_up ? (bulk.kept.size() >= 3 ? pcaUp(points, bulk) : Vec3::UnitZ())
                           : Vec3(parameters.up.normalized());
  if (bulk.kept.size() < 16)
    return finish();
  const Eigen::Matrix3d rot = frameFor(report.up);
  const std::vector<Vec3> local = toLocal(points, bulk, rot);
  report.spacing = parameters.spacing > 0.0 ? parameters.spacing : estimateSpacing(local);
  if (!(report.spacing > 0.0))
    return finish();
  const double s = report.spacing;
  Settings st{s, parameters.detection_cell_factor * s, parameters.lattice_factor * s,
              parameters.clearance_factor * s, parameters.rim_width_factor * s,
              0.5 * parameters.min_hole_diameter_factor * s,
              parameters.max_hole_diameter > 0.0 ? parameters.max_hole_diameter : parameters.max_hole_diameter_factor * s,
              parameters.rim_smoothing, parameters.max_spline_sites};
  report.cell_size = st.cell;
  const auto probe = static_cast<std::size_t>(std::max(1.0, std::round(parameters.outside_probe_factor * s / st.cell)));
  const Raster r = buildRaster(local, st.cell, parameters.max_raster_cells, probe + 1);
  report.raster_width = r.nx;
  report.raster_height = r.ny;
  const std::vector<char> outside = outsideMask(r, probe);
  const Components comp = emptyComponents(r, outside);
  report.empty_components = comp.cells.size();
  std::vector<std::uint32_t> mark(r.nx * r.ny, 0);
  std::vector<char> claimed(r.nx * r.ny, 0);
  std::vector<Vec3> out_local;
  for (std::size_t id = 0; id < comp.cells.size(); ++id) {
    const std::vector<std::uint32_t>& cells = comp.cells[id];
    const Shape shape = shapeOf(r, cells, comp.label, outside);
    if (static_cast<double>(shape.open) > parameters.max_open_share * static_cast<double>(shape.boundary)) {
      ++report.rejected_border;
      continue;
    }
    if (shape.width * st.cell > st.max_diameter) {
      ++report.rejected_too_big;
      continue;
    }
    const auto stamp = static_cast<std::uint32_t>(2 * id + 2);
    const Outcome o = fillHole(r, local, cells, st, mark, stamp, claimed, out_local, added_source);
    (o == Outcome::filled ? report.holes_filled : o == Outcome::too_small ? report.rejected_too_small
                                                                          : report.rejected_no_rim)++;
  }
  added.reserve(out_local.size());
  for (std::size_t k = 0; k < out_local.size(); ++k) {
    added.push_back(bulk.centre + rot.transpose() * out_local[k]);
    added_source[k] = bulk.kept[added_source[k]];
  }
  finish();
}

}  // namespace patchdict
}  // namespace pcl
