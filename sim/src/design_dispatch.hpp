// Internal: which instantiation of the engine runs a design. The engine's lane capacity (Caps)
// and path-sum word (Word) are template parameters, so every run maps the design's figures to
// one instantiation here: dispatch_design() is the only place that does, for every caller.
#pragma once

#include <cstdint>
#include <string>
#include <utility>

#include "internal_error.hpp"
#include "parallax/kernels/caps.hpp"

namespace parallax::sim::detail {

using TinyCaps = kern::Caps<kern::kMaxWidthPx, kern::kMaxDisparities, 8>;  // PU <= 8: 16-byte tokens
// The timing run's tokens carry no payload; one lane keeps the FIFOs' rings small.
using ControlCaps = kern::Caps<kern::kMaxWidthPx, kern::kMaxDisparities, 1>;
using NarrowCaps = kern::Caps<kern::kMaxWidthPx, kern::kMaxDisparities, 64>;
using WideCaps = kern::Caps<kern::kMaxWidthPx, kern::kMaxDisparities, 256>;

// The instantiation dispatch_design() chose, as a type.
template <class C, class W>
struct Design {
  using Caps = C;
  using Word = W;
};

// Calls f(Design<Caps, Word>{}) and returns what f returns: Caps is the first capacity of the
// list (narrowest first) whose lanes hold `lanes`, Word uint16_t when the path sums fit in
// word_bits <= 16 bits, else uint32_t. f is a generic lambda; every capacity x word of the list
// is instantiated. Callers validate the design first (func_param_errors): lanes beyond the
// widest capacity are an internal error.
template <class Caps, class... Wider, class F>
decltype(auto) dispatch_design(int lanes, int word_bits, F&& f) {
  if constexpr (sizeof...(Wider) > 0) {
    if (lanes > Caps::lanes) return dispatch_design<Wider...>(lanes, word_bits, std::forward<F>(f));
  } else if (lanes > Caps::lanes) {
    internal_error("no engine carries " + std::to_string(lanes) + " lanes");
  }
  if (word_bits <= 16) return f(Design<Caps, uint16_t>{});
  return f(Design<Caps, uint32_t>{});
}

}  // namespace parallax::sim::detail
