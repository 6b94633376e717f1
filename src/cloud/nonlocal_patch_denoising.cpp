// Non-local averaging of height-map patches (nonlocal_patch_denoising.h): Digne 2012, "Similarity based
// filtering of point clouds", and Buades, Coll & Morel 2005, non-local means; bench/denoise_probes.py nonlocal.
#include <pcl_patchdict/cloud/nonlocal_patch_denoising.h>

#include <pcl_patchdict/core/error.h>

#include "geometry/point_search.h"

#include <flann/flann.hpp>
#include <omp.h>

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>

namespace pcl {
namespace patchdict {

void NonlocalPatchOptions::check() const
{
  decision.check();
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (grid_size < 4 || grid_size > 32 || grid_size % 2 != 0)
    throw Error("non-local patches: the grid size must be even, in [4, 32]");
  if (!positive(bin_spacings) || !positive(kernel_bins) || !positive(fine_bin_spacings) || !positive(fine_kernel_bins))
    throw Error("non-local patches: the bins and their kernels must be > 0");
  if (dimensions < 1 || dimensions > grid_size * grid_size)
    throw Error("non-local patches: the dimensions must be in [1, grid size²]");
  if (neighbours < 1 || neighbours > 1024)
    throw Error("non-local patches: the neighbours must be in [1, 1024]");
  if (!positive(bandwidth_factor) || !std::isfinite(self_weight) || self_weight < 0.0)
    throw Error("non-local patches: the bandwidth factor must be > 0 and the self weight ≥ 0");
  if (!std::isfinite(search_eps) || search_eps < 0.0 || !std::isfinite(blind_radius) || blind_radius < 0.0)
    throw Error("non-local patches: the search tolerance and the blind radius must be ≥ 0");
  if (blind_radius >= 0.5 * grid_size * bin_spacings)
    throw Error("non-local patches: the blind radius must be below half the patch side");
  if (!std::isfinite(check_alpha) || check_alpha < 0.05 || check_alpha > 2.0)
    throw Error("non-local patches: the check's alpha must be in [0.05, 2]");
  if (pca_sample < 1 || num_threads < 0)
    throw Error("non-local patches: the PCA sample must be ≥ 1 and the threads ≥ 0");
}

namespace detail {
namespace {

constexpr int kCopies = 4;
constexpr int kLeafSize = 32;  // kd-tree leaves (12-D descriptors: measured a little faster than FLANN's 10)  // identity, 180° turn, and the two mirror images with negated heights

/** The sizes every patch shares. */
struct Geometry {
  int n = 8, nv = 16;               // descriptor and fine bins per side
  double s = 0.0, bin = 0.0, fine = 0.0, radius = 0.0;  // spacing, bin sides, neighbourhood radius
  double kernel = 0.0, fine_kernel = 0.0, blind = 0.0;  // in bins; blind radius in input units
  double exclusion = 0.0;  // with a blind spot: no match whose own point is this close (3 fine kernels at least)
  std::vector<char> blind_bin;      // per descriptor bin: inside the blind spot
  Geometry(double spacing, const NonlocalPatchOptions& o)
      : n(o.grid_size), nv(std::max(2, static_cast<int>(std::lround(o.grid_size * o.bin_spacings / o.fine_bin_spacings)))),
        s(spacing), bin(o.bin_spacings * spacing), fine(o.fine_bin_spacings * spacing),
        radius(o.grid_size * o.bin_spacings * spacing / 2.0 * std::sqrt(2.0)), kernel(o.kernel_bins),
        fine_kernel(o.fine_kernel_bins), blind(o.blind_radius * spacing),
        exclusion(std::max(blind, 3.0 * o.fine_kernel_bins * fine)), blind_bin(static_cast<std::size_t>(n * n), 0)
  {
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        blind_bin[static_cast<std::size_t>(i * n + j)] =
            std::hypot((i + 0.5 - n / 2.0) * bin, (j + 0.5 - n / 2.0) * bin) < blind;
  }
};

/** One patch as described: its frame, its own point's place and heights, its descriptor and fine grid. */
struct Patch {
  Eigen::Vector3d at = Eigen::Vector3d::Zero();  // the base point the patch is made around
  Eigen::Vector3d centre = Eigen::Vector3d::Zero(), normal = Eigen::Vector3d::UnitZ();
  double own = 0.0, base_height = 0.0;  // heights of the own noisy point and of the patch's base point
  double p = 0.0, q = 0.0;              // the own point in fine-bin coordinates
  double bin_variance = 0.0;            // mean over the seen bins of Σw²/(Σw)² (0 for the unseen)
  bool valid = false;
};

/** Tangent axes of a unit normal (the probe's convention). */
void tangentAxes(const Eigen::Vector3d& n, Eigen::Vector3d& t1, Eigen::Vector3d& t2)
{
  const Eigen::Vector3d ax = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  t1 = (ax - ax.dot(n) * n).normalized();
  t2 = n.cross(t1);
}

/** The angle of the structure tensor of a weighted quadric fit of the heights h over (u, v). */
double tensorAngle(const std::vector<double>& u, const std::vector<double>& v, const std::vector<double>& h,
                   const std::vector<double>& w, double R)
{
  Eigen::Matrix<double, 6, 6> M = Eigen::Matrix<double, 6, 6>::Identity() * 1e-9;
  Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
  for (std::size_t k = 0; k < u.size(); ++k) {
    Eigen::Matrix<double, 6, 1> a;
    const double x = u[k] / R, y = v[k] / R;
    a << x * x, x * y, y * y, x, y, 1.0;
    M.noalias() += w[k] * a * a.transpose();
    b += w[k] * h[k] * a;
  }
  const Eigen::Matrix<double, 6, 1> c = M.ldlt().solve(b);
  double j00 = 0.0, j01 = 0.0, j11 = 0.0;
  for (std::size_t k = 0; k < u.size(); ++k) {
    const double x = u[k] / R, y = v[k] / R;
    const double gu = 2.0 * c[0] * x + c[1] * y + c[3], gv = c[1] * x + 2.0 * c[2] * y + c[4];
    j00 += w[k] * gu * gu;
    j01 += w[k] * gu * gv;
    j11 += w[k] * gv * gv;
  }
  return 0.5 * std::atan2(2.0 * j01, j00 - j11);
}

/** Gaussian splat of heights h at bin coordinates (x, y) over an n × n grid of bin centres offset + k:
  * weight sums W, weighted heights H, squared weights W2. */
void splat(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& h,
           const std::vector<char>& use, int n, double offset, double kernel, std::vector<double>& W,
           std::vector<double>& H, std::vector<double>& W2)
{
  W.assign(static_cast<std::size_t>(n * n), 0.0);
  H = W;
  W2 = W;
  std::vector<double> gu(static_cast<std::size_t>(n)), gv(static_cast<std::size_t>(n));
  const double c = -0.5 / (kernel * kernel);
  for (std::size_t k = 0; k < x.size(); ++k) {
    if (!use[k])
      continue;
    for (int i = 0; i < n; ++i) {
      gu[static_cast<std::size_t>(i)] = std::exp(c * (x[k] - offset - i) * (x[k] - offset - i));
      gv[static_cast<std::size_t>(i)] = std::exp(c * (y[k] - offset - i) * (y[k] - offset - i));
    }
    for (int i = 0; i < n; ++i) {
      const double a = gu[static_cast<std::size_t>(i)];
      if (a < 1e-12)
        continue;
      for (int j = 0; j < n; ++j) {
        const double g = a * gv[static_cast<std::size_t>(j)];
        const auto b = static_cast<std::size_t>(i * n + j);
        W[b] += g;
        H[b] += g * h[k];
        W2[b] += g * g;
      }
    }
  }
}

/** Describes the patch around `centre` (a base point) with `own` its noisy point: the frame from the
  * database's base points within the radius, the descriptor (into desc) and the fine grid (into fine). */
Patch describe(const Eigen::Vector3d& centre, const Eigen::Vector3d& own, const std::vector<Eigen::Vector3d>& noisy,
               const std::vector<Eigen::Vector3d>& base, const PointSearch& search, const Geometry& g, double* desc,
               double* fine)
{
  Patch patch;
  std::vector<int> found;
  std::vector<float> squared;
  search.within(centre, floatSearchRadius(g.radius), found, squared);
  std::vector<std::size_t> nb;
  std::vector<double> w;
  const double r2 = g.radius * g.radius, sw = g.radius / 2.0;
  for (const int f : found) {
    const double d2 = (base[static_cast<std::size_t>(f)] - centre).squaredNorm();
    if (d2 <= r2) {
      nb.push_back(static_cast<std::size_t>(f));
      w.push_back(std::exp(-0.5 * d2 / (sw * sw)));
    }
  }
  std::fill(desc, desc + g.n * g.n, 0.0);
  std::fill(fine, fine + g.nv * g.nv, std::numeric_limits<double>::quiet_NaN());
  if (nb.size() < 6)
    return patch;
  double wsum = 0.0;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < nb.size(); ++k) {
    c += w[k] * base[nb[k]];
    wsum += w[k];
  }
  c /= wsum;
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (std::size_t k = 0; k < nb.size(); ++k)
    C.noalias() += w[k] * (base[nb[k]] - c) * (base[nb[k]] - c).transpose();
  const Eigen::Vector3d n = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(C).eigenvectors().col(0);
  Eigen::Vector3d t1, t2;
  tangentAxes(n, t1, t2);
  if (g.blind > 0.0)  // the grid centred on the patch's own point, the blind spot around it
    c += (centre - c) - (centre - c).dot(n) * n;
  const std::size_t m = nb.size();
  std::vector<double> u(m), v(m), hb(m), hx(m);
  for (std::size_t k = 0; k < m; ++k) {
    const Eigen::Vector3d d = base[nb[k]] - c;
    u[k] = d.dot(t1);
    v[k] = d.dot(t2);
    hb[k] = d.dot(n);
    hx[k] = (noisy[nb[k]] - c).dot(n);
  }
  const double angle = tensorAngle(u, v, hb, w, g.radius), ca = std::cos(angle), sa = std::sin(angle);
  const Eigen::Vector3d a1 = ca * t1 + sa * t2, a2 = -sa * t1 + ca * t2;  // the turned axes
  std::vector<char> use(m, 1);
  double fill = 0.0;
  for (std::size_t k = 0; k < m; ++k) {
    const double uu = ca * u[k] + sa * v[k], vv = -sa * u[k] + ca * v[k];
    u[k] = uu / g.bin;
    v[k] = vv / g.bin;
    use[k] = g.blind <= 0.0 || std::hypot(uu, vv) >= g.blind;
    fill += w[k] * hb[k];
  }
  fill /= wsum;
  std::vector<double> W, H, W2;
  splat(u, v, hx, use, g.n, 0.5 - g.n / 2.0, g.kernel, W, H, W2);
  double variance = 0.0;
  int counted = 0;
  for (int b = 0; b < g.n * g.n; ++b) {
    const auto k = static_cast<std::size_t>(b);
    if (g.blind_bin[k])
      continue;  // left out of the match (0 in every descriptor)
    const bool seen = W[k] > 0.3;
    desc[b] = seen ? H[k] / W[k] : fill;
    variance += seen ? W2[k] / (W[k] * W[k]) : 0.0;
    ++counted;
  }
  patch.bin_variance = counted ? variance / counted : 0.0;
  // The fine grid of the noisy points, in fine-bin coordinates (bin centres at 0 … nv − 1).
  const double off = g.nv / 2.0 - 0.5;
  for (std::size_t k = 0; k < m; ++k) {
    const Eigen::Vector3d d = noisy[nb[k]] - c;
    u[k] = d.dot(a1) / g.fine + off;
    v[k] = d.dot(a2) / g.fine + off;
    use[k] = 1;
  }
  splat(u, v, hx, use, g.nv, 0.0, g.fine_kernel, W, H, W2);
  for (int b = 0; b < g.nv * g.nv; ++b)
    if (W[static_cast<std::size_t>(b)] > 0.05)
      fine[b] = H[static_cast<std::size_t>(b)] / W[static_cast<std::size_t>(b)];
  patch.at = centre;
  patch.centre = c;
  patch.normal = n;
  patch.own = (own - c).dot(n);
  patch.base_height = (centre - c).dot(n);
  patch.p = (own - c).dot(a1) / g.fine + off;
  patch.q = (own - c).dot(a2) / g.fine + off;
  patch.valid = true;
  return patch;
}

/** Copy `copy` of an nv × nv grid read bilinearly at (p, q), clipped into the grid (NaN if a corner is). */
double gridAt(const double* G, int nv, int copy, double p, double q)
{
  if (copy == 1 || copy == 3)
    p = nv - 1 - p;
  if (copy == 1 || copy == 2)
    q = nv - 1 - q;
  p = std::min(std::max(p, 0.0), nv - 1 - 1e-9);
  q = std::min(std::max(q, 0.0), nv - 1 - 1e-9);
  const int i0 = static_cast<int>(std::floor(p)), j0 = static_cast<int>(std::floor(q));
  const int i1 = std::min(i0 + 1, nv - 1), j1 = std::min(j0 + 1, nv - 1);
  const double fu = p - i0, fv = q - j0;
  const double value = G[i0 * nv + j0] * (1 - fu) * (1 - fv) + G[i1 * nv + j0] * fu * (1 - fv) +
                       G[i0 * nv + j1] * (1 - fu) * fv + G[i1 * nv + j1] * fu * fv;
  return copy >= 2 ? -value : value;
}

/** Copy `copy` of an n × n descriptor. */
void copyOf(const double* d, int n, int copy, double* out)
{
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const int si = copy == 1 || copy == 3 ? n - 1 - i : i, sj = copy == 1 || copy == 2 ? n - 1 - j : j;
      out[i * n + j] = (copy >= 2 ? -1.0 : 1.0) * d[si * n + sj];
    }
}

/** PCA basis (mean, dims columns) over the copies of an evenly strided sample of the descriptors;
  * accumulated in a fixed order. */
void pcaBasis(const std::vector<double>& desc, std::size_t count, int n, int dims, std::size_t sample,
              Eigen::VectorXd& mean, Eigen::MatrixXd& basis)
{
  const int D = n * n;
  const std::size_t stride = std::max<std::size_t>(1, count / sample);
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(D);
  Eigen::MatrixXd scatter = Eigen::MatrixXd::Zero(D, D);
  Eigen::VectorXd x(D);
  double total = 0.0;
  for (std::size_t i = 0; i < count; i += stride)
    for (int copy = 0; copy < kCopies; ++copy) {
      copyOf(&desc[i * static_cast<std::size_t>(D)], n, copy, x.data());
      sum += x;
      scatter.selfadjointView<Eigen::Lower>().rankUpdate(x);
      total += 1.0;
    }
  mean = sum / total;
  Eigen::MatrixXd cov = scatter.selfadjointView<Eigen::Lower>();
  cov = cov / total - mean * mean.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(cov);
  basis = eig.eigenvectors().rightCols(dims).rowwise().reverse();  // largest first
}

int threadCount(int requested) { return requested > 0 ? requested : omp_get_max_threads(); }

}  // namespace

namespace {

/** The database: every point's patch, descriptor (n² values) and fine grid (nv² values). */
struct Database {
  std::vector<Patch> patches;
  std::vector<double> desc, fine;
};

void describeAll(const std::vector<Eigen::Vector3d>& centres, const std::vector<Eigen::Vector3d>& owns,
                 const std::vector<Eigen::Vector3d>& noisy, const std::vector<Eigen::Vector3d>& base,
                 const PointSearch& search, const Geometry& g, int threads, Database& out)
{
  const std::size_t m = centres.size(), D = static_cast<std::size_t>(g.n * g.n), F = static_cast<std::size_t>(g.nv * g.nv);
  out.patches.assign(m, Patch());
  out.desc.assign(m * D, 0.0);
  out.fine.assign(m * F, 0.0);
  const auto count = static_cast<std::ptrdiff_t>(m);
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads)
  for (std::ptrdiff_t i = 0; i < count; ++i) {
    const auto k = static_cast<std::size_t>(i);
    out.patches[k] = describe(centres[k], owns[k], noisy, base, search, g, &out.desc[k * D], &out.fine[k * F]);
  }
}

/** The mean over valid patches of the bin variance factor. */
double meanBinVariance(const std::vector<Patch>& patches)
{
  double sum = 0.0;
  std::size_t count = 0;
  for (const Patch& p : patches)
    if (p.valid) {
      sum += p.bin_variance;
      ++count;
    }
  return count ? sum / static_cast<double>(count) : 0.0;
}

/** Embeds every copy of every database descriptor (row copy × m + i) and each query's identity. */
void embed(const std::vector<double>& desc, std::size_t m, int n, const Eigen::VectorXd& mean,
           const Eigen::MatrixXd& basis, int copies, int threads, std::vector<double>& out)
{
  const int D = n * n, dims = static_cast<int>(basis.cols());
  out.assign(static_cast<std::size_t>(copies) * m * static_cast<std::size_t>(dims), 0.0);
  const auto count = static_cast<std::ptrdiff_t>(m);
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::ptrdiff_t i = 0; i < count; ++i) {
    Eigen::VectorXd x(D);
    for (int copy = 0; copy < copies; ++copy) {
      copyOf(&desc[static_cast<std::size_t>(i) * static_cast<std::size_t>(D)], n, copy, x.data());
      const Eigen::VectorXd y = basis.transpose() * (x - mean);
      double* row = &out[(static_cast<std::size_t>(copy) * m + static_cast<std::size_t>(i)) * static_cast<std::size_t>(dims)];
      for (int d = 0; d < dims; ++d)
        row[d] = y[d];
    }
  }
}

