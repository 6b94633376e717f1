// Extrinsic 4-PoSy position field on the multi-resolution hierarchy (Jakob et al. 2015, §4–5),
// implemented from the paper's description — not from the reference code.
#include <pcl_patchdict/quads/position_field.h>

#include <pcl_patchdict/core/error.h>

#include "quads/field_common.h"

#include <omp.h>

#include <cmath>
#include <limits>
#include <random>

namespace pcl {
namespace patchdict {

Eigen::Vector2i positionFloorIndex4(const Eigen::Vector3d& o, const Eigen::Vector3d& q, const Eigen::Vector3d& n,
                                    const Eigen::Vector3d& p, double scale)
{
  const Eigen::Vector3d t = n.cross(q);
  const Eigen::Vector3d d = p - o;
  return Eigen::Vector2i(static_cast<int>(std::floor(q.dot(d) / scale)),
                         static_cast<int>(std::floor(t.dot(d) / scale)));
}

Eigen::Vector3d positionFloor4(const Eigen::Vector3d& o, const Eigen::Vector3d& q, const Eigen::Vector3d& n,
                               const Eigen::Vector3d& p, double scale)
{
  const Eigen::Vector3d t = n.cross(q);
  const Eigen::Vector3d d = p - o;
  return o + q * (std::floor(q.dot(d) / scale) * scale) + t * (std::floor(t.dot(d) / scale) * scale);
}

Eigen::Vector3d positionRound4(const Eigen::Vector3d& o, const Eigen::Vector3d& q, const Eigen::Vector3d& n,
                               const Eigen::Vector3d& p, double scale)
{
  const Eigen::Vector3d t = n.cross(q);
  const Eigen::Vector3d d = p - o;
  return o + q * (std::round(q.dot(d) / scale) * scale) + t * (std::round(t.dot(d) / scale) * scale);
}

Eigen::Vector3d middlePoint(const Eigen::Vector3d& p0, const Eigen::Vector3d& n0, const Eigen::Vector3d& p1,
                            const Eigen::Vector3d& n1)
{
  // Lagrange conditions of min |x−p0|² + |x−p1|² s.t. n0·(x−p0) = 0, n1·(x−p1) = 0.
  const double n0p0 = n0.dot(p0), n0p1 = n0.dot(p1), n1p0 = n1.dot(p0), n1p1 = n1.dot(p1);
  const double n0n1 = n0.dot(n1);
  const double denominator = 1.0 / (1.0 - n0n1 * n0n1 + 1e-4);
  const double lambda0 = 2.0 * ((n0p1 - n0p0) - n0n1 * (n1p0 - n1p1)) * denominator;
  const double lambda1 = 2.0 * ((n1p0 - n1p1) - n0n1 * (n0p1 - n0p0)) * denominator;
  return 0.5 * (p0 + p1) - 0.25 * (lambda0 * n0 + lambda1 * n1);
}

namespace {

/** Of the corners c0 + {0, s·q0} + {0, s·t0} and c1 + {0, s·q1} + {0, s·t1} (given as c, s·q, s·t),
  * the closest pair: their indices (bit 0: +q, bit 1: +t), positions and squared distance. */
struct CornerMatch {
  int a = 0, b = 0;
  Eigen::Vector3d p0, p1;
  double squared_distance = 0.0;
};

inline CornerMatch closestCornerPair(const Eigen::Vector3d& c0, const Eigen::Vector3d& sq0, const Eigen::Vector3d& st0,
                                     const Eigen::Vector3d& c1, const Eigen::Vector3d& sq1, const Eigen::Vector3d& st1)
{
  const Eigen::Vector3d corners0[4] = {c0, c0 + sq0, c0 + st0, c0 + sq0 + st0};
  const Eigen::Vector3d corners1[4] = {c1, c1 + sq1, c1 + st1, c1 + sq1 + st1};
  CornerMatch best;
  best.squared_distance = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) {
      const double d = (corners0[a] - corners1[b]).squaredNorm();
      if (d < best.squared_distance) {
        best.squared_distance = d;
        best.a = a;
        best.b = b;
      }
    }
  best.p0 = corners0[best.a];
  best.p1 = corners1[best.b];
  return best;
}

/** The cells of both lattices that contain the two vertices' middle point (their integer corners
  * relative to each origin) and the closest pair of corners of those cells. */
struct CellMatch {
  Eigen::Vector2i base0, base1;
  CornerMatch corners;
};

CellMatch matchCells(const Eigen::Vector3d& v0, const Eigen::Vector3d& n0, const Eigen::Vector3d& q0,
                     const Eigen::Vector3d& o0, const Eigen::Vector3d& v1, const Eigen::Vector3d& n1,
                     const Eigen::Vector3d& q1, const Eigen::Vector3d& o1, double scale)
{
  const Eigen::Vector3d t0 = n0.cross(q0), t1 = n1.cross(q1);
  const Eigen::Vector3d middle = middlePoint(v0, n0, v1, n1);
  CellMatch match;
  match.base0 = positionFloorIndex4(o0, q0, n0, middle, scale);
  match.base1 = positionFloorIndex4(o1, q1, n1, middle, scale);
  const Eigen::Vector3d c0 = o0 + q0 * (match.base0.x() * scale) + t0 * (match.base0.y() * scale);
  const Eigen::Vector3d c1 = o1 + q1 * (match.base1.x() * scale) + t1 * (match.base1.y() * scale);
  match.corners = closestCornerPair(c0, scale * q0, scale * t0, c1, scale * q1, scale * t1);
  return match;
}

}  // namespace

std::pair<Eigen::Vector3d, Eigen::Vector3d> compatPositionExtrinsic4(
    const Eigen::Vector3d& v0, const Eigen::Vector3d& n0, const Eigen::Vector3d& q0, const Eigen::Vector3d& o0,
    const Eigen::Vector3d& v1, const Eigen::Vector3d& n1, const Eigen::Vector3d& q1, const Eigen::Vector3d& o1,
    double scale)
{
  const CellMatch match = matchCells(v0, n0, q0, o0, v1, n1, q1, o1, scale);
  return {match.corners.p0, match.corners.p1};
}

std::pair<Eigen::Vector2i, Eigen::Vector2i> compatPositionExtrinsicIndex4(
    const Eigen::Vector3d& v0, const Eigen::Vector3d& n0, const Eigen::Vector3d& q0, const Eigen::Vector3d& o0,
    const Eigen::Vector3d& v1, const Eigen::Vector3d& n1, const Eigen::Vector3d& q1, const Eigen::Vector3d& o1,
    double scale, double* error)
{
  const CellMatch match = matchCells(v0, n0, q0, o0, v1, n1, q1, o1, scale);
  if (error)
    *error = match.corners.squared_distance;
  const int a = match.corners.a, b = match.corners.b;
  return {match.base0 + Eigen::Vector2i(a & 1, (a & 2) >> 1), match.base1 + Eigen::Vector2i(b & 1, (b & 2) >> 1)};
}

std::vector<std::vector<Eigen::Vector3d>> restrictOrientationField(const FieldHierarchy& hierarchy,
                                                                   const std::vector<Eigen::Vector3d>& field)
{
  if (hierarchy.levels.empty() || field.size() != hierarchy.levels[0].numVertices())
    throw Error("position field: the orientation field does not match the hierarchy");
  std::vector<std::vector<Eigen::Vector3d>> q(hierarchy.numLevels());
  q[0] = field;
  for (std::size_t l = 1; l < hierarchy.numLevels(); ++l) {
    const FieldLevel& fine = hierarchy.levels[l - 1];
    const FieldLevel& coarse = hierarchy.levels[l];
    q[l].resize(coarse.numVertices());
    for (std::size_t c = 0; c < coarse.numVertices(); ++c) {
      const auto& ch = coarse.children[c];
      Eigen::Vector3d sum = q[l - 1][ch[0]];
      if (ch[1] >= 0) {
        const auto ab = compatOrientationExtrinsic4(q[l - 1][ch[0]], fine.normals[ch[0]], q[l - 1][ch[1]],
                                                    fine.normals[ch[1]]);
        const double a0 = fine.areas[ch[0]], a1 = fine.areas[ch[1]];
        sum = (a0 + a1 > 0.0) ? Eigen::Vector3d(ab.first * a0 + ab.second * a1) : Eigen::Vector3d(ab.first + ab.second);
      }
      q[l][c] = detail::projectToTangent(sum, coarse.normals[c]);
    }
  }
  return q;
}

namespace {

/** Per level, what the sweeps reuse: t = n × q per vertex, and the middle point of every directed
  * edge (it depends only on positions and normals). */
struct LevelCache {
  std::vector<Eigen::Vector3d> t;
  std::vector<Eigen::Vector3d> middle;  ///< parallel to level.adjacency
};

LevelCache makeLevelCache(const FieldLevel& level, const std::vector<Eigen::Vector3d>& q, int threads)
{
  LevelCache cache;
  const std::int64_t n = static_cast<std::int64_t>(level.numVertices());
  cache.t.resize(level.numVertices());
  cache.middle.resize(level.adjacency.size());
#pragma omp parallel for num_threads(threads) schedule(static) if (n > 4096)
  for (std::int64_t i = 0; i < n; ++i) {
    cache.t[i] = level.normals[i].cross(q[i]);
    for (std::int32_t e = level.adjacency_offsets[i]; e < level.adjacency_offsets[i + 1]; ++e) {
      const std::int32_t j = level.adjacency[e];
      cache.middle[e] = middlePoint(level.positions[i], level.normals[i], level.positions[j], level.normals[j]);
    }
  }
  return cache;
}

/** The corner of the cell of lattice (o, q, t, s) that contains p. */
inline Eigen::Vector3d floorCorner(const Eigen::Vector3d& o, const Eigen::Vector3d& q, const Eigen::Vector3d& t,
                                   const Eigen::Vector3d& p, double scale, double inverse_scale)
{
  const Eigen::Vector3d d = p - o;
  return o + q * (std::floor(q.dot(d) * inverse_scale) * scale) + t * (std::floor(t.dot(d) * inverse_scale) * scale);
}

/** One Gauss–Seidel update of origin i (Jakob et al. 2015 §4), with the
  * same arithmetic as compatPositionExtrinsic4 but the per-level constants taken from the cache. */
void smoothPositionVertex(const FieldLevel& level, const std::vector<Eigen::Vector3d>& q, const LevelCache& cache,
                          std::vector<Eigen::Vector3d>& o, std::int32_t i, double scale)
{
  const double inverse_scale = 1.0 / scale;
  const Eigen::Vector3d& v_i = level.positions[i];
  const Eigen::Vector3d& n_i = level.normals[i];
  const Eigen::Vector3d sq_i = scale * q[i], st_i = scale * cache.t[i];
  Eigen::Vector3d sum = o[i];
  double weight_sum = 0.0;
  for (std::int32_t e = level.adjacency_offsets[i]; e < level.adjacency_offsets[i + 1]; ++e) {
    const std::int32_t j = level.adjacency[e];
    const double w = level.adjacency_weights[e];
    const Eigen::Vector3d& middle = cache.middle[e];
    const Eigen::Vector3d c0 = floorCorner(sum, q[i], cache.t[i], middle, scale, inverse_scale);
    const Eigen::Vector3d c1 = floorCorner(o[j], q[j], cache.t[j], middle, scale, inverse_scale);
    const CornerMatch match = closestCornerPair(c0, sq_i, st_i, c1, scale * q[j], scale * cache.t[j]);
    sum = (match.p0 * weight_sum + match.p1 * w) / (weight_sum + w);
    weight_sum += w;
    sum -= n_i * n_i.dot(sum - v_i);
  }
  if (weight_sum > 0.0)
    o[i] = positionRound4(sum, q[i], n_i, v_i, scale);
}

}  // namespace

std::vector<Eigen::Vector3d> computePositionField(const FieldHierarchy& hierarchy,
                                                  const std::vector<std::vector<Eigen::Vector3d>>& orientation,
                                                  const PositionFieldParameters& parameters)
{
  if (hierarchy.levels.empty() || orientation.size() != hierarchy.numLevels())
    throw Error("position field: the orientation field does not match the hierarchy");
  for (std::size_t l = 0; l < hierarchy.numLevels(); ++l)
    if (orientation[l].size() != hierarchy.levels[l].numVertices())
      throw Error("position field: the orientation field does not match the hierarchy");
  const double scale = parameters.scale;
  if (!(scale > 0.0) || !std::isfinite(scale))
    throw Error("position field: the lattice spacing must be positive and finite");
  if (parameters.iterations_per_level < 0)
    throw Error("position field: iterations_per_level must be non-negative");
  const int threads = parameters.num_threads > 0 ? parameters.num_threads : omp_get_max_threads();

  const int coarsest = static_cast<int>(hierarchy.numLevels()) - 1;
  const FieldLevel& top = hierarchy.levels[coarsest];
  std::vector<Eigen::Vector3d> o(top.numVertices());
  std::mt19937_64 rng(parameters.seed ^ 0x9e3779b97f4a7c15ULL);
  for (std::size_t i = 0; i < top.numVertices(); ++i) {
    Eigen::Vector3d e1 = Eigen::Vector3d::UnitX(), e2 = Eigen::Vector3d::UnitY();
    if (top.normals[i].squaredNorm() > 0.0)
      detail::tangentFrame(top.normals[i], e1, e2);
    const double x = 2.0 * detail::uniform01(rng) - 1.0, y = 2.0 * detail::uniform01(rng) - 1.0;
    o[i] = top.positions[i] + scale * (x * e1 + y * e2);
  }
  for (int l = coarsest; l >= 0; --l) {
    const FieldLevel& level = hierarchy.levels[l];
    const std::vector<Eigen::Vector3d>& q = orientation[l];
    const LevelCache cache = makeLevelCache(level, q, threads);
    for (int iteration = 0; iteration < parameters.iterations_per_level; ++iteration) {
      for (const auto& phase : level.phases) {
        const std::int64_t size = static_cast<std::int64_t>(phase.size());
        // Vertices of one phase are pairwise non-adjacent: the parallel sweep equals the serial one.
#pragma omp parallel for num_threads(threads) schedule(static) if (size > 1024)
        for (std::int64_t p = 0; p < size; ++p)
          smoothPositionVertex(level, q, cache, o, phase[p], scale);
      }
    }
    if (l == 0)
      break;
    const FieldLevel& finer = hierarchy.levels[l - 1];
    std::vector<Eigen::Vector3d> o_fine(finer.numVertices(), Eigen::Vector3d::Zero());
    for (std::size_t c = 0; c < level.children.size(); ++c)
      for (const std::int32_t child : level.children[c])
        if (child >= 0) {
          const Eigen::Vector3d& n = finer.normals[child];
          o_fine[child] = o[c] - n * n.dot(o[c] - finer.positions[child]);
        }
    o.swap(o_fine);
  }
  // Re-anchor every origin at the lattice point nearest its vertex (also when no sweep ran).
  const FieldLevel& finest = hierarchy.levels[0];
  for (std::size_t i = 0; i < o.size(); ++i)
    o[i] = positionRound4(o[i], orientation[0][i], finest.normals[i], finest.positions[i], scale);
  return o;
}

double positionFieldEnergy(const FieldLevel& level, const std::vector<Eigen::Vector3d>& orientation,
                           const std::vector<Eigen::Vector3d>& origins, double scale)
{
  if (orientation.size() != level.numVertices() || origins.size() != level.numVertices())
    throw Error("position field: field sizes do not match the level");
  double energy = 0.0;
  for (std::size_t i = 0; i < level.numVertices(); ++i)
    for (std::int32_t e = level.adjacency_offsets[i]; e < level.adjacency_offsets[i + 1]; ++e) {
      const std::int32_t j = level.adjacency[e];
      if (static_cast<std::size_t>(j) <= i)
        continue;
      const auto ab = compatPositionExtrinsic4(level.positions[i], level.normals[i], orientation[i], origins[i],
                                               level.positions[j], level.normals[j], orientation[j], origins[j], scale);
      energy += (ab.first - ab.second).squaredNorm() / (scale * scale);
    }
  return energy;
}

}  // namespace patchdict
}  // namespace pcl
