// Point-to-mesh distance: exact closest points on triangles (Ericson) through an AABB tree with
// binned-SAH splits, float boxes rounded outwards and nearer-child-first traversal.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/geometry/metrics.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <string>

namespace pcl {
namespace patchdict {

namespace {

using Eigen::Vector3d;

/** Closest point to p on the segment [a, b]; a zero-length segment gives a. */
Vector3d closestPointOnSegment(const Vector3d& p, const Vector3d& a, const Vector3d& b)
{
  const Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  if (!(len2 > 0.0))
    return a;
  const double t = std::clamp(ab.dot(p - a) / len2, 0.0, 1.0);
  return a + t * ab;
}

/** Zero-area (collinear or coincident) triangle: its point set is the union of its three edges. */
Vector3d closestPointOnDegenerate(const Vector3d& p, const Vector3d& a, const Vector3d& b, const Vector3d& c)
{
  Vector3d best = closestPointOnSegment(p, a, b);
  double best_d2 = (p - best).squaredNorm();
  for (const Vector3d& q : {closestPointOnSegment(p, b, c), closestPointOnSegment(p, c, a)}) {
    const double d2 = (p - q).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = q;
    }
  }
  return best;
}

/** Relative thinness below which a triangle is treated as its three edges: |ab × ac| ≤ τ·L²
  * (L = longest edge) means the triangle is narrower than τ·L, so replacing it by its edges moves
  * the answer by less than τ·L, while the plane normal (needed for the face region) would carry a
  * relative error of about ε/τ. τ = 1e-8 balances the two near √ε; zero-area triangles are exact. */
constexpr double kThinness = 1e-8;

/** Whether the triangle with n = ab × ac counts as degenerate (see kThinness). */
bool isThin(const Vector3d& a, const Vector3d& b, const Vector3d& c, const Vector3d& n)
{
  const double longest2 = std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), (c - b).squaredNorm()});
  return !(n.squaredNorm() > kThinness * kThinness * longest2 * longest2);
}

// Ericson, "Real-Time Collision Detection" (2005), section 5.1.5 "Closest point on triangle to
// point": classify p against the seven Voronoi regions (3 vertices, 3 edges, face) using the six
// dot products d1..d6 and the scaled barycentrics va, vb, vc, in an order that returns as early as
// possible. Two changes to the book's version, both for robustness:
//  * zero-area / needle triangles go to the exact segment set above (the book divides by
//    va + vb + vc = |ab × ac|², which vanishes there);
//  * in the face region the point is the orthogonal projection onto the plane, p − n(n·ap)/|n|²,
//    which is algebraically identical to a + v·ab + w·ac but does not lose the cancellation in vb, vc.
// `thin` is passed in so that the tree can classify its triangles once, at build time.
inline Vector3d closestPointClassified(const Vector3d& p, const Vector3d& a, const Vector3d& b,
                                       const Vector3d& c, bool thin)
{
  if (thin)
    return closestPointOnDegenerate(p, a, b, c);
  const Vector3d ab = b - a, ac = c - a;
  // Vertex region A.
  const Vector3d ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0)
    return a;
  // Vertex region B.
  const Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3)
    return b;
  // Edge region AB.
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0)
    return a + (d1 / (d1 - d3)) * ab;
  // Vertex region C.
  const Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6)
    return c;
  // Edge region AC.
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0)
    return a + (d2 / (d2 - d6)) * ac;
  // Edge region BC.
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  // Face region.
  const Vector3d n = ab.cross(ac);
  return p - (n.dot(ap) / n.squaredNorm()) * n;
}

}  // namespace

Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c)
{
  return closestPointClassified(p, a, b, c, isThin(a, b, c, (b - a).cross(c - a)));
}

