// The bunny and its stored local dictionary, which the codec tests share (test_patch_codec.cpp,
// test_patch_codec_errors.cpp).
#pragma once

#include <pcl_patchdict/codec/patch_codec.h>
#include <pcl_patchdict/coding/patch_dictionary.h>
#include <pcl_patchdict/core/triangle_mesh.h>
#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict/io/patch_dictionary_io.h>

#include "test_support.h"

#include <string>

namespace codec_test {

using namespace pcl::patchdict;

inline TriangleMesh loadBunny()
{
  TriangleMesh bunny;
  readMesh(test_support::dataDir() + "/bunny.obj", bunny);
  return bunny;
}

inline std::string bunnyDictionaryPath() { return test_support::testDataDir() + "/bunny_local48.pdd"; }

/** learnBunnyDictionary(bunny, 1) as stored in test/data, so that the codec tests do not each learn
  * it again; FixtureDictionaryIsTheBunnysOwn learns it once (1.8 s, 23.8 s under the sanitizers,
  * learning and checking), checks the fixture and rewrites it with PCL_PATCHDICT_WRITE_FIXTURES=1. */
inline PatchDictionary::Ptr bunnyDictionary() { return loadPatchDictionary(bunnyDictionaryPath(), 16); }

/** A codec with bunnyDictionary(), its parameters still the defaults (the test gives them). */
inline PatchCodec bunnyCodec()
{
  PatchCodec codec;
  codec.setDictionary(bunnyDictionary());
  return codec;
}

inline PatchCodecParameters bunnyParameters()
{
  PatchCodecParameters parameters;
  parameters.quad_length = 0.064;  // patch side 0.08
  parameters.coefficients = 12;
  return parameters;
}

}  // namespace codec_test
