#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/patches/patch_set.h>

#include <cmath>

namespace pcl {
namespace patchdict {


double PatchSet::side() const { return std::sqrt(2.0) * radius; }

double PatchSet::observedFraction() const
{
  if (observed.size() == 0)
    return 0.0;
  return static_cast<double>(observed.count()) / static_cast<double>(observed.size());
}

void PatchSet::check() const
{
  if (grid_size < 1 || grid_size > kMaxGridSize)
    throw Error("patch set: grid size " + std::to_string(grid_size) + " is outside [1, " + std::to_string(kMaxGridSize) +
                "]");
  if (!(radius > 0.0) || !std::isfinite(radius))
    throw Error("patch set: radius must be positive and finite");
  const auto patches = static_cast<Eigen::Index>(seeds.size());
  const Eigen::Index bins = static_cast<Eigen::Index>(grid_size) * grid_size;
  if (static_cast<Eigen::Index>(rotations.size()) != patches || static_cast<Eigen::Index>(source.size()) != patches ||
      heights.rows() != bins || heights.cols() != patches || observed.rows() != bins || observed.cols() != patches)
    throw Error("patch set: sizes disagree (" + std::to_string(seeds.size()) + " seeds, " +
                std::to_string(rotations.size()) + " frames, " + std::to_string(source.size()) + " sources, heights " +
                std::to_string(heights.rows()) + "×" + std::to_string(heights.cols()) + ", mask " +
                std::to_string(observed.rows()) + "×" + std::to_string(observed.cols()) + ", " +
                std::to_string(bins) + " bins expected)");
  if (!heights.allFinite())
    throw Error("patch set: heights contain NaN or Inf");
  for (std::size_t p = 0; p < seeds.size(); ++p)
    if (!seeds[p].allFinite() || !rotations[p].allFinite())
      throw Error("patch set: seed or frame " + std::to_string(p) + " is not finite");
}

void PatchSet::append(const PatchSet& other)
{
  other.check();
  if (seeds.empty() && heights.size() == 0 && grid_size == 0) {
    *this = other;
    return;
  }
  check();
  if (other.grid_size != grid_size || other.radius != radius)
    throw Error("patch set: cannot append patches of grid " + std::to_string(other.grid_size) + " to patches of grid " +
                std::to_string(grid_size) + " (grid size and radius must match)");
  const Eigen::Index old_count = heights.cols(), extra = other.heights.cols();
  heights.conservativeResize(Eigen::NoChange, old_count + extra);
  heights.rightCols(extra) = other.heights;
  observed.conservativeResize(Eigen::NoChange, old_count + extra);
  observed.rightCols(extra) = other.observed;
  seeds.insert(seeds.end(), other.seeds.begin(), other.seeds.end());
  rotations.insert(rotations.end(), other.rotations.begin(), other.rotations.end());
  source.insert(source.end(), other.source.begin(), other.source.end());
}

}  // namespace patchdict
}  // namespace pcl