// ---------------------------------------------------------------------------------------------
// AABB tree over the faces, in one flat array. Each node holds the boxes of its TWO children
// (64 bytes, one cache line), so expanding a node costs a single memory access; a child slot is
// either an inner node (index into the array) or a leaf (a run of ≤ kLeafSize triangles, stored
// contiguously in leaf order; the mesh's vertices are copied in, renumbered in order of first use
// along the leaves, so the tree does not depend on the mesh outliving it). Splits: binned SAH on the triangle
// centroids (Wald, "On fast construction of SAH-based bounding volume hierarchies", IEEE Symp.
// Interactive Ray Tracing 2007): the plane minimising area(L)·|L| + area(R)·|R| over 16 bins per
// axis; when all centroids coincide the range is halved. Boxes are stored as float rounded
// outwards, so they still contain their triangles and the pruning stays exact.
// Query: depth-first with an explicit stack, nearer child first, a subtree pruned as soon as its
// squared box distance is not below the best squared distance found so far.

namespace {

constexpr int kLeafSize = 4;
constexpr int kNumBins = 16;

/** Two child slots. count[k] > 0: leaf, child[k] = first triangle; count[k] = 0: inner node
  * child[k]; count[k] < 0: empty slot (only in the root of a single-leaf tree). */
struct Node {
  std::array<float, 3> lo[2], hi[2];
  std::int32_t child[2];
  std::int32_t count[2];
};
static_assert(sizeof(Node) == 64, "a node should fill one cache line");

struct Box {
  Vector3d lo = Vector3d::Constant(std::numeric_limits<double>::infinity());
  Vector3d hi = Vector3d::Constant(-std::numeric_limits<double>::infinity());
  void grow(const Vector3d& p) { lo = lo.cwiseMin(p); hi = hi.cwiseMax(p); }
  void grow(const Box& b) { lo = lo.cwiseMin(b.lo); hi = hi.cwiseMax(b.hi); }
  /** Half the surface area (the SAH only compares areas). */
  double halfArea() const
  {
    if (!(lo.x() <= hi.x()))
      return 0.0;
    const Vector3d e = hi - lo;
    return e.x() * e.y() + e.y() * e.z() + e.z() * e.x();
  }
};

/** Largest float ≤ x (x finite; beyond the float range the cast would be undefined). */
float roundDown(double x)
{
  constexpr double kMax = std::numeric_limits<float>::max();
  if (x >= kMax)
    return std::numeric_limits<float>::max();
  if (x < -kMax)
    return -std::numeric_limits<float>::infinity();
  float f = static_cast<float>(x);
  if (static_cast<double>(f) > x)
    f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}

/** Smallest float ≥ x. */
float roundUp(double x)
{
  return -roundDown(-x);
}

/** Squared distance from p to the box of slot k (0 inside, +inf for an empty slot). */
inline double boxDistance2(const Node& node, int k, const Vector3d& p)
{
  double d2 = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    const double below = static_cast<double>(node.lo[k][axis]) - p[axis];
    const double above = p[axis] - static_cast<double>(node.hi[k][axis]);
    const double gap = std::max({below, above, 0.0});
    d2 += gap * gap;
  }
  return d2;
}

/** A triangle in leaf order: 16 bytes, corners index `vertices`, which are renumbered in order of
  * first use along the leaves, so a leaf and its neighbours touch few cache lines. */
struct Triangle {
  std::array<std::int32_t, 3> corner;
  std::int32_t tag;  ///< face index in the original mesh; ~face (negative) for a thin triangle
  bool thin() const { return tag < 0; }
  std::int32_t face() const { return tag < 0 ? ~tag : tag; }
};

