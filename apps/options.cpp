// The command-line table (see options.h). An option several commands take is made by one function
// below (quadLength, overlap, grid, ...), so that its spelling, argument and range are written once.
#include "options.h"

#include <pcl_patchdict/cloud/nonlocal_patch_denoising.h>

#include <stdexcept>
#include <tuple>

namespace pcl {
namespace patchdict {
namespace cli {

OptionSpec OptionSpec::noted(const std::string& text) const
{
  OptionSpec option = *this;
  option.note = text;
  return option;
}

OptionSpec OptionSpec::differing(const std::string& why) const
{
  OptionSpec option = *this;
  option.differs = why;
  return option;
}

namespace {

constexpr double kUnbounded = std::numeric_limits<double>::infinity();

OptionSpec flag(const std::string& name, const std::string& help)
{
  OptionSpec option;
  option.name = name;
  option.help = help;
  return option;
}

/** An option with a value and a typed default (computed() takes it away). */
OptionSpec valued(const std::string& name, OptionKind kind, const std::string& argument, const std::string& help)
{
  OptionSpec option = flag(name, help);
  option.kind = kind;
  option.argument = argument;
  option.has_default = true;
  return option;
}

/** A file name or text; without a default unless `fallback` is given. */
OptionSpec text(const std::string& name, const std::string& argument, const std::string& help,
                const std::string& fallback = "")
{
  OptionSpec option = valued(name, OptionKind::Text, argument, help);
  option.has_default = !fallback.empty();
  option.text_default = fallback;
  return option;
}

OptionSpec required(const std::string& name, const std::string& argument, const std::string& help)
{
  OptionSpec option = text(name, argument, help);
  option.required = true;
  return option;
}

OptionSpec hidden(OptionSpec option)
{
  option.hidden = true;
  option.has_default = false;
  option.help.clear();
  return option;
}

OptionSpec integer(const std::string& name, const std::string& argument, long long fallback, long long min_value,
                   long long max_value, const std::string& help)
{
  OptionSpec option = valued(name, OptionKind::Integer, argument, help);
  option.int_default = fallback;
  std::tie(option.int_min, option.int_max) = std::make_pair(min_value, max_value);
  return option;
}

OptionSpec real(const std::string& name, const std::string& argument, double fallback, double min_value,
                double max_value, const std::string& help)
{
  OptionSpec option = valued(name, OptionKind::Real, argument, help);
  option.real_default = fallback;
  std::tie(option.real_min, option.real_max) = std::make_pair(min_value, max_value);
  return option;
}

OptionSpec word(const std::string& name, const std::vector<std::string>& words, const std::string& fallback,
                const std::string& help)
{
  std::string argument;
  for (const std::string& w : words)
    argument += (argument.empty() ? "" : "|") + w;
  OptionSpec option = valued(name, OptionKind::Word, argument, help);
  option.words = words;
  option.has_default = !fallback.empty();
  option.text_default = fallback;
  return option;
}

/** No typed default: the command computes it, as `how` says (or, with "", the option is off). */
OptionSpec computed(OptionSpec option, const std::string& how)
{
  option.has_default = false;
  option.note = how;
  return option;
}

std::vector<OptionSpec> operator+(std::vector<OptionSpec> a, const std::vector<OptionSpec>& b)
{
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// Options that several commands take: one spelling, one argument, one range each.

OptionSpec quadLength(double fallback, const std::string& help = "quad edge length, unit-cube units")
{
  return real("quad-length", "L", fallback, 1e-3, 0.5, help);
}

OptionSpec overlap(long long fallback, const std::string& help = "4K extra seeds per quad")
{
  return integer("overlap", "K", fallback, 0, 16, help);
}

/** Patch sets of a whole surface and the dictionaries learned from them: at most 64 × 64 bins. */
OptionSpec grid(long long fallback, const std::string& help = "bins per patch side")
{
  return integer("grid", "N", fallback, 2, 64, help);
}

OptionSpec sparsity(long long fallback, const std::string& help = "atoms per sparse code at most")
{
  return integer("sparsity", "S", fallback, 1, 1024, help);
}

OptionSpec atoms(long long fallback, const std::string& help)
{
  return integer("atoms", "K", fallback, 1, 65536, help);
}

OptionSpec samples(const std::string& help)
{
  return integer("samples", "N", 200000, 1000, 100000000, help);
}

OptionSpec smoothingIterations(long long fallback, const std::string& help)
{
  return integer("smoothing-iterations", "N", fallback, 0, 10000, help);
}

OptionSpec placement(const std::string& help)
{
  return word("placement", {"quads", "random"}, "quads", help);
}

OptionSpec patchScale(double fallback, double min_value, double max_value)
{
  return real("patch-scale", "F", fallback, min_value, max_value, "patch side, × the quad length");
}

OptionSpec seed(long long fallback)
{
  return integer("seed", "X", fallback, 0, 1LL << 62, "seed of every random choice");
}

OptionSpec noise(double max_value, const std::string& help)
{
  return real("noise", "S", 0.0, 0.0, max_value, help).noted("estimated");
}

OptionSpec dictionary(const std::string& note)
{
  return text("dict", "DICT.pdd", "correct by patches coded with this dictionary").noted(note);
}

/** What the patch stage of a mesh repair reads (repair_options.cpp); defaults by mode. */
struct PatchDefaults {
  double quad_factor;
  long long sparsity;
  double mu;  ///< < 0: the mode has no --mu
  double fit_scale;
};

std::vector<OptionSpec> patchStageOptions(const PatchDefaults& d)
{
  OptionSpec quad_length = quadLength(0.0, "quad length in unit-cube units; 0: --quad-factor × the mean edge")
                               .noted("automatic")
                               .differing("0 asks for the automatic length");
  quad_length.real_min = 0.0;
  std::vector<OptionSpec> options{
      quad_length,
      real("quad-factor", "C", d.quad_factor, 0.1, 1000.0, "automatic quad length, in mean edge lengths"),
      sparsity(d.sparsity)};
  if (d.mu >= 0.0)
    options.push_back(real("mu", "M", d.mu, 0.0, 1e12, "weight of the patch constraints in the solve"));
  return options + std::vector<OptionSpec>{
      overlap(1),
      atoms(100, "atoms of the self-similar dictionary (not with --dict)"),
      computed(integer("grid", "N", 0, 2, 256, "bins per patch side; with --dict it must match"),
               "the dictionary's (16 self-similar)")
          .differing("it must match a given dictionary's, which a .pdd holds up to 256"),
      patchScale(1.0, 0.05, 20.0),
      real("centre-sigma", "S", 0.5, 0.0, 100.0,
           "constraint weight's Gaussian fall-off from the patch centre, × half the side"),
      real("observed-power", "P", 1.0, 0.0, 100.0, "constraint weight ∝ (observed fraction of the patch)^P"),
      real("fit-scale", "F", d.fit_scale, 0.0, 1e6, "constraint weight's tolerance of a poor sparse fit, × the mean edge"),
      real("agreement-scale", "A", 0.1, 0.0, 1e6,
           "constraint weight's tolerance of disagreeing patches, × the mean edge"),
      real("min-observed", "F", 0.2, 0.0, 1.0, "patches less observed than this fraction give no constraint"),
      smoothingIterations(30, "smoothing iterations of the coarse shape the quads are laid on")};
}

/** The report options and the seed, after a mesh repair's patch-stage options. */
std::vector<OptionSpec> meshRepairTail()
{
  return {text("report", "DIR", "write before/after pictures (and, with --ref, the error colouring) to DIR"),
          text("ref", "REF", "the true surface, for the report's error colouring (needs --report)"),
          real("error-scale", "E", 0.0, 0.0, kUnbounded, "distance coloured red in the report (needs --ref)")
              .noted("99th percentile"),
          seed(0)};
}

OptionSpec patchDecision()
{
  return word("patch-decision", {"measured", "always"}, "measured",
              "keep the patches only when measured to help, or always (to measure them)");
}

std::vector<OptionSpec> cloudDenoisingOptions()
{
  const std::string units = "with --absolute, the cloud's own units";
  return {noise(kUnbounded, "noise σ, in units of the largest bounding-box side").differing(units),
          real("bandwidth", "H", 0.0, 0.0, kUnbounded, "patch bandwidth, in units of the largest bounding-box side")
              .noted("by risk"),
          flag("absolute", "lengths in the cloud's own units, not the largest side's"),
          flag("no-outlier-filter", "no statistical outlier pre-filter"),
          integer("outlier-neighbours", "K", 50, 1, 1000, "neighbours of the outlier pre-filter"),
          real("outlier-std", "M", 1.0, 0.0, 1e6, "pre-filter threshold: mean + M standard deviations"),
          real("residual-outliers", "F", 4.0, 0.0, 1e6, "points farther than F σ from their patch are removed"),
          flag("no-patches", "the geometric result alone (no patch stage)"),
          flag("self-similar", "patches of a dictionary learned from the input (the default; applied if measured to help)"),
          patchDecision(),
          integer("max-checked-points", "N", static_cast<long long>(NonlocalPatchOptions().max_checked_points), 0, 1LL << 40,
                  "unorganised clouds of more points skip the non-local patches (on 2 cores their check costs "
                  "0.1-0.5 ms a point, the stage 0.3-0.6 ms); 0: no limit"),
          text("dict", "DICT.pdd", "code the patches over this dictionary (applied if measured to help)"),
          text("sensor-model", "MODEL.txt",
               "organised frames: the sensor model saved by info --save-sensor-model (nothing fitted; "
               "a frame that does not fit it is refused)")};
}

/** The commands that make and score surfaces and patches (demo ... reconstruct). */
void addSurfaceCommands(std::vector<CommandSpec>& table)
{
  table.push_back({"demo", "", "", 0, 0,
                   "the main job: the bundled bunny and a generated relief damaged, repaired with and without patches",
                   {text("output", "DIR", "folder of the meshes and pictures", "pcl_patchdict_demo"),
                    flag("no-pictures", "meshes only")},
                   {{"out", "output"}}});
  table.push_back({"info", "", "IN", 1, 1, "statistics and hygiene report of a mesh or cloud",
                   {text("save-sensor-model", "MODEL.txt",
                         "an organised cloud: write its sensor model (camera or beams, noise law) for the frames after")},
                   {}});
  table.push_back({"eval", "", "REF OUT", 2, 2,
                   "vertex RMSE, symmetric surface distance, Hausdorff and PSNR of OUT against REF",
                   {text("vertices", "IDX.txt", "vertex RMSE over these vertices only (same vertex count)").noted("all"),
                    samples("surface samples per side"),
                    flag("absolute", "distances in the input's units, not the unit cube's")},
                   {}});
  table.push_back({"quads", "", "IN", 1, 1, "coarse shape, field-aligned quad mesh, and the seeds with their frames",
                   {required("output", "QUADS.obj", "the quad mesh (.obj or .ply)"), quadLength(0.03), overlap(1),
                    text("frames", "FRAMES.ply", "the seeds and their frames, as a PLY point set"),
                    text("coarse", "COARSE.ply", "the coarse shape"),
                    text("png", "PICTURE.png", "a picture of the quad mesh"),
                    word("smoothing", {"laplacian", "taubin"}, "laplacian", "smoothing of the coarse shape"),
                    smoothingIterations(30, "its iterations"), seed(0)},
                   {}});
  table.push_back({"patches", "", "IN", 1, 1, "height-map patch set (unit-cube units)",
                   {required("output", "PATCHES.pds", "the patch set"),
                    text("png", "SHEET.png", "a contact sheet of the first 400 patches"), grid(16), quadLength(0.03),
                    overlap(1), placement("where the seeds go")},
                   {}});
  table.push_back(
      {"learn", "", "INPUT...", 1, 1000000,
       "learn a patch dictionary from .pds files, meshes, clouds, folders, globs or @lists (one input: K-SVD, "
       "local; several: online, streamed, resumable)",
       {required("output", "DICT.pdd", "the dictionary"),
        computed(word("method", {"ksvd", "online"}, "", "learning method"), "ksvd (one input), online (several)"),
        atoms(100, "atoms"), sparsity(8),
        computed(integer("iterations", "T", 0, 1, 100000, "K-SVD iterations, or passes over the inputs"),
                 "20 (ksvd), 3 (online)"),
        integer("batch", "B", 512, 1, 1 << 20, "mini-batch size (online)"),
        integer("buffer", "N", 20000, 1, 1LL << 32, "patches of the shuffle buffer (online; each shard has its own)"),
        grid(16).noted("or the first input's"), quadLength(0.03, "quad edge length of surface inputs, unit-cube units"),
        overlap(1, "4K extra seeds per quad (surface inputs)"),
        flag("skip-bad", "skip unreadable inputs (each named on stderr) instead of failing"),
        flag("no-patch-cache",
             "make the patches of surface inputs again on every pass, instead of keeping them in a temporary folder (online)"),
        text("checkpoint", "FILE.pdk", "save the learner's state there (online)"),
        integer("checkpoint-every", "N", 10, 1, 1LL << 40, "inputs between checkpoints (needs --checkpoint)"),
        computed(integer("stop-after", "N", 0, 1, 1LL << 40, "stop after N inputs, resumable (needs --checkpoint)"), ""),
        text("resume", "FILE.pdk", "continue from a checkpoint (online)"),
        computed(integer("shards", "S", 1, 1, 4096,
                         "split the inputs over S shards whose statistics are summed every mini-batch (online; "
                         "under mpirun, one shard per rank)"),
                 "1, or the number of MPI ranks"),
        flag("remove-mean", "remove each patch's mean before learning (ksvd)"),
        text("png", "ATOMS.png", "a picture of the atoms")},
       {}});
  table.push_back({"reconstruct", "", "IN", 1, 1,
                   "surface -> patches -> surface round trip (identity, or through a dictionary), scored",
                   {required("output", "OUT", "the reconstructed mesh (a cloud's: the patches' points)"),
                    text("dict", "DICT.pdd", "code the patches through this dictionary"),
                    sparsity(20, "atoms per code (needs --dict)"),
                    word("rule", {"bilinear", "bin-centres"}, "bilinear", "how a vertex reads a patch (meshes)"),
                    grid(16), quadLength(0.03), overlap(1), placement("where the seeds go (clouds: quads)"),
                    samples("surface samples per side of the score (meshes)")},
                   {}});
}

/** The codec: compress and decompress. */
void addCodecCommands(std::vector<CommandSpec>& table)
{
  table.push_back(
      {"compress", "", "IN", 1, 1, "compress as quad mesh + sparse codes (.pdc); reports bytes per part and PSNR",
       {required("dict", "DICT.pdd", "the dictionary (the decoder needs the same)"),
        required("output", "OUT.pdc", "the compressed file"),
        real("quad-length", "L", 0.05, 1e-3, 1.0, "quad edge length, unit-cube units")
            .differing("the .pdc format holds quad lengths up to 1"),
        patchScale(1.25, 0.5, 4.0).differing("the .pdc format holds patch scales of 0.5 to 4"), overlap(0),
        sparsity(20, "non-zero coefficients per patch at most"),
        integer("coefficient-bits", "B", 6, 2, 16, "bits of a quantised coefficient"),
        integer("position-bits", "B", 10, 4, 24, "bits of a quad-mesh vertex coordinate"),
        integer("subdivision", "N", 0, 0, 256, "splits per quad side of the decoded mesh").noted("grid / 2"),
        smoothingIterations(5, "smoothing iterations of the coarse shape"),
        flag("keep-connectivity", "store the input's connectivity and every vertex's place"),
        integer("location-bits", "B", 10, 4, 16, "precision of a vertex's place (needs --keep-connectivity)"),
        flag("no-projection", "leave the quad vertices off the surface"),
        real("coverage-tolerance", "T", 0.1, 0.0, 10.0, "coverage patches where the decoded surface misses the input"),
        real("coverage-budget", "F", 1.0, 0.0, 10.0, "coverage patches at most, × the quad patches"),
        real("target-error", "E", 0.0, 0.0, 1.0, "per-patch error target, × the quad length (0: --sparsity atoms each)"),
        real("atom-cost", "C", 0.0, 0.0, 10.0, "rate-distortion weight of an atom (0: off)"),
        samples("surface samples per side of the PSNR"), flag("no-eval", "do not decode and score the result")},
       {{"coefficients", "sparsity"}}});
  table.push_back({"decompress", "", "IN.pdc", 1, 1, "decode a .pdc file (with the dictionary it was encoded with)",
                   {required("dict", "DICT.pdd", "the dictionary it was encoded with"),
                    required("output", "OUT", "the decoded mesh"),
                    text("ref", "REF", "score the decoded mesh against this surface"),
                    samples("surface samples per side of the score (needs --ref)"),
                    text("png", "PICTURE.png", "a picture, coverage patches in orange")},
                   {}});
}

/** The repairs: denoise, inpaint, fill-holes (with their cloud paths). */
void addRepairCommands(std::vector<CommandSpec>& table)
{
  table.push_back(
      {"denoise", "", "IN", 1, 1,
       "denoise: Taubin smoothing (iterations by the discrepancy principle); with --dict or --self-similar, "
       "corrected by patches where measured to help",
       std::vector<OptionSpec>{
           required("output", "OUT", "the denoised mesh (vertex order kept: .ply, .obj, .off)"), dictionary(""),
           flag("self-similar", "correct by patches of a dictionary learned from the input"),
           flag("no-patches", "the Taubin base alone (the default without --dict)"), patchDecision(),
           noise(1.0, "noise σ, unit-cube units"),
           computed(real("noise-edges", "K", 0.0, 0.0, 100.0, "noise σ, in mean edge lengths"), ""),
           integer("base-iterations", "T", -1, -1, 10000, "Taubin iterations").noted("by the discrepancy principle"),
           real("discrepancy", "D", 0.95, 0.0, 100.0, "stop the base when it moved D × σ (RMS)"),
           real("error-factor", "E", 0.7, 0.0, 100.0, "sparse-code error target, × σ per bin (patches)"),
           real("fidelity", "A", 0.05, 1e-9, 1e9, "weight of staying at the base (patches)"),
           hidden(real("mu", "M", 0.0, 0.0, 1e12, ""))} +
           patchStageOptions({6.0, 20, -1.0, 0.1}) + meshRepairTail(),
       {}});
  table.push_back({"denoise", "cloud", "CLOUD.pcd|CLOUD.ply", 1, 1,
                   "a point cloud: statistical pre-filter, local quadric patches, residual outliers",
                   std::vector<OptionSpec>{required("output", "OUT.pcd|OUT.ply", "the denoised cloud")} +
                       cloudDenoisingOptions(),
                   {}});
  table.push_back({"fill-missing", "", "IN", 1, 1, "recover missing vertices (formerly `inpaint`, a name still accepted)",
                   std::vector<OptionSpec>{
                       required("missing", "IDX.txt", "the missing vertices' indices"),
                       required("output", "OUT", "the repaired mesh (vertex order kept: .ply, .obj, .off)"),
                       dictionary("self-similar"), flag("no-patches", "the bi-Laplacian base alone")} +
                       patchStageOptions({3.0, 8, 0.03, 0.1}) + meshRepairTail(),
                   {}});
  table.push_back(
      {"fill-holes", "", "IN", 1, 1, "fill holes: Liepa's triangulate-refine-fair, new vertices corrected by patches",
       std::vector<OptionSpec>{
           required("output", "OUT", "the filled mesh (input vertices first, in order)"), dictionary("self-similar"),
           flag("no-patches", "Liepa's fill alone"),
           integer("max-hole-edges", "E", 0, 0, 1LL << 40, "fill holes of at most E boundary edges").noted("any"),
           computed(real("max-hole-diameter", "D", 0.0, 0.0, kUnbounded,
                         "fill holes of at most this diameter, unit-cube units"),
                    "any")
               .differing("in unit-cube units (or, with --absolute, the input's); 0 fills none"),
           flag("absolute", "--max-hole-diameter in the input's units"),
           word("surface", {"auto", "smooth", "relief"}, "auto", "patch settings: measured, smooth or relief (patches)"),
           real("hole-factor", "F", 0.6, 0.0, 100.0, "quad length at least F × the median hole diameter (patches)")} +
           patchStageOptions({3.0, 8, 0.1, 0.02}) + meshRepairTail(),
       {}});
  OptionSpec cloud_diameter = computed(real("max-hole-diameter", "D", 0.0, 0.0, kUnbounded,
                                            "fill holes of at most this diameter"),
                                       "each fill's own")
                                  .differing("in units of the largest side (or, with --absolute, the cloud's)");
  cloud_diameter.above_min = true;
  table.push_back(
      {"fill-holes", "cloud", "CLOUD.pcd|CLOUD.ply", 1, 1,
       "a point cloud: depth image, height field or Poisson gaps, filled from their rims",
       std::vector<OptionSpec>{
           required("output", "OUT.pcd|OUT.ply", "the filled cloud (a PCD keeps every field)"), cloud_diameter,
           flag("denoise", "denoise as well"),
           real("rim-width", "W", 0.3, 0.05, 10.0, "rim of a Poisson gap, × its radius"),
           integer("max-hole-pixels", "N", 2000, 1, 100000000, "depth image: holes of at most N pixels"),
           integer("fit-ring", "N", 0, 0, 64, "depth image: pixels of the rim fitted"),
           word("height-field", {"auto", "yes", "no"}, "auto", "fill as a height field over the dominant plane")} +
           cloudDenoisingOptions(),
       {}});
}

std::vector<CommandSpec> makeTable()
{
  std::vector<CommandSpec> table;
  addSurfaceCommands(table);
  addCodecCommands(table);
  addRepairCommands(table);
  return table;
}

}  // namespace

const std::vector<OptionSpec>& commonOptions()
{
  static const std::vector<OptionSpec> options{
      computed(integer("threads", "T", 0, 1, 1024, "threads"), "OpenMP's"), seed(1),
      flag("json", "one JSON object on stdout (no progress on stderr)"), flag("quiet", "no progress on stderr")};
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

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
