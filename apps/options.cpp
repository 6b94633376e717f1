// The command-line table (see options.h) and the help texts made from it.
#include "options.h"

#include <algorithm>
#include <sstream>
#include <stdexcept>

namespace pcl {
namespace patchdict {
namespace cli {

namespace {

OptionSpec flag(const std::string& name, const std::string& help)
{
  return OptionSpec{name, "", "", help};
}

OptionSpec value(const std::string& name, const std::string& argument, const std::string& fallback,
                 const std::string& help)
{
  return OptionSpec{name, argument, fallback, help};
}

OptionSpec required(const std::string& name, const std::string& argument, const std::string& help)
{
  OptionSpec option{name, argument, "", help};
  option.required = true;
  return option;
}

OptionSpec hidden(const std::string& name, const std::string& argument)
{
  OptionSpec option{name, argument, "", ""};
  option.hidden = true;
  return option;
}

std::vector<OptionSpec> operator+(std::vector<OptionSpec> a, const std::vector<OptionSpec>& b)
{
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

/** What the patch stage of a mesh repair reads (repair_options.cpp); defaults by mode. */
struct PatchDefaults {
  const char* quad_factor;
  const char* sparsity;
  const char* mu;  ///< nullptr: the mode has no --mu
  const char* fit_scale;
};

std::vector<OptionSpec> patchStageOptions(const PatchDefaults& d)
{
  std::vector<OptionSpec> options{
      value("quad-length", "L", "0 (automatic)", "quad length in unit-cube units; 0: --quad-factor × the mean edge"),
      value("quad-factor", "C", d.quad_factor, "automatic quad length, in mean edge lengths"),
      value("sparsity", "S", d.sparsity, "atoms per sparse code at most")};
  if (d.mu)
    options.push_back(value("mu", "M", d.mu, "weight of the patch constraints in the solve"));
  return options + std::vector<OptionSpec>{
      value("overlap", "K", "1", "4K extra seeds per quad"),
      value("atoms", "K", "100", "atoms of the self-similar dictionary (not with --dict)"),
      value("grid", "N", "the dictionary's (16 self-similar)", "bins per patch side, 2-256; with --dict it must match"),
      value("patch-scale", "F", "1", "patch side, × the quad length"),
      value("centre-sigma", "S", "0.5", "constraint weight's Gaussian fall-off from the patch centre, × half the side"),
      value("observed-power", "P", "1", "constraint weight ∝ (observed fraction of the patch)^P"),
      value("fit-scale", "F", d.fit_scale, "constraint weight's tolerance of a poor sparse fit, × the mean edge"),
      value("agreement-scale", "A", "0.1", "constraint weight's tolerance of disagreeing patches, × the mean edge"),
      value("min-observed", "F", "0.2", "patches less observed than this fraction give no constraint"),
      value("smoothing-iterations", "N", "30", "smoothing iterations of the coarse shape the quads are laid on")};
}

std::vector<OptionSpec> reportOptions()
{
  return {value("report", "DIR", "", "write before/after pictures (and, with --ref, the error colouring) to DIR"),
          value("ref", "REF", "", "the true surface, for the report's error colouring (needs --report)"),
          value("error-scale", "E", "99th percentile", "distance coloured red in the report (needs --ref)")};
}

std::vector<OptionSpec> cloudDenoisingOptions()
{
  return {value("noise", "S", "estimated", "noise σ, in units of the largest bounding-box side"),
          value("bandwidth", "H", "by risk", "patch bandwidth, in units of the largest bounding-box side"),
          flag("absolute", "lengths in the cloud's own units, not the largest side's"),
          flag("no-outlier-filter", "no statistical outlier pre-filter"),
          value("outlier-neighbours", "K", "50", "neighbours of the outlier pre-filter"),
          value("outlier-std", "M", "1", "pre-filter threshold: mean + M standard deviations"),
          value("residual-outliers", "F", "4", "points farther than F σ from their patch are removed"),
          flag("no-patches", "accepted: the cloud path's result is the geometric one"),
          hidden("dict", "DICT.pdd")};
}

/** The commands that make, score and code surfaces (demo ... decompress). */
void addToolCommands(std::vector<CommandSpec>& table)
{
  table.push_back({"demo", "", "", 0, 0,
                   "the main job: the bundled bunny and a generated relief damaged, repaired with and without patches",
                   {value("output", "DIR", "pcl_patchdict_demo", "folder of the meshes and pictures"),
                    flag("no-pictures", "meshes only")},
                   {{"out", "output"}}});
  table.push_back({"info", "", "IN", 1, 1, "statistics and hygiene report of a mesh or cloud", {}, {}});
  table.push_back({"eval", "", "REF OUT", 2, 2,
                   "vertex RMSE, symmetric surface distance, Hausdorff and PSNR of OUT against REF",
                   {value("vertices", "IDX.txt", "all", "vertex RMSE over these vertices only (same vertex count)"),
                    value("samples", "N", "200000", "surface samples per side, 1000-1e8"),
                    flag("absolute", "distances in the input's units, not the unit cube's")},
                   {}});
  table.push_back({"quads", "", "IN", 1, 1, "coarse shape, field-aligned quad mesh, and the seeds with their frames",
                   {required("output", "QUADS.obj", "the quad mesh (.obj or .ply)"),
                    value("quad-length", "L", "0.03", "quad edge length, unit-cube units"),
                    value("overlap", "K", "1", "4K extra seeds per quad"),
                    value("frames", "FRAMES.ply", "", "the seeds and their frames, as a PLY point set"),
                    value("coarse", "COARSE.ply", "", "the coarse shape"),
                    value("png", "PICTURE.png", "", "a picture of the quad mesh"),
                    value("smoothing", "laplacian|taubin", "laplacian", "smoothing of the coarse shape"),
                    value("smoothing-iterations", "N", "30", "its iterations")},
                   {}});
  table.push_back({"patches", "", "IN", 1, 1, "height-map patch set (unit-cube units)",
                   {required("output", "PATCHES.pds", "the patch set"),
                    value("png", "SHEET.png", "", "a contact sheet of the first 400 patches"),
                    value("grid", "N", "16", "bins per patch side, 2-64"),
                    value("quad-length", "L", "0.03", "quad edge length, unit-cube units"),
                    value("overlap", "K", "1", "4K extra seeds per quad"),
                    value("placement", "quads|random", "quads", "where the seeds go")},
                   {}});
  table.push_back(
      {"learn", "", "INPUT...", 1, 1000000,
       "learn a patch dictionary from .pds files, meshes, clouds, folders, globs or @lists (one input: K-SVD, "
       "local; several: online, streamed, resumable)",
       {required("output", "DICT.pdd", "the dictionary"),
        value("method", "ksvd|online", "ksvd (one input), online (several)", "learning method"),
        value("atoms", "K", "100", "atoms"), value("sparsity", "S", "8", "atoms per sparse code at most"),
        value("iterations", "T", "20 (ksvd), 3 (online)", "K-SVD iterations, or passes over the inputs"),
        value("batch", "B", "512", "mini-batch size (online)"),
        value("buffer", "N", "20000", "patches of the shuffle buffer (online)"),
        value("grid", "N", "16 (or the first input's)", "bins per patch side, 2-64"),
        value("quad-length", "L", "0.03", "quad edge length of surface inputs, unit-cube units"),
        value("overlap", "K", "1", "4K extra seeds per quad (surface inputs)"),
        flag("skip-bad", "skip unreadable inputs (each named on stderr) instead of failing"),
        value("checkpoint", "FILE.pdk", "", "save the learner's state there (online)"),
        value("checkpoint-every", "N", "10", "inputs between checkpoints (needs --checkpoint)"),
        value("stop-after", "N", "", "stop after N inputs, resumable (needs --checkpoint)"),
        value("resume", "FILE.pdk", "", "continue from a checkpoint (online)"),
        flag("remove-mean", "remove each patch's mean before learning (ksvd)"),
        value("png", "ATOMS.png", "", "a picture of the atoms")},
       {}});
  table.push_back({"reconstruct", "", "IN", 1, 1,
                   "surface -> patches -> surface round trip (identity, or through a dictionary), scored",
                   {required("output", "OUT", "the reconstructed mesh (a cloud's: the patches' points)"),
                    value("dict", "DICT.pdd", "", "code the patches through this dictionary"),
                    value("sparsity", "S", "20", "atoms per code (needs --dict)"),
                    value("rule", "bilinear|bin-centres", "bilinear", "how a vertex reads a patch (meshes)"),
                    value("grid", "N", "16", "bins per patch side, 2-64"),
                    value("quad-length", "L", "0.03", "quad edge length, unit-cube units"),
                    value("overlap", "K", "1", "4K extra seeds per quad"),
                    value("placement", "quads|random", "quads", "where the seeds go (clouds: quads)"),
                    value("samples", "N", "200000", "surface samples per side of the score (meshes)")},
                   {}});
  table.push_back(
      {"compress", "", "IN", 1, 1, "compress as quad mesh + sparse codes (.pdc); reports bytes per part and PSNR",
       {required("dict", "DICT.pdd", "the dictionary (the decoder needs the same)"),
        required("output", "OUT.pdc", "the compressed file"),
        value("quad-length", "L", "0.05", "quad edge length, unit-cube units"),
        value("patch-scale", "F", "1.25", "patch side, × the quad length, 0.5-4"),
        value("overlap", "K", "0", "4K extra seeds per quad"),
        value("sparsity", "S", "20", "non-zero coefficients per patch at most"),
        value("coefficient-bits", "B", "6", "bits of a quantised coefficient, 2-16"),
        value("position-bits", "B", "10", "bits of a quad-mesh vertex coordinate, 4-24"),
        value("subdivision", "N", "0 (grid / 2)", "splits per quad side of the decoded mesh"),
        value("smoothing-iterations", "N", "5", "smoothing iterations of the coarse shape"),
        flag("keep-connectivity", "store the input's connectivity and every vertex's place"),
        value("location-bits", "B", "10", "precision of a vertex's place (needs --keep-connectivity)"),
        flag("no-projection", "leave the quad vertices off the surface"),
        value("coverage-tolerance", "T", "0.1", "coverage patches where the decoded surface misses the input"),
        value("coverage-budget", "F", "1", "coverage patches at most, × the quad patches"),
        value("target-error", "E", "0", "per-patch error target, × the quad length (0: --sparsity atoms each)"),
        value("atom-cost", "C", "0", "rate-distortion weight of an atom (0: off)"),
        value("samples", "N", "200000", "surface samples per side of the PSNR"),
        flag("no-eval", "do not decode and score the result")},
       {{"coefficients", "sparsity"}}});
  table.push_back({"decompress", "", "IN.pdc", 1, 1, "decode a .pdc file (with the dictionary it was encoded with)",
                   {required("dict", "DICT.pdd", "the dictionary it was encoded with"),
                    required("output", "OUT", "the decoded mesh"),
                    value("ref", "REF", "", "score the decoded mesh against this surface"),
                    value("samples", "N", "200000", "surface samples per side of the score (needs --ref)"),
                    value("png", "PICTURE.png", "", "a picture, coverage patches in orange")},
                   {}});
}

/** The repairs: denoise, inpaint, fill-holes (with their cloud paths). */
void addRepairCommands(std::vector<CommandSpec>& table)
{
  table.push_back(
      {"denoise", "", "IN", 1, 1,
       "denoise: Taubin smoothing (iterations by the discrepancy principle); with --dict or --self-similar, "
       "corrected by patches",
       std::vector<OptionSpec>{required("output", "OUT", "the denoised mesh (vertex order kept: .ply, .obj, .off)"),
                               value("dict", "DICT.pdd", "", "correct by patches coded with this dictionary"),
                               flag("self-similar", "correct by patches of a dictionary learned from the input"),
                               flag("no-patches", "the Taubin base alone (the default without --dict)"),
                               value("noise", "S", "estimated", "noise σ, unit-cube units"),
                               value("noise-edges", "K", "", "noise σ, in mean edge lengths"),
                               value("base-iterations", "T", "by the discrepancy principle", "Taubin iterations"),
                               value("discrepancy", "D", "0.95", "stop the base when it moved D × σ (RMS)"),
                               value("error-factor", "E", "0.7", "sparse-code error target, × σ per bin (patches)"),
                               value("fidelity", "A", "0.05", "weight of staying at the base (patches)"),
                               hidden("mu", "M")} +
           patchStageOptions({"6", "20", nullptr, "0.1"}) + reportOptions(),
       {}});
  table.push_back({"denoise", "cloud", "CLOUD.pcd|CLOUD.ply", 1, 1,
                   "a point cloud: statistical pre-filter, local quadric patches, residual outliers",
                   std::vector<OptionSpec>{required("output", "OUT.pcd|OUT.ply", "the denoised cloud")} +
                       cloudDenoisingOptions(),
                   {}});
  table.push_back({"inpaint", "", "IN", 1, 1, "recover missing vertices",
                   std::vector<OptionSpec>{
                       required("missing", "IDX.txt", "the missing vertices' indices"),
                       required("output", "OUT", "the repaired mesh (vertex order kept: .ply, .obj, .off)"),
                       value("dict", "DICT.pdd", "self-similar", "correct by patches coded with this dictionary"),
                       flag("no-patches", "the bi-Laplacian base alone")} +
                       patchStageOptions({"3", "8", "0.03", "0.1"}) + reportOptions(),
                   {}});
  table.push_back(
      {"fill-holes", "", "IN", 1, 1, "fill holes: Liepa's triangulate-refine-fair, new vertices corrected by patches",
       std::vector<OptionSpec>{
           required("output", "OUT", "the filled mesh (input vertices first, in order)"),
           value("dict", "DICT.pdd", "self-similar", "correct by patches coded with this dictionary"),
           flag("no-patches", "Liepa's fill alone"),
           value("max-hole-edges", "E", "0 (any)", "fill holes of at most E boundary edges"),
           value("max-hole-diameter", "D", "any", "fill holes of at most this diameter, unit-cube units"),
           flag("absolute", "--max-hole-diameter in the input's units"),
           value("surface", "auto|smooth|relief", "auto", "patch settings: measured, smooth or relief (patches)"),
           value("hole-factor", "F", "0.6", "quad length at least F × the median hole diameter (patches)")} +
           patchStageOptions({"3", "8", "0.1", "0.02"}) + reportOptions(),
       {}});
  table.push_back(
      {"fill-holes", "cloud", "CLOUD.pcd|CLOUD.ply", 1, 1,
       "a point cloud: depth image, height field or Poisson gaps, filled from their rims",
       std::vector<OptionSpec>{
           required("output", "OUT.pcd|OUT.ply", "the filled cloud (a PCD keeps every field)"),
           value("max-hole-diameter", "D", "each fill's own", "fill holes of at most this diameter"),
           flag("denoise", "denoise as well"),
           value("rim-width", "W", "0.3", "rim of a Poisson gap, × its radius, 0.05-10"),
           value("max-hole-pixels", "N", "2000", "depth image: holes of at most N pixels"),
           value("fit-ring", "N", "0", "depth image: pixels of the rim fitted"),
           value("height-field", "auto|yes|no", "auto", "fill as a height field over the dominant plane")} +
           cloudDenoisingOptions(),
       {}});
}

std::vector<CommandSpec> makeTable()
{
  std::vector<CommandSpec> table;
  addToolCommands(table);
  addRepairCommands(table);
  return table;
}

std::string optionLabel(const OptionSpec& option)
{
  std::string label = (option.name == "output" ? "-o, --" : "--") + option.name;
  if (!option.argument.empty())
    label += " " + option.argument;
  return label;
}

std::string markdownCell(std::string text)
{
  std::string out;
  for (const char c : text)
    out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

std::vector<const CommandSpec*> pathsOf(const std::string& name)
{
  std::vector<const CommandSpec*> paths;
  for (const CommandSpec& spec : commandSpecs())
    if (spec.name == name)
      paths.push_back(&spec);
  return paths;
}

}  // namespace

const std::vector<OptionSpec>& commonOptions()
{
  static const std::vector<OptionSpec> options{
      value("threads", "T", "OpenMP's", "threads, 1-1024"),
      value("seed", "X", "1 (0 in quads and the mesh repairs)", "seed of every random choice"),
      flag("json", "one JSON object on stdout (no progress on stderr)"),
      flag("quiet", "no progress on stderr")};
  return options;
}

const std::vector<CommandSpec>& commandSpecs()
{
  static const std::vector<CommandSpec> table = makeTable();
  return table;
}

const CommandSpec& commandSpec(const std::string& name, const std::string& variant)
{
  for (const CommandSpec& spec : commandSpecs())
    if (spec.name == name && spec.variant == variant)
      return spec;
  throw std::logic_error("no command '" + name + "' (" + variant + ") in the option table");
}

const OptionSpec* findOption(const CommandSpec& spec, const std::string& name)
{
  for (const auto* list : {&spec.options, &commonOptions()})
    for (const OptionSpec& option : *list)
      if (option.name == name)
        return &option;
  return nullptr;
}

std::string synopsis(const CommandSpec& spec)
{
  std::string text = "pcl_patchdict " + spec.name;
  if (!spec.positionals.empty())
    text += " " + spec.positionals;
  for (const OptionSpec& option : spec.options)
    if (option.required)
      text += (option.name == "output" ? " -o " : " --" + option.name + " ") + option.argument;
  return text + " [options]";
}

std::string commandHelp(const std::string& name)
{
  std::ostringstream out;
  for (const CommandSpec* spec : pathsOf(name)) {
    out << (spec->variant.empty() ? "usage: " : "\n   or: ") << synopsis(*spec) << "\n  " << spec->what << "\n\n"
        << (spec->variant.empty() ? "options" : "options of the " + spec->variant + " path") << ":\n";
    for (const OptionSpec& option : spec->options) {
      if (option.hidden)
        continue;
      std::string label = optionLabel(option);
      out << "  " << label << std::string(label.size() < 34 ? 34 - label.size() : 1, ' ') << option.help;
      if (option.required)
        out << " (required)";
      else if (!option.fallback.empty())
        out << " [" << option.fallback << "]";
      out << '\n';
    }
    for (const auto& [old_name, new_name] : spec->deprecated)
      out << "  --" << old_name << std::string(old_name.size() < 32 ? 32 - old_name.size() : 1, ' ')
          << "deprecated spelling of --" << new_name << '\n';
  }
  out << "\ncommon options:";
  for (const OptionSpec& option : commonOptions())
    out << ' ' << optionLabel(option);
  out << "\n";
  return out.str();
}

std::string overviewHelp()
{
  std::ostringstream out;
  out << "pcl_patchdict — repair and compress 3D surfaces with learned dictionaries of height-map patches\n\n"
         "usage: pcl_patchdict COMMAND [ARGS] [OPTIONS]   (pcl_patchdict COMMAND --help: its options)\n\n"
         "commands:\n";
  for (const CommandSpec& spec : commandSpecs())
    if (spec.variant.empty())
      out << "  " << synopsis(spec) << "\n      " << spec.what << '\n';
  out << "  pcl_patchdict help [COMMAND] [--markdown]\n      this text, a command's options, or all of them as "
         "Markdown (docs/cli.md)\n\ncommon options:";
  for (const OptionSpec& option : commonOptions())
    out << ' ' << optionLabel(option);
  out << "\nformats: PLY (ascii/binary), OBJ, OFF, STL meshes; PCD and face-less PLY clouds\n";
  return out.str();
}

std::string markdownHelp()
{
  std::ostringstream out;
  out << "# The command line\n\n"
         "<!-- Generated by `pcl_patchdict help --markdown` from the option table in apps/options.cpp; the test\n"
         "     Cli.DocsMatchTheOptionTable fails when this file differs from what the tool prints. -->\n\n"
         "`pcl_patchdict COMMAND [ARGS] [OPTIONS]`; options may come before, between or after the positionals, "
         "as `--name VALUE` or `--name=VALUE`. A malformed command line (an unknown option, a value out of range, "
         "options that contradict each other or that the command would ignore) is one line on stderr and exit "
         "code 2; bad input or a failed run, one line and exit code 1.\n\n"
         "| command | what it does |\n|---|---|\n";
  for (const CommandSpec& spec : commandSpecs())
    if (spec.variant.empty())
      out << "| [`" << spec.name << "`](#" << spec.name << ") | " << markdownCell(spec.what) << " |\n";
  out << "\nEvery command also takes:\n\n| option | default | |\n|---|---|---|\n";
  for (const OptionSpec& option : commonOptions())
    out << "| `" << markdownCell(optionLabel(option)) << "` | " << markdownCell(option.fallback) << " | "
        << markdownCell(option.help) << " |\n";
  for (const CommandSpec& spec : commandSpecs()) {
    if (spec.variant.empty())
      out << "\n## " << spec.name << "\n";
    else
      out << "\n### " << spec.name << " on a " << spec.variant << "\n";
    out << "\n`" << synopsis(spec) << "`\n\n" << spec.what << "\n";
    bool any = false;
    for (const OptionSpec& option : spec.options) {
      if (option.hidden)
        continue;
      if (!any)
        out << "\n| option | default | |\n|---|---|---|\n";
      any = true;
      out << "| `" << markdownCell(optionLabel(option)) << "` | "
          << (option.required ? std::string("required") : markdownCell(option.fallback)) << " | "
          << markdownCell(option.help) << " |\n";
    }
    for (const auto& [old_name, new_name] : spec.deprecated)
      out << "\n`--" << old_name << "` is still accepted as a deprecated spelling of `--" << new_name << "`.\n";
  }
  return out.str();
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
