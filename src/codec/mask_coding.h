// Context-modelled binary arithmetic coding of N×N observation masks for the .pdc format (v3).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace pcl {
namespace patchdict {
namespace detail {

/** \brief Codes the bins of N×N masks (one char per bin, 0 or 1, row-major) with an adaptive binary
  * range coder (the LZMA coder, I. Pavlov: 11-bit probabilities, adaptation shift 4), each bin in
  * the context of six causal neighbours — left, up-left, up, up-right, two left, two up; outside
  * the grid 0 — as JBIG codes bilevel images. Masks are blobs (where a patch left the surface, where
  * coverage is needed), which this codes in fewer bytes than .pdc version 2's deflated bitmaps
  * (figures in docs/). */
std::string encodeMasks(const std::vector<std::vector<char>>& masks, int grid);

/** Decodes `count` masks of grid × grid bins from what encodeMasks wrote. Never reads past the end
  * of `bytes`; false unless the stream holds exactly those masks (not cut, nothing left over). */
bool decodeMasks(const std::string& bytes, std::size_t count, int grid, std::vector<std::vector<char>>& masks);

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
