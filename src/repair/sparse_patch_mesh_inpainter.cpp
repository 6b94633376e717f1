// SparsePatchMeshInpainter (sparse_patch_mesh_inpainter.h): PolygonMesh in, the repair, PolygonMesh out.
#include <pcl_patchdict/repair/sparse_patch_mesh_inpainter.h>

#include <pcl_patchdict/pcl/conversions.h>

namespace pcl {
namespace patchdict {

void SparsePatchMeshInpainter::setDictionary(const PatchDictionary::ConstPtr& dictionary)
{
  hole_options_.dictionary = dictionary;
  denoise_options_.dictionary = dictionary;
  missing_options_.dictionary = dictionary;
}

void SparsePatchMeshInpainter::performProcessing(pcl::PolygonMesh& output)
{
  TriangleMesh input, repaired;
  fromPolygonMesh(*input_mesh_, input);
  switch (mode_) {
  case Mode::FillHoles:
    fillHolesWithPatches(input, repaired, hole_options_, &hole_report_);
    break;
  case Mode::Denoise:
    denoiseWithPatches(input, repaired, denoise_options_, &denoise_report_);
    break;
  case Mode::FillMissingVertices:
    fillMissingVertices(input, missing_, repaired, missing_options_, &missing_report_);
    break;
  }
  toPolygonMesh(repaired, output);
}

}  // namespace patchdict
}  // namespace pcl