/** 21-bit spread for Morton codes: bit i of x goes to bit 3i. */
std::uint64_t spreadBits(std::uint64_t x)
{
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

/** The faces' boxes and centroids; every corner index and coordinate is checked. */
void faceBoxes(const TriangleMesh& mesh, std::vector<Box>& boxes, std::vector<Vector3d>& centroids)
{
  const std::size_t num_faces = mesh.faces.size();
  const auto num_vertices = static_cast<std::int64_t>(mesh.vertices.size());
  boxes.assign(num_faces, Box());
  centroids.assign(num_faces, Vector3d::Zero());
  for (std::size_t f = 0; f < num_faces; ++f) {
    for (const std::int32_t v : mesh.faces[f]) {
      if (v < 0 || v >= num_vertices)
        throw Error("face " + std::to_string(f) + " has a vertex index out of range");
      if (!mesh.vertices[v].allFinite())
        throw Error("vertex " + std::to_string(v) + " has a non-finite coordinate");
      boxes[f].grow(mesh.vertices[v]);
    }
    centroids[f] = (mesh.vertices[mesh.faces[f][0]] + mesh.vertices[mesh.faces[f][1]] +
                    mesh.vertices[mesh.faces[f][2]]) / 3.0;
  }
}

/** Binned SAH over the three axes: partitions order[begin, end) at the plane minimising
  * area(L)·|L| + area(R)·|R| and returns where the right part starts; the middle of the range when
  * all centroids coincide. */
std::int32_t sahSplit(std::vector<std::int32_t>& order, std::int32_t begin, std::int32_t end,
                      const Box& centroid_bounds, const std::vector<Box>& boxes,
                      const std::vector<Vector3d>& centroids)
{
  const std::int32_t count = end - begin;
  int best_axis = -1, best_split = -1;
  double best_cost = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    const double lo = centroid_bounds.lo[axis], extent = centroid_bounds.hi[axis] - lo;
    if (!(extent > 0.0))
      continue;
    const double scale = kNumBins / extent;
    std::array<Box, kNumBins> bin_box;
    std::array<int, kNumBins> bin_count{};
    for (std::int32_t i = begin; i < end; ++i) {
      const int b = std::min(kNumBins - 1, static_cast<int>((centroids[order[i]][axis] - lo) * scale));
      bin_box[b].grow(boxes[order[i]]);
      ++bin_count[b];
    }
    // right_cost[s] = area·count of bins s+1.. (split after bin s).
    std::array<double, kNumBins> right_cost{};
    Box acc;
    int acc_count = 0;
    for (int s = kNumBins - 1; s > 0; --s) {
      acc.grow(bin_box[s]);
      acc_count += bin_count[s];
      right_cost[s - 1] = acc.halfArea() * acc_count;
    }
    acc = Box();
    acc_count = 0;
    for (int s = 0; s < kNumBins - 1; ++s) {
      acc.grow(bin_box[s]);
      acc_count += bin_count[s];
      const double cost = acc.halfArea() * acc_count + right_cost[s];
      if (acc_count > 0 && acc_count < count && cost < best_cost) {
        best_cost = cost;
        best_axis = axis;
        best_split = s;
      }
    }
  }
  if (best_axis < 0)
    return begin + count / 2;  // all centroids coincide: any halving is as good
  const double lo = centroid_bounds.lo[best_axis];
  const double scale = kNumBins / (centroid_bounds.hi[best_axis] - lo);
  const auto it = std::partition(order.begin() + begin, order.begin() + end, [&](std::int32_t f) {
    return std::min(kNumBins - 1, static_cast<int>((centroids[f][best_axis] - lo) * scale)) <= best_split;
  });
  return static_cast<std::int32_t>(it - order.begin());
}

}  // namespace

struct PointToMeshDistance::Impl {
  std::vector<Node> nodes;          ///< nodes[0] is the root
  std::vector<Triangle> triangles;  ///< in leaf order
  std::vector<Vector3d> vertices;   ///< copy of the mesh's used vertices, in first-use order
  int max_depth = 0;

  void build(const TriangleMesh& mesh);
  void storeTriangles(const TriangleMesh& mesh, const std::vector<std::int32_t>& order);
  Result query(const Vector3d& p) const;
};

