// Patch histograms — a PatchDictionary learned from, coding and decoding height-map patches held as
// pcl::PointCloud<pcl::Histogram<N·N>> (HeightMapPatchExtractor's output): NaN bins are unobserved.
#pragma once

#include <pcl_patchdict/coding/patch_dictionary.h>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Core>

namespace pcl {
namespace patchdict {

/** \brief Histograms as the core's patches: `heights` M × P (one column per histogram, NaN bins as
  * 0) and `observed` (false where the bin is NaN). Infinite values are kept: coding rejects them. */
template <int M>
void histogramsToPatches(const pcl::PointCloud<pcl::Histogram<M>>& histograms, Eigen::MatrixXd& heights,
                         ObservationMask& observed);

/** \brief Patches (M × P) as histograms: unobserved bins (mask false) NaN; an empty mask observes
  * every bin. width P, height 1, is_dense when no bin is NaN. Throws Error when heights.rows() ≠ M
  * or the mask's size differs. */
template <int M>
void patchesToHistograms(const Eigen::MatrixXd& heights, const ObservationMask& observed,
                         pcl::PointCloud<pcl::Histogram<M>>& histograms);

/** \brief A dictionary learned from histograms (M = N·N bins each), NaN bins unobserved: the same
  * as PatchDictionary::learn on histogramsToPatches' heights and mask (the mask left out when every
  * bin is finite). Histograms without any finite bin (seeds without a frame) are left out. The
  * dictionary keeps the mean (to remove it: PatchDictionary::setRemoveMean, then learn). Throws
  * Error for bad sizes or options, or when no histogram has a finite bin. */
template <int M>
PatchDictionary learnPatchDictionary(const pcl::PointCloud<pcl::Histogram<M>>& histograms,
                                     const DictionaryLearningOptions& options = DictionaryLearningOptions(),
                                     LearningReport* report = nullptr);

/** \brief Sparse codes of histograms: Batch-OMP when every bin is finite (PatchDictionary::encode),
  * masked OMP over the finite bins otherwise (encodeMasked: decodePatches then fills every bin). */
template <int M>
PatchCodes encodePatches(const PatchDictionary& dictionary, const pcl::PointCloud<pcl::Histogram<M>>& histograms,
                         const SparseCodingParameters& parameters);

/** \brief The histograms the codes describe, every bin filled (PatchDictionary::decode). Throws Error
  * when the dictionary's atoms do not have M bins. */
template <int M>
void decodePatches(const PatchDictionary& dictionary, const PatchCodes& codes,
                   pcl::PointCloud<pcl::Histogram<M>>& histograms);

/** \brief RMS of estimate − histograms over the bins where `histograms` is finite (0 when none is):
  * how well decoded histograms describe the ones they were coded from. Throws Error when the two
  * clouds differ in size. */
template <int M>
double observedRMSE(const pcl::PointCloud<pcl::Histogram<M>>& estimate,
                    const pcl::PointCloud<pcl::Histogram<M>>& histograms);

}  // namespace patchdict
}  // namespace pcl

#include <pcl_patchdict/pcl/impl/patch_histograms.hpp>
