// The .pdc file of a compressed surface: PatchCodec::encode's bytes written atomically, and read
// back through PatchCodec::decode (the bytes themselves are the codec's range-coded sections).
#pragma once

#include <pcl_patchdict/codec/patch_codec.h>

#include <string>

namespace pcl {
namespace patchdict {

/** codec.encode(mesh) written to `path` atomically (core/atomic_file.h). */
void saveCompressedMesh(const std::string& path, const PatchCodec& codec, const TriangleMesh& mesh,
                        PatchCodec::Report* report = nullptr);

/** codec.decode of the file's bytes, errors prefixed with the file's name. */
void loadCompressedMesh(const std::string& path, const PatchCodec& codec, TriangleMesh& out,
                        PatchCodec::Report* report = nullptr);

}  // namespace patchdict
}  // namespace pcl
