// Context-modelled binary arithmetic coding of observation masks (see mask_coding.h).
#include "codec/mask_coding.h"

#include "codec/range_coder.h"

#include <array>
#include <cstdint>

namespace pcl {
namespace patchdict {
namespace detail {

namespace {

using Contexts = std::array<std::uint16_t, 64>;

Contexts freshContexts()
{
  Contexts contexts;
  contexts.fill(kHalfProbability);
  return contexts;
}

/** Six causal neighbours of bin (row, col) as a 6-bit context. */
int context(const std::vector<char>& mask, int grid, int row, int col)
{
  const auto at = [&](int r, int c) { return r >= 0 && c >= 0 && c < grid && mask[static_cast<std::size_t>(r * grid + c)] ? 1 : 0; };
  return at(row, col - 1) | (at(row - 1, col - 1) << 1) | (at(row - 1, col) << 2) | (at(row - 1, col + 1) << 3) |
         (at(row, col - 2) << 4) | (at(row - 2, col) << 5);
}

}  // namespace

std::string encodeMasks(const std::vector<std::vector<char>>& masks, int grid)
{
  RangeEncoder encoder;
  Contexts contexts = freshContexts();
  for (const auto& mask : masks)
    for (int row = 0; row < grid; ++row)
      for (int col = 0; col < grid; ++col)
        encoder.encode(contexts[static_cast<std::size_t>(context(mask, grid, row, col))],
                       mask[static_cast<std::size_t>(row * grid + col)] ? 1 : 0);
  return encoder.finish();
}

bool decodeMasks(const std::string& bytes, std::size_t count, int grid, std::vector<std::vector<char>>& masks)
{
  RangeDecoder decoder(bytes);
  Contexts contexts = freshContexts();
  masks.assign(count, std::vector<char>(static_cast<std::size_t>(grid) * static_cast<std::size_t>(grid), 0));
  for (auto& mask : masks)
    for (int row = 0; row < grid; ++row)
      for (int col = 0; col < grid; ++col) {
        const int bit = decoder.decode(contexts[static_cast<std::size_t>(context(mask, grid, row, col))]);
        mask[static_cast<std::size_t>(row * grid + col)] = static_cast<char>(bit);
        if (decoder.overrun() > 0)  // the encoder's flush covers every bit it coded
          return false;
      }
  return decoder.exhausted();
}

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
