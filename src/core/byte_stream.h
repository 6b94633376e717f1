// Little-endian byte streams with LEB128 varints and zlib-packed sections: the one binary idiom of
// the .pds, .pdd, .pdk and .pdc formats (private to the library). Every read is bounds-checked and fails with one line.
#pragma once

#include <pcl_patchdict/core/error.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <utility>

namespace pcl {
namespace patchdict {
namespace detail {

class ByteWriter {
public:
  void putU8(std::uint8_t v) { bytes_.push_back(static_cast<char>(v)); }
  void putU32(std::uint32_t v) { putRaw(&v, sizeof v); }
  void putU64(std::uint64_t v) { putRaw(&v, sizeof v); }
  void putF64(double v) { putRaw(&v, sizeof v); }
  void putRaw(const void* data, std::size_t size) { bytes_.append(static_cast<const char*>(data), size); }
  /** Unsigned LEB128: 7 bits a byte, small numbers in one byte. */
  void putVarint(std::uint64_t v)
  {
    while (v >= 0x80) {
      putU8(static_cast<std::uint8_t>(v | 0x80));
      v >>= 7;
    }
    putU8(static_cast<std::uint8_t>(v));
  }
  /** Zigzag-mapped signed varint (0, −1, 1, −2, … → 0, 1, 2, 3, …). */
  void putSigned(std::int64_t v) { putVarint((static_cast<std::uint64_t>(v) << 1) ^ static_cast<std::uint64_t>(v >> 63)); }
  const std::string& bytes() const { return bytes_; }
  std::string& bytes() { return bytes_; }

private:
  std::string bytes_;
};

class ByteReader {
public:
  /** `what` names the data in error messages ("'x.pdc': ..."). */
  ByteReader(const char* data, std::size_t size, std::string what) : data_(data), size_(size), what_(std::move(what)) {}
  std::uint8_t getU8()
  {
    need(1);
    return static_cast<std::uint8_t>(data_[pos_++]);
  }
  std::uint32_t getU32() { return getPod<std::uint32_t>(); }
  std::uint64_t getU64() { return getPod<std::uint64_t>(); }
  double getF64() { return getPod<double>(); }
  void getRaw(void* out, std::size_t size)
  {
    need(size);
    std::memcpy(out, data_ + pos_, size);
    pos_ += size;
  }
  std::uint64_t getVarint()
  {
    std::uint64_t v = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      const std::uint8_t byte = getU8();
      v |= static_cast<std::uint64_t>(byte & 0x7f) << shift;
      if (!(byte & 0x80))
        return v;
    }
    throw Error(what_ + "malformed number");
  }
  std::int64_t getSigned()
  {
    const std::uint64_t v = getVarint();
    return static_cast<std::int64_t>(v >> 1) ^ -static_cast<std::int64_t>(v & 1);
  }
  std::size_t position() const { return pos_; }
  std::size_t remaining() const { return size_ - pos_; }
  bool atEnd() const { return pos_ == size_; }
  const std::string& what() const { return what_; }

private:
  template <typename T>
  T getPod()
  {
    T v;
    getRaw(&v, sizeof v);
    return v;
  }
  void need(std::size_t n) const
  {
    if (n > size_ - pos_)
      throw Error(what_ + "data is truncated");
  }
  const char* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
  std::string what_;
};

/** zlib (deflate, best compression) of `raw`. */
std::string deflateBytes(const std::string& raw);
/** Inverse of deflateBytes; `raw_size` is the size the writer recorded. Throws Error (prefixed with
  * `what`) for a size deflate cannot reach from `packed` (checked before allocating) or a corrupt stream. */
std::string inflateBytes(const std::string& packed, std::size_t raw_size, const std::string& what);

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