using KdIndex = flann::Index<flann::L2<double>>;

/** Every query's matches among the database's descriptor copies, weighed exp(−d²/h²), their fine grids
  * read at the query's own place and averaged with its own grid (self_weight). */
void averageMatches(const Database& db, const std::vector<std::size_t>& queries, const std::vector<double>& rows,
                    const KdIndex& index, const Geometry& g, double h2, const NonlocalPatchOptions& o, int threads,
                    NonlocalHeights& heights)
{
  const std::size_t m = index.size() / kCopies, nq = queries.size(), dims = static_cast<std::size_t>(o.dimensions);
  const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(o.neighbours + kCopies), kCopies * m);
  heights.centre.assign(nq, Eigen::Vector3d::Zero());
  heights.normal.assign(nq, Eigen::Vector3d::UnitZ());
  heights.own.assign(nq, 0.0);
  heights.base_height.assign(nq, 0.0);
  heights.estimate.assign(nq, 0.0);
  heights.effective.assign(nq, 0.0);
  heights.blind.assign(nq, 0.0);
  heights.weight.assign(nq, 0.0);
  heights.valid.assign(nq, 0);
  const std::size_t F = static_cast<std::size_t>(g.nv * g.nv);
  const auto count = static_cast<std::ptrdiff_t>(nq);
