// What the repair subcommands (inpaint, fill-holes, denoise) share: the patch-stage options, the
// dictionary, and how the patch stage is summarised on stderr and in --json.
#pragma once

#include "cli.h"

#include <pcl_patchdict/repair/patch_repairs.h>

#include <set>
#include <string>

namespace pcl {
namespace patchdict {
namespace cli {

struct CommandSpec;

/** The options that tune the patch stage (--quad-length, --sparsity, --mu, ...): refused when the
  * command runs without patches (refusePatchOptions). */
const std::vector<std::string>& patchStageOptionNames();
/** UsageError "--X tunes the patch stage, which `why`" for the first such option given. */
void refusePatchOptions(const Arguments& args, const std::string& why);

/** True when the command line (read with the options of both paths of `command`) names one point
  * cloud (.pcd, face-less .ply): the command takes its cloud path, with its own options. */
bool takesCloudPath(const std::vector<std::string>& raw, const std::string& command);

/** The command line of a mesh repair (inpaint, fill-holes, denoise), read with `spec`'s table:
  * IN, -o OUT; --threads applied, the output checked (checkRepairOutput). */
struct RepairCommandLine {
  Arguments args;
  bool quiet = false;  ///< --quiet or --json: no progress on stderr
  std::string in_path, out_path;
};
RepairCommandLine parseRepairCommand(const std::vector<std::string>& raw, const CommandSpec& spec,
                                     bool keeps_vertex_order);
/** Refuses an output that would overwrite the input or that is no mesh file; with
  * keeps_vertex_order, also STL (which does not keep vertex order). */
void checkRepairOutput(const std::string& out_path, const std::string& in_path, bool keeps_vertex_order);
/** loadMesh, and an Error naming `command` when the file has no faces. */
TriangleMesh loadRepairMesh(const std::string& path, bool quiet, const std::string& command);
/** The patch-stage options every repair shares, read from the command's table into `options`
  * (whose other fields keep their repair's defaults); --mu, where the command has it, is the
  * caller's (the repairs name their weights apart). UsageErrors: --dict with --no-patches, a
  * patch-stage option with --no-patches, --atoms with --dict, --ref without --report,
  * --error-scale without --ref. */
void readRepairOptions(const Arguments& args, PatchRepairCommon& options);
/** The patch source, once the inputs are loaded: `dictionary` (null: self-similar) when
  * `use_patches`, none otherwise (decision Never: the geometric base alone). */
void setPatchSource(PatchRepairCommon& options, const PatchDictionary::ConstPtr& dictionary, bool use_patches);

/** What --report DIR [--ref REF [--error-scale E]] asks for. */
struct ReportRequest {
  std::string folder;  ///< empty: no report
  TriangleMesh reference;
  bool has_reference = false;
  double error_scale = 0.0;
};
/** Reads the reference (it must have faces) and makes the folder: called after every option is
  * parsed and before any work, so that a report that cannot be made fails the command before its
  * output exists, and a command-line error leaves no folder behind. */
ReportRequest prepareReport(const Arguments& args);
/** What a mesh repair reads before its work. */
struct RepairInputs {
  ReportRequest report;
  TriangleMesh mesh;
  PatchDictionary::ConstPtr dictionary;  ///< --dict's, or null
};
/** prepareReport, then (the timer's "load" stage) the mesh (loadRepairMesh) and --dict D, checked
  * against the grid of --grid, `grid_size` (0: any). */
RepairInputs loadRepairInputs(const RepairCommandLine& line, int grid_size, const std::string& command,
                              StageTimer& timer);
/** The pictures (and with a reference the error colouring, red at --error-scale, default the 99th
  * percentile) of repair_report.h when a report was asked for; an empty object otherwise. */
JsonObject reportIfAsked(const ReportRequest& request, const TriangleMesh& before, const TriangleMesh& after,
                         std::size_t first_new_face, bool quiet);
/** "given", "self-similar" or "none". */
std::string dictionaryKind(const Arguments& args);

/** "L = … (… × mean edge), … of … patches used, … constraints on … vertices". */
std::string patchStageSummary(const PatchCorrectionReport& report);
JsonObject patchStageJson(const PatchCorrectionReport& report);
/** Seconds of the base, the patch stage (and its parts), and the solve. */
/** Seconds of the base, the patch stage (and its parts), and the solve; the hole repair's adds its
  * relief check's (zeros for the other repairs, so every report has the same keys). */
JsonObject repairStagesJson(const PatchRepairReport& report);
JsonObject repairStagesJson(const HoleRepairReport& report);

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
