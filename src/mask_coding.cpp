// Context-modelled binary arithmetic coding of observation masks (see mask_coding.h).
#include "mask_coding.h"

#include <array>
#include <cstdint>

namespace pcl {
namespace patchdict {
namespace detail {

namespace {

constexpr int kProbabilityBits = 11, kMoveBits = 4;
constexpr std::uint32_t kTop = 1u << 24;
using Contexts = std::array<std::uint16_t, 64>;

Contexts freshContexts()
{
  Contexts contexts;
  contexts.fill(1u << (kProbabilityBits - 1));  // one half
  return contexts;
}

/** Six causal neighbours of bin (row, col) as a 6-bit context. */
int context(const std::vector<char>& mask, int grid, int row, int col)
{
  const auto at = [&](int r, int c) { return r >= 0 && c >= 0 && c < grid && mask[static_cast<std::size_t>(r * grid + c)] ? 1 : 0; };
  return at(row, col - 1) | (at(row - 1, col - 1) << 1) | (at(row - 1, col) << 2) | (at(row - 1, col + 1) << 3) |
         (at(row, col - 2) << 4) | (at(row - 2, col) << 5);
}

class RangeEncoder {
public:
  void encode(std::uint16_t& probability, int bit)
  {
    const std::uint32_t bound = (range_ >> kProbabilityBits) * probability;
    if (!bit) {
      range_ = bound;
      probability = static_cast<std::uint16_t>(probability + (((1u << kProbabilityBits) - probability) >> kMoveBits));
    } else {
      low_ += bound;
      range_ -= bound;
      probability = static_cast<std::uint16_t>(probability - (probability >> kMoveBits));
    }
    while (range_ < kTop) {
      range_ <<= 8;
      shiftLow();
    }
  }
  std::string finish()
  {
    for (int i = 0; i < 5; ++i)
      shiftLow();
    return out_;
  }

private:
  void shiftLow()
  {
    if (static_cast<std::uint32_t>(low_) < 0xFF000000u || (low_ >> 32) != 0) {
      const auto carry = static_cast<std::uint8_t>(low_ >> 32);
      std::uint8_t byte = cache_;
      do {
        out_.push_back(static_cast<char>(static_cast<std::uint8_t>(byte + carry)));
        byte = 0xFF;
      } while (--pending_ != 0);
      cache_ = static_cast<std::uint8_t>(low_ >> 24);
    }
    ++pending_;
    low_ = (low_ & 0x00FFFFFFu) << 8;
  }

  std::uint64_t low_ = 0;
  std::uint32_t range_ = 0xFFFFFFFFu;
  std::uint8_t cache_ = 0;
  std::uint64_t pending_ = 1;
  std::string out_;
};

class RangeDecoder {
public:
  explicit RangeDecoder(const std::string& bytes) : bytes_(bytes)
  {
    for (int i = 0; i < 5; ++i)
      code_ = (code_ << 8) | next();
  }
  int decode(std::uint16_t& probability)
  {
    const std::uint32_t bound = (range_ >> kProbabilityBits) * probability;
    int bit;
    if (code_ < bound) {
      range_ = bound;
      probability = static_cast<std::uint16_t>(probability + (((1u << kProbabilityBits) - probability) >> kMoveBits));
      bit = 0;
    } else {
      code_ -= bound;
      range_ -= bound;
      probability = static_cast<std::uint16_t>(probability - (probability >> kMoveBits));
      bit = 1;
    }
    while (range_ < kTop) {
      range_ <<= 8;
      code_ = (code_ << 8) | next();
    }
    return bit;
  }
  std::size_t overrun() const { return overrun_; }

private:
  std::uint32_t next()
  {
    if (position_ < bytes_.size())
      return static_cast<std::uint8_t>(bytes_[position_++]);
    ++overrun_;
    return 0;
  }

  const std::string& bytes_;
  std::size_t position_ = 0, overrun_ = 0;
  std::uint32_t range_ = 0xFFFFFFFFu, code_ = 0;
};

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
        if (decoder.overrun() > 4)  // the encoder's flush covers every bit it coded
          return false;
      }
  return true;
}

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
