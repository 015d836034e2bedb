#pragma once
// Errors at I/O and API boundaries: exceptions carrying their context.
#include <stdexcept>
#include <string>

namespace nf {

// Raised for bad user input or a failing external API; `what()` names the file/API and the problem.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

[[noreturn]] inline void fail(const std::string& message) { throw Error(message); }

}  // namespace nf
