// The error type for bad user input (data files, dataset folders, arguments).
#pragma once

#include "parallax/config/user_error.hpp"

namespace parallax::eval {

// Any problem with the user's input data or arguments (missing or unreadable file, size
// mismatch, unknown layout, bad frame filter, bad ROI, malformed calibration). The message names
// the file (and the field or line) or the argument and the problem, ready to be printed as is.
class InputError : public UserError {
 public:
  using UserError::UserError;
};

}  // namespace parallax::eval
