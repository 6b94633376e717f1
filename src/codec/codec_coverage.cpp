// Coverage patches of the .pdc codec: frames chosen where the quad mesh's surface misses the
// input, stored quantised, and decoded as small grids of their kept bins.
#include "codec/codec_coverage.h"

#include "codec/pdc_format.h"

#include "geometry/point_search.h"

#include <pcl_patchdict/geometry/metrics.h>
#include <pcl_patchdict/core/local_frame.h>
#include <pcl_patchdict/core/vertex_normals.h>

#include <pcl/kdtree/kdtree_flann.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace pcl {
namespace patchdict {
namespace detail {

namespace {

constexpr double kPi = 3.14159265358979323846;

double signNotZero(double v) { return v < 0.0 ? -1.0 : 1.0; }

/** Octahedral map of a unit vector to [−1, 1]² (Cigolle et al. 2014, section 3.3). */
Eigen::Vector2d octahedralEncode(const Eigen::Vector3d& n)
{
  const Eigen::Vector3d p = n / (std::abs(n.x()) + std::abs(n.y()) + std::abs(n.z()));
  if (p.z() >= 0.0)
    return {p.x(), p.y()};
  return {(1.0 - std::abs(p.y())) * signNotZero(p.x()), (1.0 - std::abs(p.x())) * signNotZero(p.y())};
}

Eigen::Vector3d octahedralDecode(const Eigen::Vector2d& e)
{
  Eigen::Vector3d n(e.x(), e.y(), 1.0 - std::abs(e.x()) - std::abs(e.y()));
  if (n.z() < 0.0) {
    const double x = n.x();
    n.x() = (1.0 - std::abs(n.y())) * signNotZero(x);
    n.y() = (1.0 - std::abs(x)) * signNotZero(n.y());
  }
  return n.normalized();
}

std::uint32_t quantiseUnit(double v, std::uint32_t bits)  // v in [−1, 1]
{
  const double scale = gridScale(bits);
  return static_cast<std::uint32_t>(std::clamp(std::lround((v + 1.0) * 0.5 * scale), 0L, static_cast<long>(scale)));
}

CoverageFrame quantiseFrame(const Eigen::Vector3d& seed, const Eigen::Vector3d& normal, const Eigen::Vector3d& tangent,
                            std::uint32_t position_bits)
{
  CoverageFrame frame;
  frame.position = quantisePosition(seed, position_bits);
  const Eigen::Vector2d e = octahedralEncode(normal);
  frame.normal_u = quantiseUnit(e.x(), kCoverageNormalBits);
  frame.normal_v = quantiseUnit(e.y(), kCoverageNormalBits);
  // The angle of the tangent against the decoder's own reference X for the *quantised* normal.
  Eigen::Vector3d seed_q;
  Eigen::Matrix3d reference;
  CoverageFrame zero_angle = frame;
  zero_angle.angle = 0;
  coverageSeedAndRotation(zero_angle, position_bits, seed_q, reference);
  double angle = std::atan2(tangent.dot(reference.row(1)), tangent.dot(reference.row(0)));
  if (angle < 0.0)
    angle += kPi;  // X and −X give the same patch up to a half turn; keep [0, π)
  const double steps = std::ldexp(1.0, static_cast<int>(kCoverageAngleBits));
  frame.angle = static_cast<std::uint32_t>(std::lround(angle / kPi * steps)) % static_cast<std::uint32_t>(steps);
  return frame;
}

}  // namespace

void coverageSeedAndRotation(const CoverageFrame& frame, std::uint32_t position_bits, Eigen::Vector3d& seed,
                             Eigen::Matrix3d& rotation)
{
  const double scale = gridScale(position_bits);
  for (int k = 0; k < 3; ++k)
    seed[k] = frame.position[static_cast<std::size_t>(k)] / scale - 0.5;
  const double normal_scale = gridScale(kCoverageNormalBits);
  const Eigen::Vector3d z = octahedralDecode(
      Eigen::Vector2d(frame.normal_u / normal_scale * 2.0 - 1.0, frame.normal_v / normal_scale * 2.0 - 1.0));
  const Eigen::Vector3d x0 = z.unitOrthogonal(), y0 = z.cross(x0);
  const double angle = frame.angle * kPi / std::ldexp(1.0, static_cast<int>(kCoverageAngleBits));
  const Eigen::Vector3d x = std::cos(angle) * x0 + std::sin(angle) * y0;
  rotation.row(0) = x;
  rotation.row(1) = z.cross(x);
  rotation.row(2) = z;
  // Rounded to float, as the quad patches' frames (core/local_frame.h): the rotation the height
  // maps are sampled in is exactly the one both sides decode with, as in version-3 files.
  rotation = roundToSinglePrecision(rotation);
}

std::vector<CoverageFrame> chooseCoverageFrames(const TriangleMesh& surface, const PointToMeshDistance& decoded,
                                                double radius, double tolerance, std::uint32_t position_bits,
                                                std::size_t max_patches)
{
  std::vector<CoverageFrame> frames;
  if (max_patches == 0 || surface.vertices.empty())
    return frames;
  const std::size_t n = surface.vertices.size();
  const std::vector<double> distance = decoded.distances(surface.vertices);
  std::vector<std::int32_t> candidates;
  std::vector<char> covered(n, 1);
  for (std::size_t v = 0; v < n; ++v)
    if (distance[v] > tolerance) {
      candidates.push_back(static_cast<std::int32_t>(v));
      covered[v] = 0;
    }
  if (candidates.empty())
    return frames;
  std::sort(candidates.begin(), candidates.end(), [&](std::int32_t a, std::int32_t b) {
    return distance[static_cast<std::size_t>(a)] != distance[static_cast<std::size_t>(b)]
               ? distance[static_cast<std::size_t>(a)] > distance[static_cast<std::size_t>(b)]
               : a < b;
  });

  const std::vector<Eigen::Vector3d> normals = computeVertexNormals(surface);
  const detail::PointSearch tree(surface.vertices, false);
  const double half = 0.4 * std::sqrt(2.0) * radius;  // 80 % of the square's half side
  std::vector<int> found;
  std::vector<float> squared;
  for (const std::int32_t v : candidates) {
    if (covered[static_cast<std::size_t>(v)])
      continue;
    if (frames.size() >= max_patches)
      break;
    covered[static_cast<std::size_t>(v)] = 1;
    const Eigen::Vector3d& s = surface.vertices[static_cast<std::size_t>(v)];
    const Eigen::Vector3d& own = normals[static_cast<std::size_t>(v)];
    if (own.squaredNorm() < 0.5)
      continue;  // a vertex of degenerate faces only
    tree.within(s, floatSearchRadius(radius), found, squared);
    std::vector<std::int32_t> ball;
    for (const int u : found)
      if ((surface.vertices[static_cast<std::size_t>(u)] - s).squaredNorm() <= radius * radius)
        ball.push_back(u);
    std::sort(ball.begin(), ball.end());  // FLANN's order is not part of the result
    Eigen::Vector3d z = Eigen::Vector3d::Zero();
    for (const std::int32_t u : ball) {
      const Eigen::Vector3d& nu = normals[static_cast<std::size_t>(u)];
      if ((surface.vertices[static_cast<std::size_t>(u)] - s).norm() <= 0.25 * radius && nu.dot(own) > 0.0)
        z += nu;
    }
    z = z.norm() > 1e-9 ? Eigen::Vector3d(z.normalized()) : own;
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (const std::int32_t u : ball)
      if (normals[static_cast<std::size_t>(u)].dot(z) > 0.0) {
        Eigen::Vector3d d = surface.vertices[static_cast<std::size_t>(u)] - s;
        d -= d.dot(z) * z;
        scatter += d * d.transpose();
      }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
    Eigen::Vector3d tangent = eigen.eigenvectors().col(2);
    tangent -= tangent.dot(z) * z;
    if (tangent.norm() < 1e-6)
      tangent = z.unitOrthogonal();
    const CoverageFrame frame = quantiseFrame(s, z, tangent.normalized(), position_bits);
    Eigen::Vector3d seed;
    Eigen::Matrix3d rotation;
    coverageSeedAndRotation(frame, position_bits, seed, rotation);
    std::size_t newly = 0;
    for (const std::int32_t u : ball) {
      if (covered[static_cast<std::size_t>(u)])
        continue;
      const Eigen::Vector3d local = rotation * (surface.vertices[static_cast<std::size_t>(u)] - seed);
      if (std::abs(local.x()) <= half && std::abs(local.y()) <= half &&
          normals[static_cast<std::size_t>(u)].dot(rotation.row(2)) > 0.3) {
        covered[static_cast<std::size_t>(u)] = 1;
        ++newly;
      }
    }
    if (newly >= 2)  // a lone stray vertex is not worth a patch
      frames.push_back(frame);
  }
  return frames;
}

std::vector<Eigen::Vector3d> binPoints(const Eigen::Vector3d& seed, const Eigen::Matrix3d& rotation, double side,
                                       int grid, const Eigen::VectorXd& heights)
{
  std::vector<Eigen::Vector3d> points(static_cast<std::size_t>(grid) * grid);
  for (int j = 0; j < grid; ++j)
    for (int i = 0; i < grid; ++i) {
      const double x = (i + 0.5) / grid * side - 0.5 * side, y = (j + 0.5) / grid * side - 0.5 * side;
      points[static_cast<std::size_t>(j * grid + i)] =
          seed + rotation.transpose() * Eigen::Vector3d(x, y, heights[j * grid + i]);
    }
  return points;
}

std::vector<char> coverageBins(const std::vector<char>& observed, const std::vector<double>& bin_distances,
                               double tolerance, int grid)
{
  const std::size_t bins = static_cast<std::size_t>(grid) * grid;
  std::vector<char> needed(bins, 0), kept(bins, 0);
  for (std::size_t b = 0; b < bins; ++b)
    needed[b] = observed[b] && bin_distances[b] > tolerance;
  for (int j = 0; j < grid; ++j)
    for (int i = 0; i < grid; ++i) {
      const std::size_t b = static_cast<std::size_t>(j * grid + i);
      if (!observed[b])
        continue;
      for (int dj = -1; dj <= 1 && !kept[b]; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const int ii = i + di, jj = j + dj;
          if (ii >= 0 && jj >= 0 && ii < grid && jj < grid && needed[static_cast<std::size_t>(jj * grid + ii)]) {
            kept[b] = 1;
            break;
          }
        }
    }
  return kept;
}

std::size_t completeCells(const std::vector<char>& kept, int grid)
{
  std::size_t cells = 0;
  for (int j = 0; j + 1 < grid; ++j)
    for (int i = 0; i + 1 < grid; ++i)
      cells += kept[static_cast<std::size_t>(j * grid + i)] && kept[static_cast<std::size_t>(j * grid + i + 1)] &&
                       kept[static_cast<std::size_t>((j + 1) * grid + i)] &&
                       kept[static_cast<std::size_t>((j + 1) * grid + i + 1)]
                   ? 1
                   : 0;
  return cells;
}

void appendCoveragePiece(const Eigen::Vector3d& seed, const Eigen::Matrix3d& rotation, double side, int grid,
                         const Eigen::VectorXd& heights, const std::vector<char>& kept, TriangleMesh& out)
{
  const std::vector<Eigen::Vector3d> points = binPoints(seed, rotation, side, grid, heights);
  // A vertex for every kept bin that a complete cell uses; two triangles per complete cell.
  std::vector<std::int32_t> index(points.size(), -1);
  const auto vertex = [&](int i, int j) {
    std::int32_t& slot = index[static_cast<std::size_t>(j * grid + i)];
    if (slot < 0) {
      slot = static_cast<std::int32_t>(out.vertices.size());
      out.vertices.push_back(points[static_cast<std::size_t>(j * grid + i)]);
    }
    return slot;
  };
  const auto on = [&](int i, int j) { return kept[static_cast<std::size_t>(j * grid + i)] != 0; };
  for (int j = 0; j + 1 < grid; ++j)
    for (int i = 0; i + 1 < grid; ++i) {
      if (!on(i, j) || !on(i + 1, j) || !on(i + 1, j + 1) || !on(i, j + 1))
        continue;
      const std::int32_t a = vertex(i, j), b = vertex(i + 1, j), c = vertex(i + 1, j + 1), d = vertex(i, j + 1);
      // Counter-clockwise seen from +Z (X right, Y up): the piece faces the frame's Z.
      out.faces.push_back({a, b, c});
      out.faces.push_back({a, c, d});
    }
}

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