void PointToMeshDistance::Impl::build(const TriangleMesh& mesh)
{
  const std::size_t num_faces = mesh.faces.size();
  if (num_faces == 0)
    throw Error("point-to-mesh distance needs a mesh with at least one face");
  if (num_faces > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max() / 2))
    throw Error("mesh has too many faces for the distance tree");
  std::vector<Box> boxes;
  std::vector<Vector3d> centroids;
  faceBoxes(mesh, boxes, centroids);

  std::vector<std::int32_t> order(num_faces);
  for (std::size_t f = 0; f < num_faces; ++f)
    order[f] = static_cast<std::int32_t>(f);

  // Root: slot 0 receives the whole range, slot 1 stays empty unless the range is split there.
  nodes.clear();
  nodes.reserve(2 * num_faces / kLeafSize + 2);
  Node root{};
  for (int k = 0; k < 2; ++k) {
    root.lo[k].fill(std::numeric_limits<float>::infinity());
    root.hi[k].fill(-std::numeric_limits<float>::infinity());
    root.child[k] = -1;
    root.count[k] = -1;
  }
  nodes.push_back(root);

  struct Task {
    std::int32_t begin, end;  ///< range in `order`
    std::int32_t node;        ///< node whose slot receives this range
    int slot;
    int depth;
  };
  std::vector<Task> tasks{{0, static_cast<std::int32_t>(num_faces), 0, 0, 0}};
  max_depth = 0;
  bool root_used = false;

  while (!tasks.empty()) {
    const Task task = tasks.back();
    tasks.pop_back();
    max_depth = std::max(max_depth, task.depth);

    Box bounds, centroid_bounds;
    for (std::int32_t i = task.begin; i < task.end; ++i) {
      bounds.grow(boxes[order[i]]);
      centroid_bounds.grow(centroids[order[i]]);
    }
    const std::int32_t count = task.end - task.begin;
    // The root's two slots take the first split directly, so the root never holds a single range.
    const bool split_into_root = task.node == 0 && task.slot == 0 && !root_used && count > kLeafSize;
    if (!split_into_root) {
      Node& parent = nodes[task.node];
      for (int k = 0; k < 3; ++k) {
        parent.lo[task.slot][k] = roundDown(bounds.lo[k]);
        parent.hi[task.slot][k] = roundUp(bounds.hi[k]);
      }
      if (count <= kLeafSize) {
        parent.child[task.slot] = task.begin;
        parent.count[task.slot] = count;
        continue;
      }
    }
    const std::int32_t mid = sahSplit(order, task.begin, task.end, centroid_bounds, boxes, centroids);

    std::int32_t target;
    if (split_into_root) {
      root_used = true;
      target = 0;
    } else {
      target = static_cast<std::int32_t>(nodes.size());
      Node inner{};
      inner.child[0] = inner.child[1] = -1;
      inner.count[0] = inner.count[1] = -1;
      nodes.push_back(inner);  // may reallocate: no reference into nodes is held here
      nodes[task.node].child[task.slot] = target;
      nodes[task.node].count[task.slot] = 0;
    }
    tasks.push_back({mid, task.end, target, 1, task.depth + 1});
    tasks.push_back({task.begin, mid, target, 0, task.depth + 1});
  }
  storeTriangles(mesh, order);
}

/** The triangles in leaf order, their vertices copied in and renumbered in order of first use,
  * thin ones tagged. */
void PointToMeshDistance::Impl::storeTriangles(const TriangleMesh& mesh, const std::vector<std::int32_t>& order)
{
  const std::size_t num_faces = order.size();
  triangles.resize(num_faces);
  vertices.clear();
  std::vector<std::int32_t> renumbered(mesh.vertices.size(), -1);
  for (std::size_t i = 0; i < num_faces; ++i) {
    const Face& t = mesh.faces[order[i]];
    Triangle& tri = triangles[i];
    for (int k = 0; k < 3; ++k) {
      if (renumbered[t[k]] < 0) {
        renumbered[t[k]] = static_cast<std::int32_t>(vertices.size());
        vertices.push_back(mesh.vertices[t[k]]);
      }
      tri.corner[k] = renumbered[t[k]];
    }
    const Vector3d &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    tri.tag = isThin(a, b, c, (b - a).cross(c - a)) ? ~order[i] : order[i];
  }
}

