// The .pdc file of a compressed surface: PatchCodec's bytes, written and read whole.
#include <pcl_patchdict/core/atomic_file.h>
#include <pcl_patchdict/io/patch_codec_io.h>

namespace pcl {
namespace patchdict {

void saveCompressedMesh(const std::string& path, const PatchCodec& codec, const TriangleMesh& mesh,
                        PatchCodec::Report* report)
{
  writeFileAtomically(path, codec.encode(mesh, report));
}

void loadCompressedMesh(const std::string& path, const PatchCodec& codec, TriangleMesh& out, PatchCodec::Report* report)
{
  codec.decode(readWholeFile(path), out, report, "'" + path + "': ");
}

}  // namespace patchdict
}  // namespace pcl
