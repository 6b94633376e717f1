// Area-uniform surface sampling. Why it is built this way:
//  * a face is drawn with probability area/total through a cumulative area table and a binary
//    search (O(log F) per sample, no alias table to keep exact);
//  * inside the face the point is uniform by area through the square-root warp of two uniforms
//    (Osada, Funkhouser, Chazelle, Dobkin, "Shape distributions", ACM TOG 2002, section 4.2):
//      r1 = sqrt(u), p = (1 − r1)·a + r1·(1 − v)·b + r1·v·c;
//  * reproducibility independent of the thread count: samples are produced in fixed-size blocks,
//    each block with its own std::mt19937_64 whose seed is a SplitMix64 hash of (seed, block).
//    Which thread runs a block does not matter, so any OpenMP team gives the same bytes.
//  * uniforms are built from the raw 64-bit engine output (top 53 bits), not from
//    std::uniform_real_distribution, whose algorithm differs between standard libraries.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/surface_sampling.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

namespace pcl {
namespace patchdict {

namespace {

/** Samples per independently seeded block; fixed so results do not depend on scheduling. */
constexpr std::size_t kBlockSize = 8192;

/** SplitMix64 finaliser (Steele, Lea, Flood, "Fast splittable pseudorandom number generators",
  * OOPSLA 2014): decorrelates the block seeds derived from consecutive integers. */
std::uint64_t splitMix64(std::uint64_t x)
{
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

/** Uniform double in [0, 1) from the 53 high bits of one engine draw. */
double uniform01(std::mt19937_64& rng)
{
  return static_cast<double>(rng() >> 11) * (1.0 / 9007199254740992.0);  // 2^-53
}

}  // namespace

SurfaceSamples sampleSurfaceUniform(const TriangleMesh& mesh, std::size_t num_samples, std::uint64_t seed)
{
  if (mesh.faces.empty())
    throw Error("cannot sample the surface of a mesh without faces");
  const std::size_t num_faces = mesh.faces.size();
  const auto num_vertices = static_cast<std::int64_t>(mesh.vertices.size());

  // Inclusive prefix sums of the face areas: face f covers [cumulative[f-1], cumulative[f]).
  std::vector<double> cumulative(num_faces);
  double total = 0.0;
  std::size_t last_positive = num_faces;
  for (std::size_t f = 0; f < num_faces; ++f) {
    for (const std::int32_t v : mesh.faces[f])
      if (v < 0 || v >= num_vertices)
        throw Error("face " + std::to_string(f) + " has a vertex index out of range");
    const double area = mesh.faceArea(f);
    if (area > 0.0)
      last_positive = f;
    total += area;
    cumulative[f] = total;
  }
  if (!(total > 0.0) || !std::isfinite(total))
    throw Error("cannot sample a surface of zero (or non-finite) area");

  SurfaceSamples out;
  out.points.resize(num_samples);
  out.face_ids.resize(num_samples);
  if (num_samples == 0)
    return out;

  const auto num_blocks = static_cast<std::int64_t>((num_samples + kBlockSize - 1) / kBlockSize);
#pragma omp parallel for schedule(static)
  for (std::int64_t block = 0; block < num_blocks; ++block) {
    std::mt19937_64 rng(splitMix64(seed ^ splitMix64(static_cast<std::uint64_t>(block))));
    const std::size_t begin = static_cast<std::size_t>(block) * kBlockSize;
    const std::size_t end = std::min(num_samples, begin + kBlockSize);
    for (std::size_t i = begin; i < end; ++i) {
      const double target = uniform01(rng) * total;
      // First face whose cumulative area exceeds the target; zero-area faces are never chosen
      // because their interval is empty. Rounding can push target to total: clamp.
      std::size_t f = static_cast<std::size_t>(
          std::upper_bound(cumulative.begin(), cumulative.end(), target) - cumulative.begin());
      if (f >= num_faces)
        f = last_positive;
      const Face& t = mesh.faces[f];
      const double r1 = std::sqrt(uniform01(rng));
      const double v = uniform01(rng);
      out.points[i] = (1.0 - r1) * mesh.vertices[t[0]] + (r1 * (1.0 - v)) * mesh.vertices[t[1]] +
                      (r1 * v) * mesh.vertices[t[2]];
      out.face_ids[i] = static_cast<std::int32_t>(f);
    }
  }
  return out;
}

}  // namespace patchdict
}  // namespace pcl
