// SparsePatchMeshInpainter — the mesh repairs (patch_repairs.h) as a pcl::MeshProcessing, for PCL
// pipelines that hold a pcl::PolygonMesh: fill holes, denoise, or recover missing vertices.
#pragma once

#include <pcl_patchdict/repair/patch_repairs.h>

#include <pcl/PolygonMesh.h>
#include <pcl/surface/processing.h>

#include <memory>
#include <string>
#include <vector>

namespace pcl {
namespace patchdict {

/** \brief fillHolesWithPatches, denoiseWithPatches or fillMissingVertices on a pcl::PolygonMesh
  * (setInputMesh, process(output)), with the options and reports of those functions. The output
  * is a triangle mesh with x y z fields only (other fields of the input's cloud are not carried:
  * the repairs change vertex counts and positions); its vertices in the input's units, input
  * vertices first. Throws pcl::patchdict::Error as the functions do.
  *
  * One class with a Mode rather than three: the three repairs are one sparse-patch inpainting of a
  * mesh with three kinds of damage (holes, noise, unknown vertices), as the cloud path's
  * SparsePatchInpainter covers holes and noise with one class; they share the input, the dictionary
  * and the patch stage's options type, and the mode reads as the damage. Each mode keeps its own
  * options and report (set/getHoleRepairOptions, …), so no option of one repair reaches another;
  * the free functions are the one-repair-per-call form. */
class SparsePatchMeshInpainter : public pcl::MeshProcessing {
public:
  using Ptr = std::shared_ptr<SparsePatchMeshInpainter>;
  using ConstPtr = std::shared_ptr<const SparsePatchMeshInpainter>;

  enum class Mode { FillHoles, Denoise, FillMissingVertices };

  void setMode(Mode mode) { mode_ = mode; }
  Mode getMode() const { return mode_; }
  void setHoleRepairOptions(const HoleRepairOptions& options) { hole_options_ = options; }
  const HoleRepairOptions& getHoleRepairOptions() const { return hole_options_; }
  void setDenoiseOptions(const DenoiseOptions& options) { denoise_options_ = options; }
  const DenoiseOptions& getDenoiseOptions() const { return denoise_options_; }
  void setMissingVerticesOptions(const MissingVerticesOptions& options) { missing_options_ = options; }
  const MissingVerticesOptions& getMissingVerticesOptions() const { return missing_options_; }
  /** FillMissingVertices: the vertices whose positions are unknown. */
  void setMissingVertices(const std::vector<int>& indices) { missing_ = indices; }
  const std::vector<int>& getMissingVertices() const { return missing_; }
  /** The dictionary of every mode (null, the default: self-similar where a mode uses patches). */
  void setDictionary(const PatchDictionary::ConstPtr& dictionary);

  const HoleRepairReport& getHoleRepairReport() const { return hole_report_; }
  const DenoiseReport& getDenoiseReport() const { return denoise_report_; }
  const MissingVerticesReport& getMissingVerticesReport() const { return missing_report_; }

protected:
  void performProcessing(pcl::PolygonMesh& output) override;
  std::string getClassName() const override { return "SparsePatchMeshInpainter"; }

private:
  Mode mode_ = Mode::FillHoles;
  HoleRepairOptions hole_options_;
  DenoiseOptions denoise_options_;
  MissingVerticesOptions missing_options_;
  std::vector<int> missing_;
  HoleRepairReport hole_report_;
  DenoiseReport denoise_report_;
  MissingVerticesReport missing_report_;
};

}  // namespace patchdict
}  // namespace pcl
