// A bounded, named FIFO between two stages. Reading an empty FIFO or writing a full one is an
// internal invariant violation (the scheduler consults plan() first) and aborts with the name.
#pragma once

#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

namespace parallax::sim {

template <class T>
class Fifo {
 public:
  Fifo(std::string name, std::size_t depth) : name_(std::move(name)), buf_(depth == 0 ? 1 : depth) {}
  Fifo(const Fifo&) = delete;
  Fifo& operator=(const Fifo&) = delete;

  bool empty() const { return count_ == 0; }
  bool full() const { return count_ == buf_.size(); }
  std::size_t size() const { return count_; }
  std::size_t depth() const { return buf_.size(); }
  std::size_t high_water() const { return high_water_; }
  const std::string& name() const { return name_; }
  void clear() { head_ = count_ = 0; }

  T read() {
    if (count_ == 0) fail("read from empty FIFO");
    T v = buf_[head_];
    if (++head_ == buf_.size()) head_ = 0;
    --count_;
    return v;
  }
  void write(const T& v) {
    if (count_ == buf_.size()) fail("write to full FIFO");
    std::size_t tail = head_ + count_;
    if (tail >= buf_.size()) tail -= buf_.size();
    buf_[tail] = v;
    if (++count_ > high_water_) high_water_ = count_;
  }

 private:
  [[noreturn]] void fail(const char* what) const {
    std::fprintf(stderr, "parallax: internal error: %s '%s' (depth %zu)\n", what, name_.c_str(), buf_.size());
    std::abort();
  }
  std::string name_;
  std::vector<T> buf_;
  std::size_t head_ = 0;
  std::size_t count_ = 0;
  std::size_t high_water_ = 0;
};

}  // namespace parallax::sim
