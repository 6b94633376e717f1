// Private helpers the repairs of patch_repairs.h share.
#pragma once

#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/core/triangle_mesh.h>
#include <pcl_patchdict/repair/patch_correction.h>

#include <chrono>
#include <cstdint>
#include <memory>
#include <vector>

namespace pcl {
namespace patchdict {
namespace detail {

using Clock = std::chrono::steady_clock;
inline double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/** Error(message) unless `ok` and `value` is finite. */
void checkFinite(double value, bool ok, const char* message);

/** The report a repair fills: `*report` when given, else `local`; reset either way. */
template <class Report>
Report& freshReport(Report* report, Report& local)
{
  Report& r = report ? *report : local;
  r = Report();
  return r;
}

/** Error for an empty input, one without faces, or a face index out of range. */
void checkRepairInput(const TriangleMesh& input);
/** checkRepairInput, then the input's unit-cube normalisation after checking every position is
  * finite. */
UnitCubeNormalization checkedNormalization(const TriangleMesh& input);

/** Runs the patch stage on `estimate` for `targets`; one constraint list per target. The data are
  * the estimate's `observed_faces` (empty: all), or `observed_surface` when given; `layout` (when
  * given) is used instead of computing one. */
std::vector<std::vector<PointToPlaneConstraint>> patchConstraints(
    const std::shared_ptr<const TriangleMesh>& estimate, const std::vector<bool>& observed_faces,
    const std::vector<std::int32_t>& targets, const PatchDictionary::ConstPtr& dictionary,
    const PatchCorrectionParameters& parameters, PatchCorrectionReport& report,
    const std::shared_ptr<const TriangleMesh>& observed_surface = nullptr,
    const std::shared_ptr<const PatchLayout>& layout = nullptr);

std::vector<PointToPlaneConstraint> flatten(const std::vector<std::vector<PointToPlaneConstraint>>& lists);

/** Mean |now − base| over the moved vertices (0 when none). */
double meanCorrection(const std::vector<Eigen::Vector3d>& now, const std::vector<Eigen::Vector3d>& base,
                      const std::vector<std::int32_t>& moved);

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
