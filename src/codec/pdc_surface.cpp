// The surface a .pdc content stands for (see pdc_surface.h): shared by PatchCodec's decoder and
// its encoder's coverage check.
#include "codec/pdc_surface.h"

#include "codec/codec_coverage.h"

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/patches/patch_mesh_reconstruction.h>
#include <pcl_patchdict/quads/quad_frames.h>
#include <pcl_patchdict/quads/quad_subdivision.h>

#include <chrono>

namespace pcl {
namespace patchdict {
namespace detail {

namespace {

/** Largest decoded mesh accepted (vertices before trimming). */
constexpr long long kMaxDecodedVertices = 1LL << 25;

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/** Drops the faces that reach an unseen vertex (PatchMeshReconstruction::Report::off_surface: the
  * stored masks say no surface was seen there — a quad spanning an open boundary or a hole of the
  * input), then the vertices no face uses. */
void trimUnseen(const std::vector<char>& unseen, TriangleMesh& mesh)
{
  std::vector<Face> kept;
  kept.reserve(mesh.faces.size());
  for (const Face& f : mesh.faces)
    if (!unseen[static_cast<std::size_t>(f[0])] && !unseen[static_cast<std::size_t>(f[1])] &&
        !unseen[static_cast<std::size_t>(f[2])])
      kept.push_back(f);
  mesh.faces = std::move(kept);
  renumberByFirstUse(mesh.faces, mesh.vertices);
}

std::size_t maskedPatches(const ObservationMask& observed)
{
  std::size_t count = 0;
  for (Eigen::Index p = 0; p < observed.cols(); ++p)
    count += observed.col(p).all() ? 0 : 1;
  return count;
}

}  // namespace

/** The quad mesh both sides work with: dequantised positions (unit cube), the stored faces, and
  * vertex normals from the faces' Newell vectors (area-weighted), so the frames' Z follows the
  * faces' winding without normals being stored. */
QuadMesh rebuildQuadMesh(const PdcContent& c)
{
  QuadMesh quads;
  const double scale = gridScale(c.position_bits);
  quads.vertices.reserve(c.quad_positions.size());
  for (const auto& q : c.quad_positions)
    quads.vertices.emplace_back(q[0] / scale - 0.5, q[1] / scale - 0.5, q[2] / scale - 0.5);
  quads.faces = c.quad_faces;
  std::vector<Eigen::Vector3d> sum(quads.vertices.size(), Eigen::Vector3d::Zero());
  for (const auto& face : quads.faces) {
    Eigen::Vector3d newell = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < face.size(); ++k) {
      const Eigen::Vector3d& a = quads.vertices[static_cast<std::size_t>(face[k])];
      const Eigen::Vector3d& b = quads.vertices[static_cast<std::size_t>(face[(k + 1) % face.size()])];
      newell += a.cross(b);
    }
    for (const std::int32_t v : face)
      sum[static_cast<std::size_t>(v)] += newell;
  }
  quads.normals.resize(sum.size());
  for (std::size_t v = 0; v < sum.size(); ++v) {
    const double norm = sum[v].norm();
    quads.normals[v] = norm > 0 ? Eigen::Vector3d(sum[v] / norm) : Eigen::Vector3d::UnitZ();
  }
  return quads;
}

/** Seeds and frames of the patches: computeQuadFrames on the rebuilt quad mesh, its frames
  * rounded to single precision as the encoder's were (what version-3 files were written with). */
void quadSeeds(const QuadMesh& quads, std::uint32_t overlap, std::vector<Eigen::Vector3d>& seeds,
               std::vector<Eigen::Matrix3d>& rotations)
{
  computeQuadFrames(quads, static_cast<int>(overlap), seeds, rotations);
}

/** Seeds moved along their frames' Z by the stored offsets (position-grid units). */
void applySeedOffsets(const std::vector<std::int64_t>& offsets, std::uint32_t position_bits,
                      std::vector<Eigen::Vector3d>& seeds, const std::vector<Eigen::Matrix3d>& rotations)
{
  const double scale = gridScale(position_bits);
  for (std::size_t q = 0; q < seeds.size(); ++q)
    seeds[q] += rotations[q].row(2).transpose() * (static_cast<double>(offsets[q]) / scale);
}

/** The codes the receiver decodes: dequantised coefficients and means. */
PatchCodes dequantisedCodes(const PdcContent& c)
{
  const std::size_t num_patches = c.atoms.size();
  PatchCodes codes;
  codes.coefficients.resize(static_cast<Eigen::Index>(c.num_atoms), static_cast<Eigen::Index>(num_patches));
  std::vector<Eigen::Triplet<double, std::int64_t>> entries;
  for (std::size_t q = 0; q < num_patches; ++q)
    for (std::size_t i = 0; i < c.atoms[q].size(); ++i)
      entries.emplace_back(c.atoms[q][i], static_cast<std::int64_t>(q), c.values[q][i] * c.coefficient_step);
  codes.coefficients.setFromTriplets(entries.begin(), entries.end());
  codes.means = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(num_patches));
  for (std::size_t q = 0; q < c.means.size(); ++q)
    codes.means[static_cast<Eigen::Index>(q)] = static_cast<double>(c.means[q]) * c.mean_step;
  return codes;
}

/** The quad mesh as triangles (fans from each face's first corner): where vertex places live. */
TriangleMesh fanTriangles(const QuadMesh& quads)
{
  TriangleMesh mesh;
  mesh.vertices = quads.vertices;
  for (const auto& face : quads.faces)
    for (std::size_t k = 1; k + 1 < face.size(); ++k)
      mesh.faces.push_back({face[0], face[k], face[k + 1]});
  return mesh;
}

/** What both sides report of the content: counts of the quad mesh, patches and codes. */
void describeContent(const PdcContent& c, const PatchCodes& codes, PatchCodec::Report& report)
{
  report.quad_vertices = c.quad_positions.size();
  report.quad_faces = c.quad_faces.size();
  report.patches = c.atoms.size();
  report.nonzeros = static_cast<std::size_t>(codes.coefficients.nonZeros());
  report.masked_patches = maskedPatches(c.observed);
  report.coverage_patches = c.coverage.size();
  report.coefficient_step = c.coefficient_step;
}

namespace {

/** The mesh the patches are reconstructed on: the kept connectivity, its vertices placed on the
  * fanned quad mesh, or the subdivided quad mesh. */
TriangleMesh targetMesh(const PdcContent& c, const QuadMesh& quads, const std::string& what)
{
  TriangleMesh target;
  if (c.keep_connectivity) {
    const TriangleMesh fan = fanTriangles(quads);
    const double location_scale = gridScale(c.location_bits);
    target.vertices.reserve(c.places.size());
    for (const VertexPlace& place : c.places) {
      if (place.triangle >= static_cast<std::int32_t>(fan.faces.size()))
        throw Error(what + "a vertex place refers to a missing quad triangle (the file is corrupted)");
      const Face& f = fan.faces[static_cast<std::size_t>(place.triangle)];
      const Eigen::Vector3d a = fan.vertices[static_cast<std::size_t>(f[0])];
      target.vertices.push_back(a + (fan.vertices[static_cast<std::size_t>(f[1])] - a) * (place.u / location_scale) +
                                (fan.vertices[static_cast<std::size_t>(f[2])] - a) * (place.v / location_scale));
    }
    target.faces = c.faces;
  } else {
    target = subdivideQuadMesh(quads, static_cast<int>(c.subdivision));
  }
  return target;
}

/** Appends the pieces of the coverage patches (those after the first `num_quad_patches`). */
void appendCoveragePieces(const PatchSet& patches, std::size_t num_quad_patches, TriangleMesh& decoded)
{
  const int grid = patches.grid_size;
  const std::size_t bins = static_cast<std::size_t>(grid) * static_cast<std::size_t>(grid);
  for (std::size_t q = num_quad_patches; q < patches.seeds.size(); ++q) {
    const auto column = static_cast<Eigen::Index>(q);
    std::vector<char> kept(bins);
    for (std::size_t b = 0; b < bins; ++b)
      kept[b] = patches.observed(static_cast<Eigen::Index>(b), column) ? 1 : 0;
    const Eigen::VectorXd heights = patches.heights.col(column);
    appendCoveragePiece(patches.seeds[q], patches.rotations[q], patches.side(), grid, heights, kept, decoded);
  }
}
}  // namespace

/** The unit-cube surface a .pdc content stands for — what the decoder outputs before the
  * normalisation is undone, and what the encoder checks its coverage against: the quad mesh's
  * patches reconstructed on the subdivided quad mesh (trimmed where no surface was seen) or on the
  * kept connectivity, then the coverage patches' pieces. Fills the report's counts and times. */
TriangleMesh decodeSurface(const PdcContent& c, const PatchDictionary& dictionary, const std::string& what,
                           PatchCodec::Report& report)
{
  auto t = Clock::now();
  const QuadMesh quads = rebuildQuadMesh(c);
  PatchSet patches;
  patches.grid_size = static_cast<int>(c.grid_size);
  patches.radius = c.radius;
  quadSeeds(quads, c.overlap, patches.seeds, patches.rotations);
  const std::size_t num_patches = c.atoms.size(), num_quad_patches = num_patches - c.coverage.size();
  if (patches.seeds.size() != num_quad_patches)
    throw Error(what + "the quad mesh gives " + std::to_string(patches.seeds.size()) + " patches, the file codes " +
                std::to_string(num_quad_patches) + " (the file is corrupted)");
  // The decoded mesh's size, before anything is allocated for it: the subdivided quad mesh and
  // every coverage patch's grid, with at most 10 coverage patches per quad patch (the encoder's
  // largest budget) — a few hundred bytes must not ask for gigabytes.
  if (c.coverage.size() > 10 * num_quad_patches)
    throw Error(what + "more coverage patches than an encoder makes (the file is corrupted)");
  const double grid_bins = static_cast<double>(c.grid_size) * static_cast<double>(c.grid_size);
  const double output_vertices =
      (c.keep_connectivity ? static_cast<double>(c.places.size())
                           : static_cast<double>(quads.faces.size()) * (c.subdivision + 1.0) * (c.subdivision + 1.0)) +
      static_cast<double>(c.coverage.size()) * grid_bins;
  if (output_vertices > kMaxDecodedVertices)
    throw Error(what + "the decoded mesh would have about " + std::to_string(static_cast<long long>(output_vertices)) +
                " vertices, more than this decoder accepts (" + std::to_string(kMaxDecodedVertices) + ")");
  for (const CoverageFrame& frame : c.coverage) {
    patches.seeds.emplace_back();
    patches.rotations.emplace_back();
    coverageSeedAndRotation(frame, c.position_bits, patches.seeds.back(), patches.rotations.back());
  }
  applySeedOffsets(c.offsets, c.position_bits, patches.seeds, patches.rotations);
  report.seconds_layout = since(t);

  t = Clock::now();
  const PatchCodes codes = dequantisedCodes(c);
  patches.heights = dictionary.decode(codes);
  patches.observed = c.observed.size() ? c.observed
                                       : ObservationMask::Constant(patches.heights.rows(), patches.heights.cols(), true);
  patches.source.assign(num_patches, 0);
  report.seconds_coding = since(t);

  t = Clock::now();
  const TriangleMesh target = targetMesh(c, quads, what);
  // The quad mesh's surface comes from its own patches; coverage patches only add their pieces.
  PatchSet quad_patches;
  const PatchSet* reconstruct_from = &patches;
  if (!c.coverage.empty()) {
    const auto n = static_cast<Eigen::Index>(num_quad_patches);
    quad_patches.grid_size = patches.grid_size;
    quad_patches.radius = patches.radius;
    quad_patches.seeds.assign(patches.seeds.begin(), patches.seeds.begin() + n);
    quad_patches.rotations.assign(patches.rotations.begin(), patches.rotations.begin() + n);
    quad_patches.heights = patches.heights.leftCols(n);
    quad_patches.observed = patches.observed.leftCols(n);
    quad_patches.source.assign(num_quad_patches, 0);
    reconstruct_from = &quad_patches;
  }
  PatchMeshReconstruction reconstruction;
  reconstruction.setPatches(std::make_shared<const PatchSet>(*reconstruct_from));
  reconstruction.setTargetMesh(std::make_shared<const TriangleMesh>(target));
  PatchMeshReconstruction::Report reconstruction_report;
  TriangleMesh decoded;
  reconstruction.compute(decoded, &reconstruction_report);
  decoded.normals.clear();
  if (!c.keep_connectivity)
    trimUnseen(reconstruction_report.off_surface, decoded);
  const std::size_t quad_surface_faces = decoded.faces.size();
  appendCoveragePieces(patches, num_quad_patches, decoded);
  if (decoded.faces.empty())
    throw Error(what + "the decoded surface is empty (the file is corrupted)");
  report.seconds_reconstruct = since(t);
  describeContent(c, codes, report);
  report.coverage_faces = decoded.faces.size() - quad_surface_faces;
  return decoded;
}

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
