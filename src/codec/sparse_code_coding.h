// Entropy coding of the .pdc patches' sparse codes (format version 3): atom sets and coefficients
// through the adaptive binary range coder (range_coder.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace pcl {
namespace patchdict {
namespace detail {

/** \brief Each patch's atom set as K yes/no decisions, atom k in its own adaptive context: an atom
  * used by a fraction f of the patches costs about H(f) bits per patch, where a K-bit map costs
  * one (and deflate several per non-zero). `atoms` lists each patch's
  * indices in increasing order, all below `num_atoms` (else Error). */
std::string encodeAtomSets(const std::vector<std::vector<std::uint32_t>>& atoms, std::uint32_t num_atoms);

/** Decodes `patches` atom sets; false unless the stream holds exactly them, each of at most
  * `max_atoms` atoms. */
bool decodeAtomSets(const std::string& bytes, std::size_t patches, std::uint32_t num_atoms, std::size_t max_atoms,
                    std::vector<std::vector<std::uint32_t>>& atoms);

/** \brief Quantised coefficients (non-zero, |v| ≤ 32767, one per listed atom; anything else throws
  * Error): |v| + 1 as an Elias gamma code whose unary length and mantissa bits each have an
  * adaptive context, then the sign in a context of its atom. */
std::string encodeCoefficients(const std::vector<std::vector<std::int32_t>>& values,
                               const std::vector<std::vector<std::uint32_t>>& atoms, std::uint32_t num_atoms);

/** Decodes one value per listed atom; false unless the stream holds exactly them. */
bool decodeCoefficients(const std::string& bytes, const std::vector<std::vector<std::uint32_t>>& atoms,
                        std::uint32_t num_atoms, std::vector<std::vector<std::int32_t>>& values);

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