#pragma omp parallel num_threads(threads)
  {
    std::vector<std::size_t> found(k);
    std::vector<double> d2(k);
    flann::SearchParams params(flann::FLANN_CHECKS_UNLIMITED, static_cast<float>(o.search_eps), true);
    params.cores = 1;
#pragma omp for schedule(dynamic, 256)
    for (std::ptrdiff_t i = 0; i < count; ++i) {
      const auto t = static_cast<std::size_t>(i), q = queries[t];
      const Patch& patch = db.patches[q];
      if (!patch.valid)
        continue;
      flann::Matrix<double> query(const_cast<double*>(&rows[q * dims]), 1, dims);
      flann::Matrix<std::size_t> fm(found.data(), 1, k);
      flann::Matrix<double> dm(d2.data(), 1, k);
      index.knnSearch(query, fm, dm, k, params);
      double sw = 0.0, swv = 0.0, sww = 0.0;
      int used = 0;
      for (std::size_t r = 0; r < k && used < o.neighbours; ++r) {
        const std::size_t src = found[r] % m;
        const int copy = static_cast<int>(found[r] / m);
        if (src == q || !db.patches[src].valid)
          continue;
        // Blind spot: no patch whose fine grid at the query's place could hold the query's own point.
        if (g.blind > 0.0 && (db.patches[src].at - patch.at).norm() < g.exclusion)
          continue;
        ++used;
        const double value = gridAt(&db.fine[src * F], g.nv, copy, patch.p, patch.q);
        if (!std::isfinite(value))
          continue;
        const double w = std::exp(-d2[r] / h2);
        sw += w;
        swv += w * value;
        sww += w * w;
      }
      double self = patch.own;
      if (g.blind <= 0.0) {  // the probe's: the query's own grid at its place
        self = gridAt(&db.fine[q * F], g.nv, 0, patch.p, patch.q);
        if (!std::isfinite(self))
          self = patch.base_height;
      }
      const double den = sw + o.self_weight;
      heights.blind[t] = sw > 0.0 ? swv / sw : patch.base_height;
      heights.weight[t] = sw;
      heights.centre[t] = patch.centre;
      heights.normal[t] = patch.normal;
      heights.own[t] = patch.own;
      heights.base_height[t] = patch.base_height;
      heights.estimate[t] = den > 1e-9 ? (swv + o.self_weight * self) / den : patch.base_height;
      heights.effective[t] = sww > 0.0 ? sw * sw / sww : 0.0;
      heights.valid[t] = 1;
    }
  }
}

}  // namespace

