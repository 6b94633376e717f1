// pcl_patchdict::Error — the one exception type the library throws for bad input.
// Its message is a single line meant for the user (the CLI prints it as is and exits non-zero).
#pragma once

#include <stdexcept>
#include <string>

namespace pcl {
namespace patchdict {

class Error : public std::runtime_error {
public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace patchdict
}  // namespace pcl
