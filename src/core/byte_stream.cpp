// zlib sections of the .pdc format.
#include "core/byte_stream.h"

#include <zlib.h>

namespace pcl {
namespace patchdict {
namespace detail {

std::string deflateBytes(const std::string& raw)
{
  uLongf packed_size = compressBound(static_cast<uLong>(raw.size()));
  std::string packed(packed_size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(&packed[0]), &packed_size, reinterpret_cast<const Bytef*>(raw.data()),
                static_cast<uLong>(raw.size()), Z_BEST_COMPRESSION) != Z_OK)
    throw Error("deflate failed");
  packed.resize(packed_size);
  return packed;
}

std::string inflateBytes(const std::string& packed, std::size_t raw_size, const std::string& what)
{
  // Deflate expands at most ~1032:1; a larger declared size is a corrupt header, not a reason to allocate.
  if (raw_size > 1100 * packed.size() + 64)
    throw Error(what + "implausible section size (the file is corrupted)");
  if (raw_size == 0)
    return std::string();
  std::string raw(raw_size, '\0');
  uLongf size = static_cast<uLongf>(raw_size);
  const int status = uncompress(reinterpret_cast<Bytef*>(&raw[0]), &size,
                                reinterpret_cast<const Bytef*>(packed.data()), static_cast<uLong>(packed.size()));
  if (status != Z_OK || size != raw_size)
    throw Error(what + "corrupted compressed section");
  return raw;
}

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
