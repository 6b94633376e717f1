// libFuzzer target: the .pdk checkpoint reader (parseLearningCheckpoint) and the state checks
// a resumed run applies to what it read (OnlineDictionaryLearner / PatchShuffleBuffer::setState).
#include "fuzz_common.h"

#include <pcl_patchdict/coding/learning_checkpoint.h>
#include <pcl_patchdict/io/learning_checkpoint_io.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  using namespace pcl::patchdict;
  LearningCheckpoint checkpoint;
  try {
    checkpoint = parseLearningCheckpoint(fuzz::withValidChecksum(data, size));
  }
  catch (const Error&) {
    return 0;
  }
  if (checkpoint.next_input > checkpoint.num_inputs || !checkpoint.learner.dictionary.allFinite() ||
      checkpoint.buffer.buffered.rows() != checkpoint.buffer.buffered_mask.rows() ||
      checkpoint.buffer.buffered.cols() != checkpoint.buffer.buffered_mask.cols())
    fuzz::fail("an accepted checkpoint is inconsistent");
  const OnlineLearningParameters& parameters = checkpoint.learner.parameters;
  if (parameters.num_atoms < 1 || parameters.num_atoms > 4096 || parameters.sparsity < 1 || parameters.batch_size < 1 ||
      parameters.batch_size > (1 << 20))
    return 0;
  try {
    OnlineDictionaryLearner learner(parameters);
    learner.setState(checkpoint.learner);
    PatchShuffleBuffer buffer(static_cast<std::size_t>(checkpoint.buffer.buffered.cols()) + 1,
                              parameters.batch_size, parameters.seed);
    buffer.setState(checkpoint.buffer);
    if (learner.dictionary().size() != 0 && learner.dictionary().cols() != parameters.num_atoms)
      fuzz::fail("a restored learner has another number of atoms");
  }
  catch (const Error&) {
  }
  return 0;
}
