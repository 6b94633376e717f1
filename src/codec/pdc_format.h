// The .pdc container: what PatchCodec stores, written and parsed section by section (private).
#pragma once

#include "codec/codec_coverage.h"

#include <pcl_patchdict/coding/dictionary_learning.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/core/triangle_mesh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace pcl {
namespace patchdict {
namespace detail {

/** A vertex's place on the fan-triangulated quad mesh: triangle and quantised barycentrics. */
struct VertexPlace {
  std::int32_t triangle = 0;
  std::uint32_t u = 0, v = 0;  ///< weights of the triangle's 2nd and 3rd corners, in 1/(2^bits − 1)
};

struct PdcContent {
  std::uint64_t fingerprint = 0;
  std::uint32_t grid_size = 0, num_atoms = 0;
  bool remove_mean = false, keep_connectivity = false;
  double quad_length = 0.0, radius = 0.0;
  UnitCubeNormalization normalization;
  std::uint32_t overlap = 0, coefficients = 0, coefficient_bits = 0, position_bits = 0, subdivision = 0,
                location_bits = 0;
  double coefficient_step = 0.0, mean_step = 0.0;

  std::vector<std::array<std::uint32_t, 3>> quad_positions;  ///< quantised, position_bits each
  std::vector<std::vector<std::int32_t>> quad_faces;
  /** Per patch: atoms in increasing order and their quantised coefficients. */
  std::vector<std::vector<std::uint32_t>> atoms;
  std::vector<std::vector<std::int32_t>> values;
  std::vector<std::int64_t> means;  ///< quantised (mean_step), remove_mean only
  /** Per patch: how far its seed moves along the frame's Z from the quad's centre onto the
    * surface, in units of the position grid. */
  std::vector<std::int64_t> offsets;
  ObservationMask observed;         ///< N² × P; every bin observed when empty
  std::vector<Face> faces;          ///< keep_connectivity only
  std::vector<VertexPlace> places;  ///< keep_connectivity only
  /** Frames of the coverage patches, which follow the quad mesh's patches in every per-patch
    * list above (codes, means, offsets, masks): patches = quad seeds + coverage.size(). */
  std::vector<CoverageFrame> coverage;
};

/** 2^bits − 1: the largest value of a quantisation grid of `bits` bits. */
inline double gridScale(std::uint32_t bits) { return std::ldexp(1.0, static_cast<int>(bits)) - 1.0; }

/** A unit-cube point on the position grid (quad vertices and coverage seeds alike). */
inline std::array<std::uint32_t, 3> quantisePosition(const Eigen::Vector3d& p, std::uint32_t bits)
{
  const double scale = gridScale(bits);
  std::array<std::uint32_t, 3> q;
  for (int k = 0; k < 3; ++k)
    q[static_cast<std::size_t>(k)] =
        static_cast<std::uint32_t>(std::clamp(std::lround((p[k] + 0.5) * scale), 0L, static_cast<long>(scale)));
  return q;
}

/** Sizes of the parts of a written file. */
struct PdcSizes {
  std::size_t header = 0, quad_vertices = 0, quad_faces = 0, offsets = 0, atoms = 0, coefficients = 0, means = 0, masks = 0,
              connectivity = 0, coverage = 0, total = 0;
};

std::string writePdc(const PdcContent& content, PdcSizes* sizes = nullptr);
/** Parses and checks the container (magic, version, checksum, sizes, index ranges); `what`
  * prefixes every error message. */
PdcContent readPdc(const std::string& bytes, const std::string& what);

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
