// Minimum-weight triangulation of a hole's boundary loop (Liepa 2003, section 3, after Barequet &
// Sharir 1995): an O(n³) dynamic programme over sub-polygons, with a chord split for long loops.
#include <pcl_patchdict/geometry/hole_triangulation.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace pcl {
namespace patchdict {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Dihedral badness is 1 − cos(angle) (monotone in the angle, no trigonometry in the inner loop).
// Below this difference two angles count as equal and the area decides: without it, rounding in
// the normals of a tilted planar hole (all angles 0) would decide instead of the area.
constexpr double kBadnessTolerance = 1e-12;
constexpr double kDegenerateBadness = 2.0;  // a zero-area triangle counts as a fold (angle π)

struct Weight {
  double badness = kInfinity;
  double area = kInfinity;
  bool valid() const { return badness < kInfinity; }
};

bool better(const Weight& a, const Weight& b, HoleTriangulationWeight mode)
{
  if (mode == HoleTriangulationWeight::Area)
    return a.area < b.area;
  if (a.badness < b.badness - kBadnessTolerance)
    return true;
  if (b.badness < a.badness - kBadnessTolerance)
    return false;
  return a.area < b.area;
}

std::uint64_t edgeKey(int a, int b)
{
  if (a > b)
    std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

// Unit normal of triangle (a, b, c); zero when its sine is below 1e-10 (degenerate).
Eigen::Vector3d unitNormal(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c)
{
  const Eigen::Vector3d u = b - a, v = c - a;
  const Eigen::Vector3d n = u.cross(v);
  const double squared = n.squaredNorm();
  if (!(squared > 1e-20 * u.squaredNorm() * v.squaredNorm()))
    return Eigen::Vector3d::Zero();
  return n / std::sqrt(squared);
}

struct Piece {
  std::vector<int> loop_index;             // global loop indices, in cyclic loop order
  std::vector<Eigen::Vector3d> apex_normal;  // per piece edge j → j+1 (last: closing edge); zero = none
};

class Triangulator {
public:
  Triangulator(const std::vector<Eigen::Vector3d>& loop, const std::vector<std::pair<int, int>>& forbidden,
               const HoleTriangulationOptions& options)
      : loop_(loop), options_(options)
  {
    forbidden_.reserve(forbidden.size());
    for (const auto& [a, b] : forbidden)
      forbidden_.push_back(edgeKey(a, b));
    std::sort(forbidden_.begin(), forbidden_.end());
  }

  bool isForbidden(int a, int b) const
  {
    return std::binary_search(forbidden_.begin(), forbidden_.end(), edgeKey(a, b));
  }

  // Triangulates the piece (splitting it first when too long); appends global faces.
  bool solve(const Piece& piece, std::vector<Face>& faces, std::size_t& pieces)
  {
    const std::size_t m = piece.loop_index.size();
    if (m <= std::max<std::size_t>(options_.max_dp_vertices, 3)) {
      ++pieces;
      return dynamicProgramme(piece, faces);
    }
    int a = -1, b = -1;
    if (!findSplitChord(piece, m / 4, a, b) && !findSplitChord(piece, 2, a, b))
      return false;
    Piece first, second;
    for (int j = a; j <= b; ++j)
      first.loop_index.push_back(piece.loop_index[j]);
    for (int j = a; j < b; ++j)
      first.apex_normal.push_back(piece.apex_normal[j]);
    first.apex_normal.push_back(Eigen::Vector3d::Zero());  // the chord: its other side is the other piece
    for (std::size_t j = static_cast<std::size_t>(b); j < m; ++j) {
      second.loop_index.push_back(piece.loop_index[j]);
      second.apex_normal.push_back(piece.apex_normal[j]);
    }
    for (int j = 0; j <= a; ++j) {
      second.loop_index.push_back(piece.loop_index[j]);
      second.apex_normal.push_back(j < a ? piece.apex_normal[j] : Eigen::Vector3d::Zero());
    }
    return solve(first, faces, pieces) && solve(second, faces, pieces);
  }

private:
  // The allowed chord (a, b), a < b, with at least `min_side` loop edges on each side, that
  // minimises its length over the shorter loop arc between its ends: the loop's narrowest waist.
  bool findSplitChord(const Piece& piece, std::size_t min_side, int& best_a, int& best_b) const
  {
    const std::size_t m = piece.loop_index.size();
    std::vector<double> arc(m + 1, 0.0);  // arc[j]: loop length from piece vertex 0 to j
    for (std::size_t j = 0; j < m; ++j)
      arc[j + 1] = arc[j] + (loop_[piece.loop_index[(j + 1) % m]] - loop_[piece.loop_index[j]]).norm();
    const double total = arc[m];
    double best = kInfinity;
    min_side = std::max<std::size_t>(min_side, 2);
    for (std::size_t i = 0; i < m; ++i)
      for (std::size_t k = i + min_side; k < m && m - (k - i) >= min_side; ++k) {
        const int gi = piece.loop_index[i], gk = piece.loop_index[k];
        if (isForbidden(gi, gk))
          continue;
        const double along = std::min(arc[k] - arc[i], total - (arc[k] - arc[i]));
        const double ratio = (loop_[gi] - loop_[gk]).norm() / std::max(along, 1e-300);
        if (ratio < best) {
          best = ratio;
          best_a = static_cast<int>(i);
          best_b = static_cast<int>(k);
        }
      }
    return best < kInfinity;
  }

  bool dynamicProgramme(const Piece& piece, std::vector<Face>& faces) const
  {
    const int m = static_cast<int>(piece.loop_index.size());
    const auto at = [m](int i, int k) { return static_cast<std::size_t>(i) * static_cast<std::size_t>(m) + k; };
    std::vector<Eigen::Vector3d> p(m);
    for (int j = 0; j < m; ++j)
      p[j] = loop_[piece.loop_index[j]];
    std::vector<Weight> weight(static_cast<std::size_t>(m) * m);
    std::vector<int> apex(static_cast<std::size_t>(m) * m, -1);
    std::vector<Eigen::Vector3d> normal(static_cast<std::size_t>(m) * m, Eigen::Vector3d::Zero());
    std::vector<char> forbidden(static_cast<std::size_t>(m) * m, 0);
    if (!forbidden_.empty())
      for (int i = 0; i < m; ++i)
        for (int k = i + 2; k < m; ++k)
          forbidden[at(i, k)] = !(i == 0 && k == m - 1) && isForbidden(piece.loop_index[i], piece.loop_index[k]);
    for (int i = 0; i + 1 < m; ++i)
      weight[at(i, i + 1)] = Weight{0.0, 0.0};
    const bool area_only = options_.weight == HoleTriangulationWeight::Area;
    const Eigen::Vector3d& closing_normal = piece.apex_normal[m - 1];

    for (int gap = 2; gap < m; ++gap)
      for (int i = 0; i + gap < m; ++i) {
        const int k = i + gap;
        if (forbidden[at(i, k)])
          continue;  // stays invalid
        Weight best;
        int best_apex = -1;
        Eigen::Vector3d best_normal = Eigen::Vector3d::Zero();
        const Eigen::Vector3d to_k = p[k] - p[i];
        for (int mid = i + 1; mid < k; ++mid) {
          const Weight& left = weight[at(i, mid)];
          const Weight& right = weight[at(mid, k)];
          if (!left.valid() || !right.valid())
            continue;
          const Eigen::Vector3d to_mid = p[mid] - p[i];
          const Eigen::Vector3d cross = to_mid.cross(to_k);
          const double squared = cross.squaredNorm();
          Weight candidate;
          candidate.area = left.area + right.area + 0.5 * std::sqrt(squared);
          Eigen::Vector3d n = Eigen::Vector3d::Zero();
          if (area_only) {
            candidate.badness = 0.0;
          } else if (!(squared > 1e-20 * to_mid.squaredNorm() * to_k.squaredNorm())) {
            candidate.badness = kDegenerateBadness;
          } else {
            n = cross / std::sqrt(squared);
            double badness = std::max(left.badness, right.badness);
            // Neighbours across (i, mid) and (mid, k): the mesh face beyond a loop edge, or the
            // triangle the sub-problem chose. Zero normals (no neighbour, degenerate) add nothing.
            const Eigen::Vector3d& across_left = mid == i + 1 ? piece.apex_normal[i] : normal[at(i, mid)];
            const Eigen::Vector3d& across_right = k == mid + 1 ? piece.apex_normal[mid] : normal[at(mid, k)];
            if (across_left.squaredNorm() > 0.0)
              badness = std::max(badness, 1.0 - n.dot(across_left));
            if (across_right.squaredNorm() > 0.0)
              badness = std::max(badness, 1.0 - n.dot(across_right));
            if (i == 0 && k == m - 1 && closing_normal.squaredNorm() > 0.0)
              badness = std::max(badness, 1.0 - n.dot(closing_normal));
            candidate.badness = badness;
          }
          if (better(candidate, best, options_.weight)) {
            best = candidate;
            best_apex = mid;
            best_normal = n;
          }
        }
        weight[at(i, k)] = best;
        apex[at(i, k)] = best_apex;
        normal[at(i, k)] = best_normal;
      }
    if (!weight[at(0, m - 1)].valid())
      return false;
    std::vector<std::pair<int, int>> stack{{0, m - 1}};
    while (!stack.empty()) {
      const auto [i, k] = stack.back();
      stack.pop_back();
      const int mid = apex[at(i, k)];
      faces.push_back({piece.loop_index[i], piece.loop_index[mid], piece.loop_index[k]});
      if (mid - i >= 2)
        stack.emplace_back(i, mid);
      if (k - mid >= 2)
        stack.emplace_back(mid, k);
    }
    return true;
  }

  const std::vector<Eigen::Vector3d>& loop_;
  const HoleTriangulationOptions& options_;
  std::vector<std::uint64_t> forbidden_;
};

}  // namespace

HoleTriangulation triangulateHoleLoop(const std::vector<Eigen::Vector3d>& loop,
                                      const std::vector<Eigen::Vector3d>& outside_apex,
                                      const std::vector<std::pair<int, int>>& forbidden,
                                      const HoleTriangulationOptions& options)
{
  HoleTriangulation result;
  const int n = static_cast<int>(loop.size());
  if (n < 3)
    return result;
  // Normal of the mesh face (b, a, d) across loop edge a → b: the orientation a fill triangle
  // walking a → b agrees with.
  Piece whole;
  whole.loop_index.resize(n);
  whole.apex_normal.assign(n, Eigen::Vector3d::Zero());
  for (int j = 0; j < n; ++j) {
    whole.loop_index[j] = j;
    if (static_cast<int>(outside_apex.size()) == n && outside_apex[j].allFinite())
      whole.apex_normal[j] = unitNormal(loop[(j + 1) % n], loop[j], outside_apex[j]);
  }
  Triangulator triangulator(loop, forbidden, options);
  result.pieces = 0;
  result.valid = triangulator.solve(whole, result.faces, result.pieces);
  if (!result.valid) {
    result.faces.clear();
    return result;
  }

  // The weight of what was built, measured honestly (chords of split loops included).
  std::unordered_map<std::uint64_t, std::vector<int>> edge_faces;
  std::vector<Eigen::Vector3d> face_normal(result.faces.size());
  for (std::size_t f = 0; f < result.faces.size(); ++f) {
    const Face& t = result.faces[f];
    face_normal[f] = unitNormal(loop[t[0]], loop[t[1]], loop[t[2]]);
    result.area += 0.5 * (loop[t[1]] - loop[t[0]]).cross(loop[t[2]] - loop[t[0]]).norm();
    for (int c = 0; c < 3; ++c)
      edge_faces[edgeKey(t[c], t[(c + 1) % 3])].push_back(static_cast<int>(f));
  }
  const auto angle = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    if (a.squaredNorm() == 0.0 || b.squaredNorm() == 0.0)
      return 0.0;
    return std::atan2(a.cross(b).norm(), a.dot(b));
  };
  for (std::size_t f = 0; f < result.faces.size(); ++f) {
    const Face& t = result.faces[f];
    if (face_normal[f].squaredNorm() == 0.0)
      result.max_dihedral_angle = M_PI;
    for (int c = 0; c < 3; ++c) {
      const int a = t[c], b = t[(c + 1) % 3];
      if ((a + 1) % n == b) {
        result.max_dihedral_angle = std::max(result.max_dihedral_angle, angle(face_normal[f], whole.apex_normal[a]));
        continue;
      }
      for (const int g : edge_faces[edgeKey(a, b)])
        if (g != static_cast<int>(f))
          result.max_dihedral_angle = std::max(result.max_dihedral_angle, angle(face_normal[f], face_normal[g]));
    }
  }
  return result;
}

}  // namespace patchdict
}  // namespace pcl
