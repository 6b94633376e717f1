// Liepa's refinement of a hole's triangulation (Liepa 2003, section 4): centroid splits until the
// fill's density matches its boundary's, with edge-flip relaxation between rounds.
#include <pcl_patchdict/geometry/hole_triangulation.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>

namespace pcl {
namespace patchdict {

namespace {

std::uint64_t edgeKey(int a, int b)
{
  if (a > b)
    std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

double cornerAngle(const Eigen::Vector3d& at, const Eigen::Vector3d& p, const Eigen::Vector3d& q)
{
  const Eigen::Vector3d u = p - at, v = q - at;
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

class PatchRefiner {
public:
  PatchRefiner(HolePatch& patch, const std::vector<std::pair<int, int>>& forbidden,
               const HoleRefinementOptions& options, HoleRefinementReport& report)
      : patch_(patch), options_(options), report_(report)
  {
    for (const auto& [a, b] : forbidden)
      forbidden_.push_back(edgeKey(a, b));
    std::sort(forbidden_.begin(), forbidden_.end());
    edges_.reserve(patch_.faces.size() * 2 + 64);
    for (std::size_t f = 0; f < patch_.faces.size(); ++f)
      for (int c = 0; c < 3; ++c)
        attach(patch_.faces[f][c], patch_.faces[f][(c + 1) % 3], static_cast<int>(f));
  }

  void run()
  {
    for (int round = 0; round < options_.max_rounds; ++round) {
      bool split_any = false;
      const std::size_t face_count = patch_.faces.size();
      for (std::size_t f = 0; f < face_count; ++f)
        if (trySplit(static_cast<int>(f)))
          split_any = true;
      if (!split_any)
        break;
      ++report_.rounds;
      relaxAll();
    }
  }

private:
  using FacePair = std::array<int, 2>;

  void attach(int a, int b, int face)
  {
    auto [it, inserted] = edges_.try_emplace(edgeKey(a, b), FacePair{face, -1});
    if (!inserted)
      it->second[1] = face;
  }

  void replace(int a, int b, int old_face, int new_face)
  {
    FacePair& pair = edges_.at(edgeKey(a, b));
    (pair[0] == old_face ? pair[0] : pair[1]) = new_face;
  }

  bool trySplit(int f)
  {
    const Face t = patch_.faces[f];
    const auto& p = patch_.positions;
    const Eigen::Vector3d centroid = (p[t[0]] + p[t[1]] + p[t[2]]) / 3.0;
    const double centroid_scale = (patch_.scale[t[0]] + patch_.scale[t[1]] + patch_.scale[t[2]]) / 3.0;
    for (int c = 0; c < 3; ++c) {
      const double reach = options_.density_factor * (centroid - p[t[c]]).norm();
      if (!(reach > centroid_scale && reach > patch_.scale[t[c]]))
        return false;
    }
    const int v = static_cast<int>(patch_.positions.size());
    patch_.positions.push_back(centroid);
    patch_.scale.push_back(centroid_scale);
    const int f1 = static_cast<int>(patch_.faces.size()), f2 = f1 + 1;
    patch_.faces[f] = {t[0], t[1], v};
    patch_.faces.push_back({t[1], t[2], v});
    patch_.faces.push_back({t[2], t[0], v});
    replace(t[1], t[2], f, f1);
    replace(t[2], t[0], f, f2);
    attach(t[0], v, f);
    attach(t[0], v, f2);
    attach(t[1], v, f);
    attach(t[1], v, f1);
    attach(t[2], v, f1);
    attach(t[2], v, f2);
    ++report_.splits;
    relax(t[0], t[1]);
    relax(t[1], t[2]);
    relax(t[2], t[0]);
    return true;
  }

  // Flips edge (a, b) when it is interior, not Delaunay, and the flip is legal. True if flipped;
  // then (c, d) is the new edge.
  bool relax(int a, int b, int* new_c = nullptr, int* new_d = nullptr)
  {
    const auto found = edges_.find(edgeKey(a, b));
    if (found == edges_.end() || found->second[1] < 0)
      return false;  // a loop edge (one patch face)
    int f = found->second[0], g = found->second[1];
    // Orient: f walks a → b, g walks b → a.
    const auto walks = [this](int face, int from, int to) {
      const Face& t = patch_.faces[face];
      for (int c = 0; c < 3; ++c)
        if (t[c] == from && t[(c + 1) % 3] == to)
          return true;
      return false;
    };
    if (!walks(f, a, b))
      std::swap(f, g);
    if (!walks(f, a, b) || !walks(g, b, a))
      return false;  // inconsistent orientation: leave it alone
    const auto third = [this](int face, int x, int y) {
      for (const int v : patch_.faces[face])
        if (v != x && v != y)
          return v;
      return -1;
    };
    const int c = third(f, a, b), d = third(g, a, b);
    if (c < 0 || d < 0 || c == d)
      return false;
    const auto& p = patch_.positions;
    if (!(cornerAngle(p[c], p[a], p[b]) + cornerAngle(p[d], p[a], p[b]) > M_PI + 1e-12))
      return false;
    const std::uint64_t new_key = edgeKey(c, d);
    if (edges_.count(new_key) || std::binary_search(forbidden_.begin(), forbidden_.end(), new_key))
      return false;
    // New faces (c, a, d) and (d, b, c): both proper, not folded onto each other or the old pair.
    const Eigen::Vector3d n1 = (p[a] - p[c]).cross(p[d] - p[c]);
    const Eigen::Vector3d n2 = (p[b] - p[d]).cross(p[c] - p[d]);
    const Eigen::Vector3d old = (p[b] - p[a]).cross(p[c] - p[a]) + (p[a] - p[b]).cross(p[d] - p[b]);
    const double scale = (p[a] - p[b]).squaredNorm() + (p[c] - p[d]).squaredNorm();
    if (!(n1.norm() > 1e-10 * scale && n2.norm() > 1e-10 * scale) || !(n1.dot(n2) > 0.0) ||
        !(n1.dot(old) > 0.0) || !(n2.dot(old) > 0.0))
      return false;
    patch_.faces[f] = {c, a, d};
    patch_.faces[g] = {d, b, c};
    edges_.erase(edgeKey(a, b));
    replace(a, d, g, f);
    replace(b, c, f, g);
    edges_.emplace(new_key, FacePair{f, g});
    ++report_.flips;
    if (new_c)
      *new_c = c;
    if (new_d)
      *new_d = d;
    return true;
  }

  void relaxAll()
  {
    // Every interior edge once (from its lower face), then the four outer edges of each flipped
    // quad again. 3-D flips have no termination proof, so the total is capped.
    std::vector<std::pair<int, int>> queue;
    for (std::size_t f = 0; f < patch_.faces.size(); ++f)
      for (int c = 0; c < 3; ++c) {
        const Face& t = patch_.faces[f];
        const auto found = edges_.find(edgeKey(t[c], t[(c + 1) % 3]));
        if (found != edges_.end() && found->second[1] >= 0 &&
            std::min(found->second[0], found->second[1]) == static_cast<int>(f))
          queue.emplace_back(t[c], t[(c + 1) % 3]);
      }
    const std::size_t limit = 20 * queue.size() + 100;
    for (std::size_t head = 0; head < queue.size() && head < limit; ++head) {
      const auto [a, b] = queue[head];
      int c = -1, d = -1;
      if (relax(a, b, &c, &d)) {
        queue.emplace_back(a, c);
        queue.emplace_back(c, b);
        queue.emplace_back(b, d);
        queue.emplace_back(d, a);
      }
    }
  }

  HolePatch& patch_;
  const HoleRefinementOptions& options_;
  HoleRefinementReport& report_;
  std::vector<std::uint64_t> forbidden_;
  std::unordered_map<std::uint64_t, FacePair> edges_;
};

}  // namespace

void refineHolePatch(HolePatch& patch, const std::vector<std::pair<int, int>>& forbidden,
                     const HoleRefinementOptions& options, HoleRefinementReport* report)
{
  HoleRefinementReport local;
  if (patch.scale.size() != patch.positions.size())
    patch.scale.resize(patch.positions.size(), 0.0);
  PatchRefiner refiner(patch, forbidden, options, report ? *report : local);
  refiner.run();
}

}  // namespace patchdict
}  // namespace pcl
