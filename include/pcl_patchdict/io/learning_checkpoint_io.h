// The .pdk checkpoint file of streamed online learning (LearningCheckpoint): every field in order,
// little-endian, checksummed; written atomically, so a resumed run continues bit for bit.
#pragma once

#include <pcl_patchdict/coding/learning_checkpoint.h>

#include <string>

namespace pcl {
namespace patchdict {

/** The bytes of a .pdk file: magic "PCLPDK\0\x1a", version, then the checkpoint's fields in order
  * (strings and matrices with their sizes first), then FNV-1a 64 of everything before it. */
std::string formatLearningCheckpoint(const LearningCheckpoint& checkpoint);

/** A checkpoint from the bytes of a .pdk file (version 2, or 1: before shards). A truncated,
  * corrupted or foreign file, or one of another version, is rejected with one line (Error), every
  * size checked against the bytes left before allocating; `name` is what error messages call it. */
LearningCheckpoint parseLearningCheckpoint(const std::string& bytes, const std::string& name = "<memory>");

/** formatLearningCheckpoint written atomically (core/atomic_file.h). */
void saveLearningCheckpoint(const std::string& path, const LearningCheckpoint& checkpoint);

/** parseLearningCheckpoint of the file's bytes. */
LearningCheckpoint loadLearningCheckpoint(const std::string& path);

}  // namespace patchdict
}  // namespace pcl
