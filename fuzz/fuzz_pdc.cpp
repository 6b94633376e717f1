// libFuzzer target: the .pdc decoder (PatchCodec::decode) with the small dictionary the seed corpus
// was encoded with (fuzz/pdc_dictionary.pdd): container, zlib sections, and the reconstruction
// they drive.
#include "fuzz_common.h"

#include <pcl_patchdict/codec/patch_codec.h>
#include <pcl_patchdict/io/patch_dictionary_io.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  static const pcl::patchdict::PatchCodec codec = [] {
    pcl::patchdict::PatchCodec c;
    c.setDictionary(pcl::patchdict::loadPatchDictionary(PCL_PATCHDICT_FUZZ_DIR "/pdc_dictionary.pdd"));
    pcl::patchdict::PatchCodecParameters parameters;
    parameters.num_threads = 1;
    c.setParameters(parameters);
    return c;
  }();
  pcl::patchdict::TriangleMesh mesh;
  try {
    codec.decode(fuzz::withValidChecksum(data, size), mesh);
  }
  catch (const pcl::patchdict::Error&) {
    return 0;
  }
  fuzz::checkMesh(mesh);
  return 0;
}
