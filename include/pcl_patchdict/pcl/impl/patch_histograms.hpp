// Patch histograms (see patch_histograms.h): pcl::Histogram<M> clouds ↔ the core's patch matrices
// and observation masks, around PatchDictionary.
#pragma once

#include <pcl_patchdict/core/error.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>

namespace pcl {
namespace patchdict {

template <int M>
void histogramsToPatches(const pcl::PointCloud<pcl::Histogram<M>>& histograms, Eigen::MatrixXd& heights,
                         ObservationMask& observed)
{
  const auto count = static_cast<Eigen::Index>(histograms.size());
  heights.resize(M, count);
  observed.resize(M, count);
  for (Eigen::Index p = 0; p < count; ++p) {
    const float* bins = histograms[static_cast<std::size_t>(p)].histogram;
    for (Eigen::Index b = 0; b < M; ++b) {
      const bool seen = !std::isnan(bins[b]);
      heights(b, p) = seen ? static_cast<double>(bins[b]) : 0.0;
      observed(b, p) = seen;
    }
  }
}

template <int M>
void patchesToHistograms(const Eigen::MatrixXd& heights, const ObservationMask& observed,
                         pcl::PointCloud<pcl::Histogram<M>>& histograms)
{
  if (heights.rows() != M)
    throw Error("patches of " + std::to_string(heights.rows()) + " bins cannot fill a pcl::Histogram<" +
                std::to_string(M) + ">");
  const bool masked = observed.size() != 0;
  if (masked && (observed.rows() != heights.rows() || observed.cols() != heights.cols()))
    throw Error("the observation mask does not match the patches");
  histograms.clear();
  histograms.resize(static_cast<std::size_t>(heights.cols()));
  bool dense = true;
  for (Eigen::Index p = 0; p < heights.cols(); ++p) {
    float* bins = histograms[static_cast<std::size_t>(p)].histogram;
    for (Eigen::Index b = 0; b < M; ++b) {
      const bool seen = !masked || observed(b, p);
      bins[b] = seen ? static_cast<float>(heights(b, p)) : std::numeric_limits<float>::quiet_NaN();
      dense = dense && seen;
    }
  }
  histograms.width = static_cast<std::uint32_t>(histograms.size());
  histograms.height = 1;
  histograms.is_dense = dense;
}

template <int M>
PatchDictionary learnPatchDictionary(const pcl::PointCloud<pcl::Histogram<M>>& histograms,
                                     const DictionaryLearningOptions& options, LearningReport* report)
{
  Eigen::MatrixXd heights;
  ObservationMask observed;
  histogramsToPatches(histograms, heights, observed);
  // Histograms with no finite bin say nothing about the surface: left out.
  Eigen::Index kept = 0;
  for (Eigen::Index p = 0; p < heights.cols(); ++p)
    if (observed.col(p).any()) {
      if (kept != p) {
        heights.col(kept) = heights.col(p);
        observed.col(kept) = observed.col(p);
      }
      ++kept;
    }
  if (kept == 0)
    throw Error("no histogram has a finite bin to learn a dictionary from");
  heights.conservativeResize(Eigen::NoChange, kept);
  observed.conservativeResize(Eigen::NoChange, kept);
  PatchDictionary dictionary;
  const LearningReport learned = dictionary.learn(heights, observed.all() ? ObservationMask() : observed, options);
  if (report)
    *report = learned;
  return dictionary;
}

template <int M>
PatchCodes encodePatches(const PatchDictionary& dictionary, const pcl::PointCloud<pcl::Histogram<M>>& histograms,
                         const SparseCodingParameters& parameters)
{
  Eigen::MatrixXd heights;
  ObservationMask observed;
  histogramsToPatches(histograms, heights, observed);
  return observed.all() ? dictionary.encode(heights, parameters)
                        : dictionary.encodeMasked(heights, observed, parameters);
}

template <int M>
void decodePatches(const PatchDictionary& dictionary, const PatchCodes& codes,
                   pcl::PointCloud<pcl::Histogram<M>>& histograms)
{
  if (!dictionary.empty() && dictionary.atoms().rows() != M)
    throw Error("the dictionary's atoms have " + std::to_string(dictionary.atoms().rows()) +
                " bins, a pcl::Histogram<" + std::to_string(M) + "> holds " + std::to_string(M));
  patchesToHistograms(dictionary.decode(codes), ObservationMask(), histograms);
}

template <int M>
double observedRMSE(const pcl::PointCloud<pcl::Histogram<M>>& estimate,
                    const pcl::PointCloud<pcl::Histogram<M>>& histograms)
{
  if (estimate.size() != histograms.size())
    throw Error("observedRMSE: " + std::to_string(estimate.size()) + " estimates for " +
                std::to_string(histograms.size()) + " histograms");
  double squared = 0.0;
  std::size_t count = 0;
  for (std::size_t p = 0; p < histograms.size(); ++p)
    for (int b = 0; b < M; ++b) {
      const float value = histograms[p].histogram[b];
      if (std::isnan(value))
        continue;
      squared += std::pow(static_cast<double>(estimate[p].histogram[b]) - static_cast<double>(value), 2);
      ++count;
    }
  return count ? std::sqrt(squared / static_cast<double>(count)) : 0.0;
}

}  // namespace patchdict
}  // namespace pcl
