// The element types the kernels keep values in between firings (their memories and register
// files), and the width an element type stores. C++14.
//
// Software instantiations store in the built-in integers their arithmetic uses (HostStore): the
// 16- or 32-bit aggregation word for path costs and sums, 16 bits for matching costs and
// disparity codes. The HLS export stores at the widths the resource model prices
// (parallax_config.hpp: DesignStore, ap_uint<bits>), so a memory of PU path costs is PU x
// path_bits wide in the RTL as in the model (issue 41, N6). Arithmetic stays in the built-in
// types: a kernel reads an element with from_store<W>() and writes it by assignment (the value
// always fits the stored width: docs/algorithm.md bounds each quantity, and the exported C
// simulation's bit-exact comparison would show a truncation).
//
// stored_bits<M>() is the width of one element of a member M (a built-in integer, an ap_uint, an
// array of either, or a counted or shift-register stand-in of one): the exported C simulation
// compares it with the width each storage descriptor declares (StorageWidths, parallax_top.cpp).
#pragma once

#include <stdint.h>

#include "parallax/kernels/common.hpp"

namespace parallax {
namespace kern {

// Software element types. Word is the aggregation word of the instantiation (sgm.hpp).
struct HostStore {
  typedef uint16_t cost;       // a matching cost (cost_bits)
  typedef uint16_t code;       // a disparity code (disparity_bits)
  typedef uint64_t census;     // a census code (census_bits)
  typedef uint16_t disparity;  // an integer disparity of the WTA (disparity_int_bits)
  // An aggregated cost or the mark of none, above every cost (aggregate_bits + 1): the WTA's open
  // right candidates.
  typedef uint32_t sum_or_none;
  template <class Word>
  struct path {  // a path cost Lr or its minimum (path_bits)
    typedef Word type;
  };
  template <class Word>
  struct sum {  // an aggregated cost S (aggregate_bits)
    typedef Word type;
  };
};

namespace store_detail {
template <class...>
struct VoidOf {
  typedef void type;
};
}  // namespace store_detail

// Bits of one element of T. Built-in integers: their size (bool: 1); types with a static `width`
// (ap_uint, ap_int): that width; arrays: their element's; stand-ins that name an `element_type`
// (the counted arrays and shift registers): that type's.
template <class T, class = void>
struct StoredBits {
  static constexpr int value = int(8 * sizeof(T));
};
template <>
struct StoredBits<bool, void> {
  static constexpr int value = 1;
};
template <class T>
struct StoredBits<T, typename store_detail::VoidOf<decltype(T::width)>::type> {
  static constexpr int value = int(T::width);
};
template <class T>
struct StoredBits<T, typename store_detail::VoidOf<typename T::element_type>::type> {
  static constexpr int value = StoredBits<typename T::element_type>::value;
};
template <class T, int N>
struct StoredBits<T[N], void> {
  static constexpr int value = StoredBits<T>::value;
};
template <class T, int N>
struct StoredBits<const T[N], void> {
  static constexpr int value = StoredBits<T>::value;
};

template <class M>
constexpr int stored_bits(const M&) {
  return StoredBits<M>::value;
}

// The value of a stored element (a plain element; access_count.hpp overloads the counted one).
template <class T>
PX_INLINE const T& store_value(const T& v) {
  return v;
}
// A stored element read as the built-in type W of the kernel's arithmetic.
template <class W, class S>
PX_INLINE W from_store(const S& s) {
  return W(store_value(s));
}

}  // namespace kern
}  // namespace parallax
