// Helpers shared by the project's binary formats (.pds, .pdd, .pdk, .pdc; all written and read through core/byte_stream.h): private to the library.
#pragma once

#include <cstdint>
#include <cstring>

namespace pcl {
namespace patchdict {
namespace detail {

/** The formats are little-endian on disk and written from memory as they are. */
inline bool isLittleEndian()
{
  const std::uint16_t one = 1;
  std::uint8_t first;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
