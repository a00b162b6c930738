// Internal: the simulator's response to a broken invariant (a bug, never bad input: callers
// validate first). Prints the message and aborts.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>

namespace parallax::sim::detail {

[[noreturn]] inline void internal_error(const std::string& what) {
  std::fprintf(stderr, "parallax: internal error: %s\n", what.c_str());
  std::abort();
}

}  // namespace parallax::sim::detail
