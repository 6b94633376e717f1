// PatchCodec: quad mesh + sparse codes (Sarkar et al. 2017, section 5.2), encoder and decoder.
#include <pcl_patchdict/codec/patch_codec.h>

#include <pcl_patchdict/geometry/coarse_mesh_estimation.h>
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/patches/height_maps.h>
#include <pcl_patchdict/geometry/metrics.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/quads/patch_layout.h>

#include <omp.h>

#include "codec/codec_coverage.h"
#include "codec/pdc_format.h"
#include "codec/pdc_surface.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

namespace pcl {
namespace patchdict {

namespace {

using detail::applySeedOffsets;
using detail::decodeSurface;
using detail::dequantisedCodes;
using detail::describeContent;
using detail::fanTriangles;
using detail::gridScale;
using detail::quantisePosition;
using detail::quadSeeds;
using detail::rebuildQuadMesh;
using detail::renumberByFirstUse;

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/** Masked OMP of one patch: at most `atoms` atoms, fewer once the observed bins' RMS error is
  * below target_error × L (0: always `atoms`). */
SparseCodingParameters codingParameters(const PatchCodecParameters& p, int atoms)
{
  SparseCodingParameters coding;
  coding.max_atoms = atoms;
  const double target = p.target_error * p.quad_length;
  coding.max_squared_error_per_entry = target * target;
  return coding;
}

/** Every patch coded with its first k atoms, k chosen per patch by one price per atom (a Lagrangian
  * allocation: Everett 1963; Shoham & Gersho 1988): k ≤ `coefficients` minimises E_k + λ k, with
  * E_k the summed squared error of the patch's observed bins coded with at most k atoms and
  * λ = atom_cost × L². The candidates are the codes of max_atoms = 1 … coefficients (and the mean
  * alone); OMP is greedy, so each is, up to rounding, the longer one's first atoms re-fitted. Each
  * patch keeps only its best candidate so far: no dense decode, no stored path. `caps` (empty:
  * `coefficients` for all) bounds each patch's k. */
PatchCodes allocatedCodes(const PatchDictionary& dictionary, const Eigen::MatrixXd& heights,
                          const ObservationMask& observed, const PatchCodecParameters& p, const std::vector<int>& caps = {})
{
  using Entry = std::pair<std::int64_t, double>;
  const double lambda = p.atom_cost * p.quad_length * p.quad_length;
  const Eigen::MatrixXd& atoms = dictionary.atoms();
  const Eigen::Index count = heights.cols(), bins = heights.rows();
  const auto cap = [&](Eigen::Index q) { return caps.empty() ? p.coefficients : caps[static_cast<std::size_t>(q)]; };
  const int largest = caps.empty() ? p.coefficients : *std::max_element(caps.begin(), caps.end());
  std::vector<double> best_cost(static_cast<std::size_t>(count), std::numeric_limits<double>::infinity());
  std::vector<std::vector<Entry>> best_code(static_cast<std::size_t>(count));
  PatchCodes codes;
  for (int k = 1; k <= largest; ++k) {
    const PatchCodes at_k = dictionary.encodeMasked(heights, observed, codingParameters(p, k));
    if (k == 1)
      codes.means = at_k.means;  // the same for every k
#pragma omp parallel for schedule(static) num_threads(p.num_threads > 0 ? p.num_threads : omp_get_max_threads())
    for (Eigen::Index q = 0; q < count; ++q) {
      if (k > cap(q))
        continue;
      Eigen::VectorXd residual = heights.col(q).array() - (codes.means.size() ? codes.means[q] : 0.0);
      const auto observedError = [&] {
        double error = 0.0;
        for (Eigen::Index r = 0; r < bins; ++r)
          if (observed(r, q))
            error += residual[r] * residual[r];
        return error;
      };
      const auto i = static_cast<std::size_t>(q);
      if (k == 1)
        best_cost[i] = observedError();  // the mean alone: k = 0
      std::vector<Entry> code;
      for (SparseCodes::InnerIterator it(at_k.coefficients, q); it; ++it) {
        residual -= it.value() * atoms.col(it.row());
        code.emplace_back(it.row(), it.value());
      }
      const double cost = observedError() + lambda * static_cast<double>(k);
      if (cost < best_cost[i]) {  // strictly: a tie keeps fewer atoms
        best_cost[i] = cost;
        best_code[i] = std::move(code);
      }
    }
  }
  codes.coefficients.resize(atoms.cols(), count);
  std::vector<Eigen::Triplet<double, std::int64_t>> entries;
  for (Eigen::Index q = 0; q < count; ++q)
    for (const auto& [atom, value] : best_code[static_cast<std::size_t>(q)])
      entries.emplace_back(atom, q, value);
  codes.coefficients.setFromTriplets(entries.begin(), entries.end());
  codes.coefficients.makeCompressed();
  return codes;
}

/** Per patch: the surface height at the grid's centre (mean of the four central bins that saw
  * the surface), in position-grid units — how far each seed moves along its Z onto the surface. */
std::vector<std::int64_t> seedOffsets(const PatchSet& sampled, int grid, double position_scale)
{
  std::vector<std::int64_t> offsets(sampled.numPatches());
  const int lo = (grid - 1) / 2, hi = grid / 2;
  for (std::size_t q = 0; q < offsets.size(); ++q) {
    double sum = 0.0;
    int count = 0;
    for (const int j : {lo, hi})
      for (const int i : {lo, hi})
        if (sampled.observed(j * grid + i, static_cast<Eigen::Index>(q))) {
          sum += sampled.heights(j * grid + i, static_cast<Eigen::Index>(q));
          ++count;
        }
    offsets[q] = count ? std::llround(sum / count * position_scale) : 0;
  }
  return offsets;
}

/** Appends the quantised codes of every patch of `codes` to the content (atoms in increasing
  * order, zero values dropped; values clamped to the 16 bits the byte planes hold). */
void appendQuantisedCodes(const PatchCodes& codes, detail::PdcContent& c)
{
  for (Eigen::Index q = 0; q < codes.coefficients.cols(); ++q) {
    std::vector<std::pair<std::uint32_t, std::int32_t>> entries;
    for (SparseCodes::InnerIterator it(codes.coefficients, q); it; ++it) {
      const auto value = static_cast<std::int32_t>(
          std::clamp<long>(std::lround(it.value() / c.coefficient_step), -32767L, 32767L));
      if (value != 0)
        entries.emplace_back(static_cast<std::uint32_t>(it.row()), value);
    }
    std::sort(entries.begin(), entries.end());
    c.atoms.emplace_back();
    c.values.emplace_back();
    for (const auto& [atom, value] : entries) {
      c.atoms.back().push_back(atom);
      c.values.back().push_back(value);
    }
    if (c.remove_mean)
      c.means.push_back(std::llround(codes.means[q] / c.mean_step));
  }
}

/** Encoder: coverage patches for the parts of the input that the content's decoded surface misses
  * by more than coverage_tolerance × L (see detail::chooseCoverageFrames); each codes only the
  * bins the surface lacks (detail::coverageBins), quantised with the quad patches' step. */
void addCoveragePatches(const TriangleMesh& surface, const PatchDictionary& dictionary,
                        const PatchCodecParameters& p, const HeightMapParameters& extraction, detail::PdcContent& c)
{
  // The receiver's surface, at the default subdivision at most: what is missing does not depend on
  // how finely the quads are split, and a file asking for 256 splits must not cost the encoder.
  detail::PdcContent quads_only = c;
  quads_only.subdivision = std::min<std::uint32_t>(c.subdivision, std::max<std::uint32_t>(1, c.grid_size / 2));
  PatchCodec::Report scratch;
  const TriangleMesh decoded = decodeSurface(quads_only, dictionary, "codec: decoding its own output: ", scratch);
  const double tolerance = p.coverage_tolerance * p.quad_length;
  const auto max_patches = static_cast<std::size_t>(p.coverage_budget * static_cast<double>(c.atoms.size()));
  // One distance tree of the decoded surface, for the input's vertices and the patches' bins.
  const PointToMeshDistance to_decoded(decoded);
  const std::vector<detail::CoverageFrame> frames =
      detail::chooseCoverageFrames(surface, to_decoded, c.radius, tolerance, c.position_bits, max_patches);
  if (frames.empty())
    return;
  const int grid = static_cast<int>(c.grid_size);
  const std::size_t bins = static_cast<std::size_t>(grid) * static_cast<std::size_t>(grid);
  std::vector<Eigen::Vector3d> seeds(frames.size());
  std::vector<Eigen::Matrix3d> rotations(frames.size());  // rounded by coverageSeedAndRotation
  for (std::size_t q = 0; q < frames.size(); ++q)
    detail::coverageSeedAndRotation(frames[q], c.position_bits, seeds[q], rotations[q]);
  PatchSet sampled;
  extractMeshHeightMaps(surface, seeds, rotations, extraction, sampled);
  const std::vector<std::int64_t> offsets = seedOffsets(sampled, grid, gridScale(c.position_bits));
  applySeedOffsets(offsets, c.position_bits, seeds, rotations);
  extractMeshHeightMaps(surface, seeds, rotations, extraction, sampled);

  std::vector<std::size_t> useful;
  std::vector<std::vector<char>> kept_bins;
  for (std::size_t q = 0; q < frames.size(); ++q) {
    const auto column = static_cast<Eigen::Index>(q);
    const Eigen::VectorXd heights = sampled.heights.col(column);
    std::vector<char> observed(bins);
    for (std::size_t b = 0; b < bins; ++b)
      observed[b] = sampled.observed(static_cast<Eigen::Index>(b), column) ? 1 : 0;
    const std::vector<double> distances =
        to_decoded.distances(detail::binPoints(seeds[q], rotations[q], sampled.side(), grid, heights));
    std::vector<char> kept = detail::coverageBins(observed, distances, tolerance, grid);
    if (detail::completeCells(kept, grid) > 0) {  // a piece with some surface
      useful.push_back(q);
      kept_bins.push_back(std::move(kept));
    }
  }
  if (useful.empty())
    return;
  const auto count = static_cast<Eigen::Index>(useful.size());
  Eigen::MatrixXd heights(static_cast<Eigen::Index>(bins), count);
  ObservationMask mask(static_cast<Eigen::Index>(bins), count);
  for (Eigen::Index k = 0; k < count; ++k) {
    heights.col(k) = sampled.heights.col(static_cast<Eigen::Index>(useful[static_cast<std::size_t>(k)]));
    for (std::size_t b = 0; b < bins; ++b)
      mask(static_cast<Eigen::Index>(b), k) = kept_bins[static_cast<std::size_t>(k)][b] != 0;
  }
  const auto quad_patches = static_cast<Eigen::Index>(c.atoms.size());
  // A piece of a few bins needs fewer atoms than a whole patch (and more atoms than a quarter of
  // its bins would only fit their noise): the codes' budget follows the bins kept. With a price per
  // atom, that budget is each piece's cap and the price chooses below it, as for the quad patches.
  std::vector<int> caps(static_cast<std::size_t>(count));
  for (Eigen::Index k = 0; k < count; ++k)
    caps[static_cast<std::size_t>(k)] = std::clamp(static_cast<int>(mask.col(k).count()) / 4, 1, p.coefficients);
  if (p.atom_cost > 0.0)
    appendQuantisedCodes(allocatedCodes(dictionary, heights, mask, p, caps), c);
  else
    for (Eigen::Index k = 0; k < count; ++k)
      appendQuantisedCodes(
          dictionary.encodeMasked(heights.col(k), mask.col(k), codingParameters(p, caps[static_cast<std::size_t>(k)])), c);
  if (c.observed.size() == 0)
    c.observed = ObservationMask::Constant(static_cast<Eigen::Index>(bins), quad_patches, true);
  c.observed.conservativeResize(Eigen::NoChange, quad_patches + count);
  c.observed.rightCols(count) = mask;
  for (const std::size_t q : useful) {
    c.offsets.push_back(offsets[q]);
    c.coverage.push_back(frames[q]);
  }
}

/** Refuses parameters the format or the dictionary cannot hold. */
void checkParameters(const PatchCodecParameters& p, int grid, int atoms)
{
  if (!(p.quad_length >= 1e-3 && p.quad_length <= 1.0))
    throw Error("codec: the quad length must be in [0.001, 1] (unit-cube units)");
  if (!(p.patch_scale >= 0.5 && p.patch_scale <= 4.0))
    throw Error("codec: the patch scale (patch side / quad length) must be in [0.5, 4]");
  if (p.overlap < 0 || p.overlap > 16)
    throw Error("codec: the overlap must be in [0, 16]");
  if (p.coefficients < 1 || p.coefficients > atoms)
    throw Error("codec: coefficients per patch must be in [1, " + std::to_string(atoms) + "] (the dictionary's atoms)");
  if (p.coefficient_bits < 2 || p.coefficient_bits > 16)
    throw Error("codec: coefficient bits must be in [2, 16]");
  if (p.position_bits < 4 || p.position_bits > 24)
    throw Error("codec: position bits must be in [4, 24]");
  // More splits per quad side than a patch has bins only interpolates between them, and lets a
  // tiny file ask for millions of vertices (fuzzing: 890 bytes, 255 splits -> 2M vertices, 13 s).
  if (p.subdivision < 0 || p.subdivision > grid)
    throw Error("codec: subdivision must be in [0, " + std::to_string(grid) +
                "] (at most the dictionary's grid size; 0: grid size / 2)");
  if (p.keep_connectivity && (p.location_bits < 4 || p.location_bits > 16))
    throw Error("codec: location bits must be in [4, 16]");
  if (!(p.target_error >= 0.0 && p.target_error <= 1.0))
    throw Error("codec: the target error must be in [0, 1] (quad lengths; 0: always the full coefficients)");
  if (!(p.atom_cost >= 0.0 && p.atom_cost <= 10.0))
    throw Error("codec: the atom cost must be in [0, 10] (squared quad lengths per atom; 0: off)");
  if (!(p.coverage_tolerance >= 0.0 && p.coverage_tolerance <= 10.0))
    throw Error("codec: the coverage tolerance must be in [0, 10] (quad lengths; 0: no coverage patches)");
  if (!(p.coverage_budget >= 0.0 && p.coverage_budget <= 10.0))
    throw Error("codec: the coverage budget must be in [0, 10] (coverage patches per quad patch)");
}

/** The quad layout of the smoothed surface, its vertices numbered by first use (and projected
  * onto the surface when asked). */
QuadMesh codecQuadMesh(const TriangleMesh& surface, const PatchCodecParameters& p)
{
  // The layout's coarse shape and quads (the seeds come later, from the quads as the decoder rebuilds them).
  PatchLayoutParameters layout_parameters;
  layout_parameters.quad_length = p.quad_length;
  layout_parameters.smoothing_iterations = p.smoothing_iterations;
  layout_parameters.smoothing = CoarseMeshEstimation::Method::Laplacian;
  layout_parameters.seed = p.seed;
  layout_parameters.num_threads = p.num_threads;
  PatchLayout layout;
  try {
    computeLayoutQuads(surface, layout_parameters, layout);
  } catch (const Error& e) {
    throw Error(std::string("codec: ") + e.what());
  }
  QuadMesh quads = std::move(layout.quads);
  renumberByFirstUse(quads.faces, quads.vertices);
  quads.normals.clear();
  if (p.project_quads) {
    const PointToMeshDistance to_surface(surface);
    for (auto& v : quads.vertices)
      v = to_surface.query(v).closest_point;
  }
  return quads;
}

/** The file's header fields and its quantised quad mesh. */
detail::PdcContent headerContent(const PatchDictionary& dictionary, const PatchCodecParameters& p,
                                 const UnitCubeNormalization& normalization, const QuadMesh& quads)
{
  const int grid = dictionary.gridSize();
  detail::PdcContent c;
  c.fingerprint = dictionary.fingerprint();
  c.grid_size = static_cast<std::uint32_t>(grid);
  c.num_atoms = static_cast<std::uint32_t>(dictionary.atoms().cols());
  c.remove_mean = dictionary.getRemoveMean();
  c.keep_connectivity = p.keep_connectivity;
  c.quad_length = p.quad_length;
  c.radius = p.patch_scale * p.quad_length / std::sqrt(2.0);
  c.normalization = normalization;
  c.overlap = static_cast<std::uint32_t>(p.overlap);
  c.coefficients = static_cast<std::uint32_t>(p.coefficients);
  c.coefficient_bits = static_cast<std::uint32_t>(p.coefficient_bits);
  c.position_bits = static_cast<std::uint32_t>(p.position_bits);
  c.subdivision = static_cast<std::uint32_t>(p.subdivision > 0 ? p.subdivision : std::max(1, grid / 2));
  c.location_bits = p.keep_connectivity ? static_cast<std::uint32_t>(p.location_bits) : 0;
  for (const auto& v : quads.vertices)
    c.quad_positions.push_back(quantisePosition(v, c.position_bits));
  c.quad_faces = quads.faces;
  return c;
}

/** Quantises the codes into `c`. The quantiser's range is the 99th percentile of |coefficient|,
  * not the largest: one patch over a sharp crease must not coarsen every other patch's step. Larger
  * values still fit (the byte planes hold 16 bits), at a step no finer than the largest value
  * allows. */
void quantiseCodes(const PatchCodes& codes, int coefficient_bits, int grid, detail::PdcContent& c)
{
  std::vector<double> magnitudes;
  for (Eigen::Index k = 0; k < codes.coefficients.outerSize(); ++k)
    for (SparseCodes::InnerIterator it(codes.coefficients, k); it; ++it)
      magnitudes.push_back(std::abs(it.value()));
  double range = 0.0, largest = 0.0;
  if (!magnitudes.empty()) {
    largest = *std::max_element(magnitudes.begin(), magnitudes.end());
    const auto at = magnitudes.begin() + static_cast<std::ptrdiff_t>(0.99 * static_cast<double>(magnitudes.size() - 1));
    std::nth_element(magnitudes.begin(), at, magnitudes.end());
    range = *at;
  }
  const double levels = std::ldexp(1.0, coefficient_bits - 1) - 1.0;
  c.coefficient_step = range > 0 ? std::max(range / levels, largest / 32767.0) : 1.0;
  c.mean_step = c.coefficient_step / grid;  // a mean offset over N² bins weighs N × its value
  appendQuantisedCodes(codes, c);
}

/** Kept connectivity: each surface vertex's place on the fanned quad mesh, as a triangle and
  * quantised barycentrics. */
void placeVertices(const TriangleMesh& surface, const QuadMesh& quads, detail::PdcContent& c)
{
  const TriangleMesh fan = fanTriangles(quads);
  const PointToMeshDistance to_quads(fan);
  const double location_scale = gridScale(c.location_bits);
  c.faces = surface.faces;
  c.places.resize(surface.vertices.size());
#pragma omp parallel for schedule(dynamic, 256)
  for (std::ptrdiff_t v = 0; v < static_cast<std::ptrdiff_t>(surface.vertices.size()); ++v) {
    const auto hit = to_quads.query(surface.vertices[static_cast<std::size_t>(v)]);
    const Face& f = fan.faces[static_cast<std::size_t>(hit.face)];
    const Eigen::Vector3d a = fan.vertices[static_cast<std::size_t>(f[0])];
    const Eigen::Vector3d e1 = fan.vertices[static_cast<std::size_t>(f[1])] - a;
    const Eigen::Vector3d e2 = fan.vertices[static_cast<std::size_t>(f[2])] - a;
    // Barycentrics of the closest point (least squares: robust for thin triangles).
    Eigen::Matrix<double, 3, 2> basis;
    basis << e1, e2;
    Eigen::Vector2d w = basis.colPivHouseholderQr().solve(hit.closest_point - a);
    w = w.cwiseMax(0.0);
    if (w.sum() > 1.0)
      w /= w.sum();
    detail::VertexPlace& place = c.places[static_cast<std::size_t>(v)];
    place.triangle = hit.face;
    place.u = static_cast<std::uint32_t>(std::lround(w[0] * location_scale));
    place.v = static_cast<std::uint32_t>(std::lround(w[1] * location_scale));
    if (place.u + place.v > location_scale)
      place.v = static_cast<std::uint32_t>(location_scale) - place.u;
  }
}

/** The report's byte counts, from the writer's. */
void reportSizes(const detail::PdcSizes& sizes, PatchCodec::Report& local)
{
  local.header_bytes = sizes.header + 8;  // + checksum
  local.quad_vertex_bytes = sizes.quad_vertices;
  local.quad_face_bytes = sizes.quad_faces;
  local.offset_bytes = sizes.offsets;
  local.atom_bytes = sizes.atoms;
  local.coefficient_bytes = sizes.coefficients;
  local.mean_bytes = sizes.means;
  local.mask_bytes = sizes.masks;
  local.connectivity_bytes = sizes.connectivity;
  local.coverage_bytes = sizes.coverage;
  local.total_bytes = sizes.total;
}

}  // namespace

std::size_t PatchCodec::Report::patchEntities() const
{
  return nonzeros + quad_vertices + 4 * quad_faces + 2 * coverage_patches;
}

std::size_t meshEntities(const TriangleMesh& mesh) { return 3 * mesh.faces.size() + mesh.vertices.size(); }

void PatchCodec::requireDictionary() const
{
  if (!dictionary_ || dictionary_->empty())
    throw Error("the codec needs a patch dictionary (the one the receiver holds)");
}

std::string PatchCodec::encode(const TriangleMesh& mesh, Report* report) const
{
  requireDictionary();
  const PatchCodecParameters& p = parameters_;
  const int grid = dictionary_->gridSize();
  const int atoms = static_cast<int>(dictionary_->atoms().cols());
  checkParameters(p, grid, atoms);
  if (mesh.faces.empty())
    throw Error("codec: the input has no faces (compression works on meshes)");
  Report local;
  auto t = Clock::now();

  TriangleMesh surface = mesh;
  const UnitCubeNormalization normalization = UnitCubeNormalization::fromMesh(surface);
  normalization.apply(surface);
  QuadMesh quads = codecQuadMesh(surface, p);
  detail::PdcContent c = headerContent(*dictionary_, p, normalization, quads);
  const double position_scale = gridScale(c.position_bits);
  // From here on, the encoder sees exactly what the decoder will.
  quads = rebuildQuadMesh(c);
  PatchSet patches;
  patches.grid_size = grid;
  patches.radius = c.radius;
  quadSeeds(quads, c.overlap, patches.seeds, patches.rotations);
  if (patches.seeds.empty())
    throw Error("codec: the quad mesh has no usable face");
  local.seconds_layout = since(t);

  t = Clock::now();
  HeightMapParameters heights;
  heights.radius = c.radius;
  heights.grid_size = grid;
  heights.num_threads = p.num_threads;
  PatchSet sampled;
  // A quad's centre lies off a curved surface (by its sagitta); patches learned around surface
  // points code best around surface points: each seed moves along Z to the surface height at the
  // grid's centre (one small integer per patch), then the patches are sampled there.
  extractMeshHeightMaps(surface, patches.seeds, patches.rotations, heights, sampled);
  c.offsets = seedOffsets(sampled, grid, position_scale);
  applySeedOffsets(c.offsets, c.position_bits, patches.seeds, patches.rotations);
  extractMeshHeightMaps(surface, patches.seeds, patches.rotations, heights, sampled);
  local.seconds_patches = since(t);

  t = Clock::now();
  const PatchCodes codes = p.atom_cost > 0.0 ? allocatedCodes(*dictionary_, sampled.heights, sampled.observed, p)
                                             : dictionary_->encodeMasked(sampled.heights, sampled.observed,
                                                                         codingParameters(p, p.coefficients));
  quantiseCodes(codes, p.coefficient_bits, grid, c);
  if (!sampled.observed.all())
    c.observed = sampled.observed;
  local.seconds_coding = since(t);
  if (!p.keep_connectivity && p.coverage_tolerance > 0.0) {
    t = Clock::now();
    addCoveragePatches(surface, *dictionary_, p, heights, c);
    local.seconds_coverage = since(t);
  }
  t = Clock::now();
  if (p.keep_connectivity)
    placeVertices(surface, quads, c);

  detail::PdcSizes sizes;
  std::string bytes = detail::writePdc(c, &sizes);
  local.seconds_coding += since(t);
  if (report) {
    // The error the receiver will see in the patches: quantised codes against the sampled heights.
    const PatchCodes quantised = dequantisedCodes(c);
    const auto quad_patches = static_cast<Eigen::Index>(sampled.numPatches());
    local.patch_rmse = observedRMSE(dictionary_->decode(quantised).leftCols(quad_patches), sampled.heights,
                                    sampled.observed);
    reportSizes(sizes, local);
    describeContent(c, quantised, local);
    *report = local;
  }
  return bytes;
}

void PatchCodec::decode(const std::string& bytes, TriangleMesh& out, Report* report, const std::string& what) const
{
  requireDictionary();
  const detail::PdcContent c = detail::readPdc(bytes, what);
  if (c.fingerprint != dictionary_->fingerprint() || static_cast<int>(c.grid_size) != dictionary_->gridSize() ||
      static_cast<Eigen::Index>(c.num_atoms) != dictionary_->atoms().cols()) {
    std::ostringstream message;
    message << what << "encoded with another dictionary (" << c.num_atoms << " atoms of " << c.grid_size << "×"
            << c.grid_size << ", fingerprint " << std::hex << c.fingerprint << "; given: "
            << std::dec << dictionary_->atoms().cols() << " atoms of " << dictionary_->gridSize() << "×"
            << dictionary_->gridSize() << ", fingerprint " << std::hex << dictionary_->fingerprint() << ")";
    throw Error(message.str());
  }
  Report local;
  TriangleMesh decoded = decodeSurface(c, *dictionary_, what, local);
  const auto t = Clock::now();
  c.normalization.invert(decoded);
  // Every stored number was range-checked, but extreme yet finite values (a scale of 1e-300, a huge
  // coefficient step) can still overflow on the way: a decoded surface must be finite.
  for (const auto& v : decoded.vertices)
    if (!v.allFinite())
      throw Error(what + "the decoded surface is not finite (the file is corrupted)");
  out = std::move(decoded);
  local.seconds_reconstruct += since(t);
  if (report) {
    local.total_bytes = bytes.size();
    local.output_vertices = out.vertices.size();
    local.output_faces = out.faces.size();
    *report = local;
  }
}

}  // namespace patchdict
}  // namespace pcl
