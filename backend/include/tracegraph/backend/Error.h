/// @file Error.h
/// The exception thrown by every Tracegraph API that rejects its input.
#pragma once

#include <stdexcept>
#include <string>

namespace tg {

/// Raised when an API call or a file is rejected. The message names the call (or the file and
/// line) and says what was wrong; the object the call was made on is left as it was.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace tg
