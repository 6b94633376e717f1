// Adaptive binary range coder (the LZMA coder, I. Pavlov): the entropy coder of the .pdc sections
// that version 3 codes bit by bit (masks, atom sets, coefficients).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace pcl {
namespace patchdict {
namespace detail {

/** 11-bit probabilities of a 0, adapted by 1/16 of the distance after each bit. */
constexpr int kProbabilityBits = 11, kMoveBits = 4;
constexpr std::uint16_t kHalfProbability = 1u << (kProbabilityBits - 1);
constexpr std::uint32_t kTop = 1u << 24;

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
  /** Bytes read past the end (as zeros); the encoder's flush covers every bit it coded, so more
    * than a few mean the stream was cut or asked for more than it holds. */
  std::size_t overrun() const { return overrun_; }
  /** True when the decoder read exactly the bytes the encoder wrote (its flush is read back in
    * full, nothing is left over): a cut or padded stream is not. */
  bool exhausted() const { return overrun_ == 0 && position_ == bytes_.size(); }

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


}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
