// The one base of every error the user can fix: a file, a field, a value or an option. Its
// message names what to fix and is printed as is (`parallax: error: MESSAGE`, exit status 2).
// Anything else that reaches the command line's top is a defect of Parallax (exit status 70).
#pragma once

#include <stdexcept>

namespace parallax {

class UserError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace parallax
