#include <pcl_patchdict/core/checksum.h>

namespace pcl {
namespace patchdict {

std::uint64_t fnv1a64(const void* data, std::size_t size, std::uint64_t hash)
{
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= bytes[i];
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

}  // namespace patchdict
}  // namespace pcl
