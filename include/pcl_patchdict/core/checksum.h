// The checksum of the project's binary formats (.pds, .pdd, .pdk, .pdc): 64-bit FNV-1a
// (Fowler, Noll & Vo) over a byte range.
#pragma once

#include <cstddef>
#include <cstdint>

namespace pcl {
namespace patchdict {

/** 64-bit FNV-1a of a byte range, continuing from `hash` (the FNV offset basis by default). */
std::uint64_t fnv1a64(const void* data, std::size_t size, std::uint64_t hash = 0xcbf29ce484222325ULL);

}  // namespace patchdict
}  // namespace pcl
