// Entropy coding of the .pdc sparse codes (see sparse_code_coding.h).
#include "codec/sparse_code_coding.h"

#include "codec/range_coder.h"

#include <pcl_patchdict/core/error.h>

#include <algorithm>
#include <cstdlib>

namespace pcl {
namespace patchdict {
namespace detail {

namespace {

constexpr int kLengthBits = 16;  // |v| + 1 ≤ 32768 has at most 15 bits after its leading one

/** Adaptive contexts of the coefficient code: unary length, mantissa bit per (length, position),
  * sign per atom. */
struct CoefficientContexts {
  explicit CoefficientContexts(std::uint32_t num_atoms)
    : length(kLengthBits, kHalfProbability)
    , mantissa(kLengthBits * kLengthBits, kHalfProbability)
    , sign(num_atoms, kHalfProbability)
  {}
  std::vector<std::uint16_t> length, mantissa, sign;
};

}  // namespace

std::string encodeAtomSets(const std::vector<std::vector<std::uint32_t>>& atoms, std::uint32_t num_atoms)
{
  RangeEncoder encoder;
  std::vector<std::uint16_t> used(num_atoms, kHalfProbability);
  for (const auto& list : atoms) {
    for (std::size_t i = 0; i < list.size(); ++i)
      if (list[i] >= num_atoms || (i > 0 && list[i] <= list[i - 1]))
        throw Error("atom sets must list increasing indices below the atom count");
    std::size_t next = 0;
    for (std::uint32_t a = 0; a < num_atoms; ++a) {
      const int bit = next < list.size() && list[next] == a ? 1 : 0;
      next += static_cast<std::size_t>(bit);
      encoder.encode(used[a], bit);
    }
  }
  return encoder.finish();
}

bool decodeAtomSets(const std::string& bytes, std::size_t patches, std::uint32_t num_atoms, std::size_t max_atoms,
                    std::vector<std::vector<std::uint32_t>>& atoms)
{
  RangeDecoder decoder(bytes);
  std::vector<std::uint16_t> used(num_atoms, kHalfProbability);
  atoms.assign(patches, {});
  for (auto& list : atoms) {
    for (std::uint32_t a = 0; a < num_atoms; ++a)
      if (decoder.decode(used[a]))
        list.push_back(a);
    if (decoder.overrun() > 0 || list.size() > max_atoms)
      return false;
  }
  return decoder.exhausted();
}

std::string encodeCoefficients(const std::vector<std::vector<std::int32_t>>& values,
                               const std::vector<std::vector<std::uint32_t>>& atoms, std::uint32_t num_atoms)
{
  RangeEncoder encoder;
  CoefficientContexts contexts(num_atoms);
  if (values.size() != atoms.size())
    throw Error("coefficients and atom sets differ in length");
  for (std::size_t p = 0; p < values.size(); ++p) {
    if (values[p].size() != atoms[p].size())
      throw Error("a patch has another number of coefficients than atoms");
    for (std::size_t i = 0; i < values[p].size(); ++i) {
      const std::int32_t v = values[p][i];
      if (v == 0 || v > 32767 || v < -32767)
        throw Error("coefficients must be non-zero and within ±32767");
      const auto code = static_cast<std::uint32_t>(v < 0 ? -v : v) + 1;
      int length = 0;
      while ((code >> (length + 1)) != 0)
        ++length;
      for (int k = 0; k < kLengthBits - 1; ++k) {  // unary: 1 while the length goes on
        encoder.encode(contexts.length[static_cast<std::size_t>(k)], k < length ? 1 : 0);
        if (k >= length)
          break;
      }
      for (int k = length - 1; k >= 0; --k)
        encoder.encode(contexts.mantissa[static_cast<std::size_t>(length * kLengthBits + k)], (code >> k) & 1);
      encoder.encode(contexts.sign[atoms[p][i]], v < 0 ? 1 : 0);
    }
  }
  return encoder.finish();
}

bool decodeCoefficients(const std::string& bytes, const std::vector<std::vector<std::uint32_t>>& atoms,
                        std::uint32_t num_atoms, std::vector<std::vector<std::int32_t>>& values)
{
  RangeDecoder decoder(bytes);
  CoefficientContexts contexts(num_atoms);
  values.assign(atoms.size(), {});
  for (std::size_t p = 0; p < atoms.size(); ++p) {
    for (const std::uint32_t atom : atoms[p]) {
      int length = 0;
      while (length < kLengthBits - 1 && decoder.decode(contexts.length[static_cast<std::size_t>(length)]))
        ++length;
      std::uint32_t code = 1;
      for (int k = length - 1; k >= 0; --k)
        code = (code << 1) |
               static_cast<std::uint32_t>(decoder.decode(contexts.mantissa[static_cast<std::size_t>(length * kLengthBits + k)]));
      auto v = static_cast<std::int32_t>(code - 1);
      if (v == 0 || v > 32767)  // the codec stores non-zeros within ±32767 only
        return false;
      if (decoder.decode(contexts.sign[atom]))
        v = -v;
      values[p].push_back(v);
    }
    if (decoder.overrun() > 0)
      return false;
  }
  return decoder.exhausted();
}

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