void nonlocalHeights(const NonlocalData& in, double spacing, double noise_sigma, const NonlocalPatchOptions& o,
                     NonlocalHeights& heights)
{
  o.check();
  if (in.noisy.size() != in.base.size() || in.centres.size() != in.owns.size())
    throw Error("non-local patches: one noisy point per base point is needed");
  if (!(spacing > 0.0) || !std::isfinite(spacing) || !(noise_sigma > 0.0) || !std::isfinite(noise_sigma))
    throw Error("non-local patches: the spacing and the noise sigma must be finite and > 0");
  for (const std::size_t q : in.queries)
    if (q >= in.centres.size())
      throw Error("non-local patches: a query is not a patch");
  const int threads = threadCount(o.num_threads);
  const Geometry g(spacing, o);
  const std::size_t m = in.centres.size();
  if (in.database < 1 || in.database > m)
    throw Error("non-local patches: the matchable patches must be 1 to all of them");
  const PointSearch search(in.base);
  Database db;
  describeAll(in.centres, in.owns, in.noisy, in.base, search, g, threads, db);

  Eigen::VectorXd mean;
  Eigen::MatrixXd basis;
  const std::size_t matchable = std::min(in.database, m);
  pcaBasis(db.desc, matchable, g.n, o.dimensions, o.pca_sample, mean, basis);
  const int dims = o.dimensions;
  std::vector<double> data, rows;  // every copy of every matchable descriptor; every patch's own
  embed(db.desc, matchable, g.n, mean, basis, kCopies, threads, data);
  embed(db.desc, m, g.n, mean, basis, 1, threads, rows);
  flann::Matrix<double> dataset(data.data(), kCopies * matchable, static_cast<std::size_t>(dims));
  KdIndex index(dataset, flann::KDTreeSingleIndexParams(kLeafSize));
  index.buildIndex();

  // h² = f × the expected squared distance of two noisy copies of one patch: 2 × dims × a bin's variance.
  const double h2 = std::max(o.bandwidth_factor * 2.0 * dims * noise_sigma * noise_sigma * meanBinVariance(db.patches),
                             std::numeric_limits<double>::min());
  averageMatches(db, in.queries, rows, index, g, h2, o, threads, heights);
}

}  // namespace detail

