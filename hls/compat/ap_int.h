// Parallax's stand-in for the Vitis HLS header of the same name, so that exported projects build
// and run their C simulation with g++ alone when Vitis is not installed. It covers what exported
// code uses: ap_uint<W> / ap_int<W> for W in [1, 64], constructed from and converted to built-in
// integers (implicitly, or with to_uint / to_int / to_uint64 / to_int64), with the value wrapped
// to W bits as the vendor's types do. Arithmetic happens in the built-in types after conversion.
// With Vitis present the Makefile uses the vendor's header instead.
#pragma once

#include <stdint.h>

namespace parallax_compat {

template <int W>
struct ap_bits {
  static_assert(W >= 1 && W <= 64, "this ap_int.h stand-in supports widths 1 to 64");
  static constexpr uint64_t mask = W == 64 ? ~uint64_t(0) : ((uint64_t(1) << (W == 64 ? 0 : W)) - 1u);
  // Two's complement value of the low W bits.
  static constexpr int64_t sign_extend(uint64_t v) {
    return W == 64 ? int64_t(v) : ((v >> (W - 1)) & 1u) ? int64_t(v | ~mask) : int64_t(v);
  }
};

}  // namespace parallax_compat

template <int W>
class ap_uint {
 public:
  static const int width = W;
  ap_uint() : v_(0) {}
  ap_uint(bool v) : v_(v ? 1u : 0u) {}
  ap_uint(int v) : v_(uint64_t(int64_t(v)) & parallax_compat::ap_bits<W>::mask) {}
  ap_uint(unsigned v) : v_(uint64_t(v) & parallax_compat::ap_bits<W>::mask) {}
  ap_uint(long v) : v_(uint64_t(int64_t(v)) & parallax_compat::ap_bits<W>::mask) {}
  ap_uint(unsigned long v) : v_(uint64_t(v) & parallax_compat::ap_bits<W>::mask) {}
  ap_uint(long long v) : v_(uint64_t(v) & parallax_compat::ap_bits<W>::mask) {}
  ap_uint(unsigned long long v) : v_(uint64_t(v) & parallax_compat::ap_bits<W>::mask) {}
  template <int W2>
  ap_uint(const ap_uint<W2>& o) : v_(o.to_uint64() & parallax_compat::ap_bits<W>::mask) {}

  operator unsigned long long() const { return v_; }
  unsigned to_uint() const { return unsigned(v_); }
  int to_int() const { return int(v_); }
  uint64_t to_uint64() const { return v_; }
  int64_t to_int64() const { return int64_t(v_); }
  static int length() { return W; }

 private:
  uint64_t v_;
};

template <int W>
class ap_int {
 public:
  static const int width = W;
  ap_int() : v_(0) {}
  ap_int(int v) : v_(wrap(int64_t(v))) {}
  ap_int(unsigned v) : v_(wrap(int64_t(v))) {}
  ap_int(long v) : v_(wrap(int64_t(v))) {}
  ap_int(long long v) : v_(wrap(int64_t(v))) {}
  ap_int(unsigned long long v) : v_(wrap(int64_t(v))) {}

  operator long long() const { return v_; }
  unsigned to_uint() const { return unsigned(v_); }
  int to_int() const { return int(v_); }
  uint64_t to_uint64() const { return uint64_t(v_); }
  int64_t to_int64() const { return v_; }
  static int length() { return W; }

 private:
  static int64_t wrap(int64_t v) {
    return parallax_compat::ap_bits<W>::sign_extend(uint64_t(v) & parallax_compat::ap_bits<W>::mask);
  }
  int64_t v_;
};
