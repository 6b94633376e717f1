// The surface a .pdc content stands for, as both sides of the codec derive it: the quad mesh
// rebuilt from its quantised vertices, frames re-derived, codes dequantised, the surface
// reconstructed and the coverage pieces added. Private to the library (PatchCodec uses it).
#pragma once

#include "codec/pdc_format.h"

#include <pcl_patchdict/codec/patch_codec.h>
#include <pcl_patchdict/patches/patch_set.h>
#include <pcl_patchdict/quads/quad_mesh.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace pcl {
namespace patchdict {
namespace detail {

/** Renumbers the vertices in order of first use by the faces (what the face coding expects) and
  * drops vertices no face uses; works for triangles and polygons alike. */
template <typename FaceList>
void renumberByFirstUse(FaceList& faces, std::vector<Eigen::Vector3d>& vertices)
{
  std::vector<std::int32_t> map(vertices.size(), -1);
  std::vector<Eigen::Vector3d> used;
  for (auto& face : faces)
    for (auto& v : face) {
      auto& slot = map[static_cast<std::size_t>(v)];
      if (slot < 0) {
        slot = static_cast<std::int32_t>(used.size());
        used.push_back(vertices[static_cast<std::size_t>(v)]);
      }
      v = slot;
    }
  vertices = std::move(used);
}

/** The quad mesh both sides work with: dequantised positions (unit cube), the stored faces, and
  * vertex normals from the faces' Newell vectors, so frames never need storing. */
QuadMesh rebuildQuadMesh(const PdcContent& c);

/** Seeds and frames (rounded, as rotations: rows X, Y, Z) of the quad mesh's patches
  * (computeQuadFrames). */
void quadSeeds(const QuadMesh& quads, std::uint32_t overlap, std::vector<Eigen::Vector3d>& seeds,
               std::vector<Eigen::Matrix3d>& rotations);

/** Seeds moved along their frames' Z (row 2 of each rotation) by the stored offsets, in units of
  * the position grid: the encoder and the decoder move them with this one function. */
void applySeedOffsets(const std::vector<std::int64_t>& offsets, std::uint32_t position_bits,
                      std::vector<Eigen::Vector3d>& seeds, const std::vector<Eigen::Matrix3d>& rotations);

/** The codes the receiver decodes: dequantised coefficients and means. */
PatchCodes dequantisedCodes(const PdcContent& c);

/** The quad mesh as triangles (fans from each face's first corner): where vertex places live. */
TriangleMesh fanTriangles(const QuadMesh& quads);

/** What both sides report of the content: counts of the quad mesh, patches and codes. */
void describeContent(const PdcContent& c, const PatchCodes& codes, PatchCodec::Report& report);

/** The unit-cube surface of a content — what the decoder outputs before the normalisation is
  * undone, and what the encoder checks its coverage against: the quad mesh's patches
  * reconstructed on the subdivided quad mesh (trimmed where no surface was seen) or on the kept
  * connectivity, then the coverage patches' pieces. Fills the report's counts and times; `what`
  * prefixes errors of corrupted content. */
TriangleMesh decodeSurface(const PdcContent& c, const PatchDictionary& dictionary, const std::string& what,
                           PatchCodec::Report& report);

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