namespace {
using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }
}  // namespace

namespace detail {

/** The own height and the blind average by their variances: σ², and the average's error variance
  * (one for the cloud: mean (own − blind)² − σ² over the points with matches; the own noise entered
  * neither the blind average nor its matches). */
void combineByVariance(double noise_sigma, NonlocalHeights& h)
{
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < h.own.size(); ++i)
    if (h.valid[i] && h.weight[i] > 0.0) {
      sum += (h.own[i] - h.blind[i]) * (h.own[i] - h.blind[i]);
      ++count;
    }
  const double s2 = noise_sigma * noise_sigma;
  const double v = count ? std::max(sum / static_cast<double>(count) - s2, 0.0) : 0.0;
  h.own_share = v / (v + s2);
  for (std::size_t i = 0; i < h.own.size(); ++i)
    if (h.valid[i])
      h.estimate[i] = h.own_share * h.own[i] + (1.0 - h.own_share) * h.blind[i];
}

NonlocalHeights averageAndMove(const std::vector<Eigen::Vector3d>& noisy, const std::vector<Eigen::Vector3d>& base,
                               double spacing, double noise_sigma, const NonlocalPatchOptions& options,
                               std::vector<Eigen::Vector3d>& denoised, NonlocalPatchReport& r, std::size_t stride)
{
  const auto start = Clock::now();
  options.check();
  if (noisy.size() != base.size())
    throw Error("non-local patches: one noisy point per base point is needed");
  if (base.size() < 100)
    throw Error("non-local patches: fewer than 100 points");
  for (std::size_t i = 0; i < base.size(); ++i)
    if (!base[i].allFinite() || !noisy[i].allFinite())
      throw Error("non-local patches: the points must be finite");
  if (!(spacing > 0.0) || !std::isfinite(spacing))
    spacing = detail::meanNearestSpacing(base);
  if (stride < 1)
    throw Error("non-local patches: the stride must be ≥ 1");
  std::vector<std::size_t> queries;
  for (std::size_t i = 0; i < base.size(); i += stride)
    queries.push_back(i);
  NonlocalHeights h;
  nonlocalHeights({noisy, base, base, noisy, base.size(), queries}, spacing, noise_sigma, options, h);
  if (options.blind_radius > 0.0 && options.own_by_variance)
    combineByVariance(noise_sigma, h);
  r.own_share = std::max(h.own_share, 0.0);
  denoised = base;
  std::vector<double> effective;
  double moved = 0.0;
  r.moved_points = 0;
  for (std::size_t t = 0; t < queries.size(); ++t) {
    if (!h.valid[t])
      continue;  // too few neighbours for a patch: the base's point
    const std::size_t i = queries[t];
    denoised[i] = noisy[i] + (h.estimate[t] - h.own[t]) * h.normal[t];
    moved += (denoised[i] - base[i]).norm();
    effective.push_back(h.effective[t]);
    ++r.moved_points;
  }
  r.mean_correction = r.moved_points ? moved / static_cast<double>(r.moved_points) : 0.0;
  if (!effective.empty()) {
    std::nth_element(effective.begin(), effective.begin() + static_cast<std::ptrdiff_t>(effective.size() / 2), effective.end());
    r.median_neighbours = effective[effective.size() / 2];
  }
  r.seconds_apply = secondsSince(start);
  return h;
}

}  // namespace detail

void averageSimilarPatches(const std::vector<Eigen::Vector3d>& noisy, const std::vector<Eigen::Vector3d>& base,
                           double spacing, double noise_sigma, const NonlocalPatchOptions& options,
                           std::vector<Eigen::Vector3d>& denoised, NonlocalPatchReport* report)
{
  NonlocalPatchReport local;
  detail::averageAndMove(noisy, base, spacing, noise_sigma, options, denoised, report ? *report : local);
}

}  // namespace patchdict
}  // namespace pcl
