// `pcl_patchdict compress IN --dict DICT.pdd -o OUT.pdc` and `decompress IN.pdc --dict DICT.pdd -o OUT`:
// the .pdc codec (quad mesh + sparse codes), with the sizes of its parts and the PSNR of the round trip.
#include "cli.h"
#include "options.h"

#include <pcl_patchdict/core/atomic_file.h>
#include <pcl_patchdict_eval/mesh_render.h>
#include <pcl_patchdict_eval/repair_figure.h>
#include <pcl_patchdict/geometry/metrics.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/codec/patch_codec.h>
#include <pcl_patchdict/io/patch_codec_io.h>
#include <pcl_patchdict/io/patch_dictionary_io.h>

#include <cmath>
#include <cstdio>
#include <iostream>

namespace pcl {
namespace patchdict {
namespace cli {

namespace {

JsonObject partsJson(const PatchCodec::Report& r)
{
  JsonObject parts;
  parts.add("header", r.header_bytes).add("quad_vertices", r.quad_vertex_bytes).add("quad_faces", r.quad_face_bytes);
  parts.add("seed_offsets", r.offset_bytes);
  parts.add("atoms", r.atom_bytes).add("coefficients", r.coefficient_bytes).add("means", r.mean_bytes);
  parts.add("masks", r.mask_bytes).add("connectivity", r.connectivity_bytes).add("coverage_frames", r.coverage_bytes);
  return parts;
}

/** Distances in the reference's unit-cube units (as `eval` reports them) and PSNR. */
void addPsnr(JsonObject& json, const SurfaceDistance& d, const TriangleMesh& reference)
{
  const UnitCubeNormalization unit = UnitCubeNormalization::fromMesh(reference);
  json.add("units", "unit-cube").add("rms", unit.applyLength(d.rms)).add("hausdorff", unit.applyLength(d.hausdorff));
  if (std::isfinite(d.psnr))
    json.add("psnr", d.psnr);
  else
    json.addNull("psnr");
}

}  // namespace

int runCompress(const std::vector<std::string>& raw)
{
  const Arguments args = readCommandLine(raw, commandSpec("compress"));
  args.needs("location-bits", "keep-connectivity", "only the kept connectivity stores vertex places");
  if (args.has("no-eval"))
    args.refuse("samples", "counts the samples of the PSNR, which --no-eval turns off");
  const bool quiet = args.quiet();
  PatchCodecParameters parameters;
  parameters.quad_length = args.getDouble("quad-length");
  parameters.patch_scale = args.getDouble("patch-scale");
  parameters.overlap = static_cast<int>(args.getInt("overlap"));
  parameters.coefficients = static_cast<int>(args.getInt("sparsity"));
  parameters.coefficient_bits = static_cast<int>(args.getInt("coefficient-bits"));
  parameters.position_bits = static_cast<int>(args.getInt("position-bits"));
  parameters.subdivision = static_cast<int>(args.getInt("subdivision"));
  parameters.smoothing_iterations = static_cast<int>(args.getInt("smoothing-iterations"));
  parameters.keep_connectivity = args.has("keep-connectivity");
  parameters.location_bits = static_cast<int>(args.getInt("location-bits"));
  parameters.project_quads = !args.has("no-projection");
  parameters.coverage_tolerance = args.getDouble("coverage-tolerance");
  parameters.coverage_budget = args.getDouble("coverage-budget");
  parameters.target_error = args.getDouble("target-error");
  parameters.atom_cost = args.getDouble("atom-cost");
  parameters.seed = static_cast<std::uint64_t>(args.getInt("seed"));
  const auto samples = static_cast<std::size_t>(args.getInt("samples"));
  const std::string input = args.positionals()[0], output = args.get("output");
  checkOutputPath(output, input);
  if (sameFile(args.get("dict"), output))
    throw UsageError("--dict and -o name the same file");

  StageTimer timer(quiet);
  timer.start("load");
  const TriangleMesh mesh = loadMesh(input, quiet);
  const PatchDictionary::Ptr dictionary = loadPatchDictionary(args.get("dict"));
  PatchCodec codec;
  codec.setDictionary(dictionary);
  codec.setParameters(parameters);
  timer.start("encode");
  PatchCodec::Report report;
  const std::string bytes = codec.encode(mesh, &report);
  timer.start("save");
  writeFileAtomically(output, bytes);
  SurfaceDistance distance;
  const bool evaluate = !args.has("no-eval");
  if (evaluate) {
    timer.start("decode");
    TriangleMesh decoded;
    codec.decode(bytes, decoded);
    timer.start("eval");
    distance = surfaceDistance(mesh, decoded, samples, parameters.seed);
  }
  timer.stop();

  // The paper's count (Table 1) and bytes against float32 positions + int32 indices (12 V + 12 F).
  const double entity_factor = static_cast<double>(meshEntities(mesh)) / static_cast<double>(report.patchEntities());
  const double raw_bytes = 12.0 * static_cast<double>(mesh.vertices.size() + mesh.faces.size());
  const double byte_factor = raw_bytes / static_cast<double>(report.total_bytes);
  if (args.has("json")) {
    JsonObject json;
    json.add("command", "compress").add("input", input).add("output", output).add("dictionary", args.get("dict"));
    json.add("vertices", mesh.vertices.size()).add("faces", mesh.faces.size());
    json.add("quad_length", parameters.quad_length).add("patch_scale", parameters.patch_scale).add("grid_size", dictionary->gridSize());
    json.add("atoms", static_cast<long long>(dictionary->atoms().cols())).add("coefficients", parameters.coefficients);
    json.add("coefficient_bits", parameters.coefficient_bits).add("position_bits", parameters.position_bits);
    json.add("keep_connectivity", parameters.keep_connectivity);
    json.add("quad_vertices", report.quad_vertices).add("quad_faces", report.quad_faces);
    json.add("patches", report.patches).add("nonzeros", report.nonzeros).add("masked_patches", report.masked_patches);
    json.add("coverage_patches", report.coverage_patches).add("coverage_tolerance", parameters.coverage_tolerance);
    json.add("target_error", parameters.target_error).add("atom_cost", parameters.atom_cost);
    json.add("bytes", report.total_bytes).add("parts", partsJson(report));
    json.add("mesh_entities", meshEntities(mesh)).add("patch_entities", report.patchEntities());
    json.add("entity_factor", entity_factor).add("raw_bytes", raw_bytes).add("byte_factor", byte_factor);
    json.add("patch_rmse", report.patch_rmse);
    JsonObject stages;
    stages.add("layout", report.seconds_layout).add("patches", report.seconds_patches);
    stages.add("coding", report.seconds_coding).add("coverage", report.seconds_coverage);
    json.add("encode_stages", stages);
    if (evaluate)
      addPsnr(json, distance, mesh);
    json.add("seconds", timer.json());
    std::cout << json.str() << '\n';
  } else if (!args.has("quiet")) {
    std::printf("%zu bytes (%zu patches of which %zu coverage, %zu non-zeros, quad mesh %zu/%zu): %.1f x in bytes "
                "(12 V + 12 F), %.1f x in entities",
                report.total_bytes, report.patches, report.coverage_patches, report.nonzeros, report.quad_vertices,
                report.quad_faces, byte_factor, entity_factor);
    if (evaluate)
      std::printf(", PSNR %.2f dB", distance.psnr);
    std::printf(" -> %s\n", output.c_str());
  }
  return 0;
}

int runDecompress(const std::vector<std::string>& raw)
{
  const Arguments args = readCommandLine(raw, commandSpec("decompress"));
  args.needs("samples", "ref", "they sample the score against the reference");
  const bool quiet = args.quiet();
  const auto samples = static_cast<std::size_t>(args.getInt("samples"));
  const std::string input = args.positionals()[0], output = args.get("output");
  checkOutputPath(output, input);
  if (sameFile(args.get("dict"), output))
    throw UsageError("--dict and -o name the same file");
  if (args.has("ref") && sameFile(args.get("ref"), output))
    throw UsageError("--ref and -o name the same file");
  if (args.has("ref"))  // read after the output is written: a missing one fails before
    checkInputExists(args.get("ref"), "--ref");
  if (args.has("png")) {
    checkOutputPath(args.get("png"), input);
    if (sameFile(args.get("png"), output))
      throw UsageError("--png and -o name the same file");
  }

  StageTimer timer(quiet);
  timer.start("load");
  const PatchDictionary::Ptr dictionary = loadPatchDictionary(args.get("dict"));
  PatchCodec codec;
  codec.setDictionary(dictionary);
  timer.start("decode");
  TriangleMesh decoded;
  PatchCodec::Report report;
  loadCompressedMesh(input, codec, decoded, &report);
  timer.start("save");
  writeMesh(output, decoded);
  if (args.has("png")) {
    // The quad mesh's surface in grey, the coverage patches' pieces (the last faces) in orange.
    std::vector<std::array<std::uint8_t, 3>> colours;
    const std::size_t first_piece = decoded.faces.size() - report.coverage_faces;
    for (std::size_t f = 0; f < decoded.faces.size(); ++f)
      colours.push_back(f < first_piece ? std::array<std::uint8_t, 3>{200, 200, 200}
                                        : std::array<std::uint8_t, 3>{240, 140, 40});
    writePolygonsPNG(args.get("png"), decoded.vertices, polygonsOf(decoded), colours);
  }
  SurfaceDistance distance;
  TriangleMesh reference;
  if (args.has("ref")) {
    timer.start("eval");
    reference = loadMesh(args.get("ref"), true);
    distance = surfaceDistance(reference, decoded, samples, static_cast<std::uint64_t>(args.getInt("seed")));
  }
  timer.stop();
  if (args.has("json")) {
    JsonObject json;
    json.add("command", "decompress").add("input", input).add("output", output).add("dictionary", args.get("dict"));
    json.add("bytes", report.total_bytes).add("patches", report.patches).add("nonzeros", report.nonzeros);
    json.add("coverage_patches", report.coverage_patches).add("coverage_faces", report.coverage_faces);
    json.add("vertices", report.output_vertices).add("faces", report.output_faces);
    if (args.has("ref"))
      addPsnr(json, distance, reference);
    json.add("seconds", timer.json());
    std::cout << json.str() << '\n';
  } else if (!args.has("quiet")) {
    std::printf("%zu vertices, %zu faces from %zu patches", report.output_vertices, report.output_faces,
                report.patches);
    if (args.has("ref"))
      std::printf(", PSNR %.2f dB against %s", distance.psnr, args.get("ref").c_str());
    std::printf(" -> %s\n", output.c_str());
  }
  return 0;
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