PointToMeshDistance::Result PointToMeshDistance::Impl::query(const Vector3d& p) const
{
  struct Entry {
    std::int32_t child, count;  ///< a slot: inner node (count 0) or leaf
    double d2;
  };
  // One deferred sibling per level at most, plus the two root slots.
  constexpr int kLocal = 128;
  Entry local[kLocal];
  std::vector<Entry> heap;
  Entry* stack = local;
  if (max_depth + 3 > kLocal) {
    heap.resize(static_cast<std::size_t>(max_depth) + 3);
    stack = heap.data();
  }

  Result result;
  double best = std::numeric_limits<double>::infinity();
  std::int32_t best_slot = -1;
  int top = 0;
  stack[top++] = {0, 0, 0.0};
  while (top > 0) {
    const Entry entry = stack[--top];
    if (entry.d2 >= best)
      continue;
    if (entry.count > 0) {  // leaf
      for (std::int32_t i = entry.child; i < entry.child + entry.count; ++i) {
        const Triangle& tri = triangles[i];
        const Vector3d q = closestPointClassified(p, vertices[tri.corner[0]], vertices[tri.corner[1]],
                                                  vertices[tri.corner[2]], tri.thin());
        const double d2 = (p - q).squaredNorm();
        if (d2 < best) {
          best = d2;
          result.closest_point = q;
          best_slot = i;
        }
      }
      continue;
    }
    const Node& node = nodes[entry.child];
    const double d0 = node.count[0] >= 0 ? boxDistance2(node, 0, p) : std::numeric_limits<double>::infinity();
    const double d1 = node.count[1] >= 0 ? boxDistance2(node, 1, p) : std::numeric_limits<double>::infinity();
    // Push the farther slot first so the nearer one is popped (and tightens `best`) first.
    const int near = d0 <= d1 ? 0 : 1, far = 1 - near;
    const double d_near = near == 0 ? d0 : d1, d_far = near == 0 ? d1 : d0;
    if (d_far < best)
      stack[top++] = {node.child[far], node.count[far], d_far};
    if (d_near < best)
      stack[top++] = {node.child[near], node.count[near], d_near};
  }
  if (best_slot < 0)  // only with a NaN query point: nothing compares below +inf
    throw Error("point-to-mesh distance queried with a non-finite point");
  result.squared_distance = best;
  result.face = triangles[best_slot].face();
  return result;
}

PointToMeshDistance::PointToMeshDistance(const TriangleMesh& mesh) : impl_(std::make_unique<Impl>())
{
  impl_->build(mesh);
}

PointToMeshDistance::~PointToMeshDistance() = default;
PointToMeshDistance::PointToMeshDistance(PointToMeshDistance&&) noexcept = default;
PointToMeshDistance& PointToMeshDistance::operator=(PointToMeshDistance&&) noexcept = default;

PointToMeshDistance::Result PointToMeshDistance::query(const Eigen::Vector3d& p) const
{
  if (!impl_)
    throw Error("PointToMeshDistance used after being moved from");
  return impl_->query(p);
}

std::vector<double> PointToMeshDistance::distances(const std::vector<Eigen::Vector3d>& points) const
{
  if (!impl_)
    throw Error("PointToMeshDistance used after being moved from");
  const std::size_t n = points.size();
  std::vector<double> out(n);
  if (n == 0)
    return out;
  Box bounds;
  for (const Vector3d& p : points) {
    if (!p.allFinite())
      throw Error("point-to-mesh distance queried with a non-finite point");
    bounds.grow(p);
  }
  // Queries are answered in Morton (Z-curve) order of the points: consecutive queries then walk
  // nearly the same tree nodes and triangles, which stay in cache (≈ 1.4× faster than input order
  // on the scattered points of bench_point_to_mesh). Each answer is independent of the order, so
  // the output is exactly that of querying one by one.
  std::vector<std::pair<std::uint64_t, std::size_t>> keyed(n);
  const Vector3d extent = (bounds.hi - bounds.lo).cwiseMax(Vector3d::Constant(1e-300));
  const Vector3d scale = Vector3d::Constant(2097151.0).cwiseQuotient(extent);  // 2^21 − 1
  for (std::size_t i = 0; i < n; ++i) {
    const Vector3d cell = (points[i] - bounds.lo).cwiseProduct(scale).cwiseMin(2097151.0);
    keyed[i] = {spreadBits(static_cast<std::uint64_t>(cell.x())) |
                    spreadBits(static_cast<std::uint64_t>(cell.y())) << 1 |
                    spreadBits(static_cast<std::uint64_t>(cell.z())) << 2,
                i};
  }
  std::sort(keyed.begin(), keyed.end());

  const auto count = static_cast<std::int64_t>(n);
  const Impl& impl = *impl_;
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::int64_t k = 0; k < count; ++k) {
    const std::size_t i = keyed[k].second;
    out[i] = std::sqrt(impl.query(points[i]).squared_distance);
  }
  return out;
}

}  // namespace patchdict
}  // namespace pcl
