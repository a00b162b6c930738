// A bounded, named FIFO between two stages, optionally timed. Reading an empty FIFO or writing a
// full one is an internal invariant violation (the scheduler consults plan() first) and aborts
// with the FIFO's name.
//
// Timed mode (the cycle model) keeps, per slot, the cycle at which the token becomes visible to
// the consumer and the cycle at which it was read; the scheduler sets the stamps before a firing.
// A stage of latency L that fires at cycle t puts its token into the FIFO at t + L, where it is
// visible to the consumer; a slot freed by a read at cycle r can take a token from r + 1 on.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

namespace parallax::sim {

// The type-independent part: occupancy, counters and timing, what the scheduler looks at.
class FifoBase {
 public:
  // depth 0 = unbounded (grows on demand), used to size FIFOs.
  FifoBase(std::string name, std::size_t depth, bool timed) : name_(std::move(name)), depth_(depth), timed_(timed) {}
  FifoBase(const FifoBase&) = delete;
  FifoBase& operator=(const FifoBase&) = delete;

  bool empty() const { return count_ == 0; }
  bool full() const { return depth_ != 0 && count_ == depth_; }
  std::size_t size() const { return count_; }
  std::size_t depth() const { return depth_; }
  const std::string& name() const { return name_; }
  int64_t writes() const { return writes_; }
  int64_t reads() const { return reads_; }
  // Most tokens held at once: in timed mode over time (cycles), in func mode over the schedule.
  std::size_t high_water() const { return high_water_; }

  // Timed mode: cycle at which the head token is visible (requires !empty()).
  int64_t head_visible() const { return visible_[head_]; }
  // Timed mode: first cycle at which the next write fits (requires !full()).
  int64_t next_write_free() const {
    if (depth_ == 0 || writes_ < int64_t(depth_)) return 0;
    return read_at_[tail_slot()] + 1;
  }
  void stamp(int64_t read_cycle, int64_t write_visible_cycle) {
    read_cycle_ = read_cycle;
    write_visible_ = write_visible_cycle;
  }
  // Timed mode: visible cycle of the last token written, and read cycle of the last token read.
  int64_t last_write_visible() const { return last_visible_; }
  int64_t last_read_cycle() const { return last_read_; }

  // Timed-state access for the periodic fast-forward of the cycle model (fast_forward.hpp):
  // visit(v) calls v(field) on every counter and scalar time by reference; slot_times() appends
  // the times that future firings can still read, in token order (the live tokens' visible
  // cycles, then the read cycles from the oldest token occupancy tracking or the next write's
  // slot may consult); shift_slot_times(dt) adds dt to every slot's times.
  template <class V>
  void visit(V& v) {
    v(count_);
    v(high_water_);
    v(writes_);
    v(reads_);
    v(counted_reads_);
    v(read_cycle_);
    v(write_visible_);
    v(last_visible_);
    v(last_read_);
  }
  void slot_times(std::vector<int64_t>& out) const {
    for (std::size_t k = 0; k < count_; ++k) {
      const std::size_t s = head_ + k;
      out.push_back(visible_[s >= capacity_ ? s - capacity_ : s]);
    }
    int64_t oldest = counted_reads_;
    if (depth_ != 0 && writes_ - int64_t(depth_) < oldest) oldest = std::max<int64_t>(0, writes_ - int64_t(depth_));
    for (int64_t token = oldest; token < reads_; ++token) out.push_back(read_time_of(token));
  }
  void shift_slot_times(int64_t dt) {
    for (auto& t : visible_) t += dt;
    for (auto& t : read_at_) t += dt;
  }

 protected:
  [[noreturn]] void fail(const char* what) const {
    std::fprintf(stderr, "parallax: internal error: %s '%s' (depth %zu)\n", what, name_.c_str(), depth_);
    std::abort();
  }
  std::size_t capacity() const { return capacity_; }
  std::size_t tail_slot() const {
    std::size_t t = head_ + count_;
    return t >= capacity() ? t - capacity() : t;
  }
  // Book-keeping of one write into slot s (called by Fifo<T>::write).
  [[gnu::always_inline]] void on_write(std::size_t s) {
    if (timed_) {
      visible_[s] = write_visible_;
      last_visible_ = write_visible_;
    }
    ++writes_;
    ++count_;
    if (!timed_ && count_ > high_water_) high_water_ = count_;
  }
  // Book-keeping of one read of the head slot (called by Fifo<T>::read before advancing).
  [[gnu::always_inline]] void on_read() {
    if (timed_) {
      track_occupancy();  // before this slot's read time (token k - depth's) is overwritten
      read_at_[head_] = read_cycle_;
      last_read_ = read_cycle_;
    }
    ++reads_;
    if (++head_ == capacity()) head_ = 0;
    --count_;
  }
  // Slots in the ring (set by Fifo<T>); timed mode keeps two times per slot.
  void set_capacity(std::size_t n) {
    capacity_ = n;
    if (timed_) {
      visible_.resize(n);
      read_at_.resize(n);
    }
  }

  std::string name_;
  std::size_t depth_;
  bool timed_;
  std::size_t capacity_ = 0;
  std::size_t head_ = 0;
  std::size_t count_ = 0;
  std::size_t high_water_ = 0;
  int64_t writes_ = 0, reads_ = 0;
  int64_t read_cycle_ = 0, write_visible_ = 0;
  int64_t last_visible_ = 0, last_read_ = 0;
  std::vector<int64_t> visible_;  // per slot: cycle the token becomes visible
  std::vector<int64_t> read_at_;  // per slot: cycle the token was read

 private:
  // Occupancy over time, evaluated when token k (the head) becomes visible: tokens 0..k are
  // present except those read before that cycle. Reads are monotone, so a pointer suffices;
  // it never lags by more than the occupancy, which the slot ring holds.
  [[gnu::always_inline]] void track_occupancy() {
    const int64_t k = reads_;
    const int64_t vis = visible_[head_];
    while (counted_reads_ < k && read_time_of(counted_reads_) + 1 <= vis) ++counted_reads_;
    const std::size_t occ = std::size_t(k + 1 - counted_reads_);
    if (occ > high_water_) high_water_ = occ;
  }
  int64_t read_time_of(int64_t token) const {  // token in [reads_ - (capacity - count_), reads_)
    // Token j sits in the slot that is (reads_ - j) slots behind the head.
    const std::size_t back = std::size_t(reads_ - token);
    return read_at_[head_ >= back ? head_ - back : head_ + capacity() - back];
  }
  int64_t counted_reads_ = 0;
};

template <class T>
class Fifo : public FifoBase {
 public:
  Fifo(std::string name, std::size_t depth, bool timed = false) : FifoBase(std::move(name), depth, timed) {
    buf_.resize(depth == 0 ? 64 : depth);
    set_capacity(buf_.size());
  }

  [[gnu::always_inline]] T read() {
    if (count_ == 0) fail("read from empty FIFO");
    T v = buf_[head_];
    on_read();
    return v;
  }
  [[gnu::always_inline]] void write(const T& v) {
    if (full()) fail("write to full FIFO");
    if (count_ == buf_.size()) grow();
    const std::size_t s = tail_slot();
    buf_[s] = v;
    on_write(s);
  }
  // The timing run moves tokens without payload: occupancy, counters and times as read() and
  // write() keep them, the slot's value untouched.
  [[gnu::always_inline]] void skip_read() {
    if (count_ == 0) fail("read from empty FIFO");
    on_read();
  }
  [[gnu::always_inline]] void skip_write() {
    if (full()) fail("write to full FIFO");
    if (count_ == buf_.size()) grow();
    on_write(tail_slot());
  }

 private:
  // Unbounded FIFOs double their ring when full. The live tokens move to [n, 2n) with the head
  // at n; the read times of the tokens just behind the head move to [0, n), where occupancy
  // tracking looks for them (read_at_ is only overwritten by reads, never by writes).
  [[gnu::noinline]] void grow() {
    const std::size_t n = buf_.size();
    std::vector<T> b(2 * n);
    std::vector<int64_t> vis(timed_ ? 2 * n : 0), rd(timed_ ? 2 * n : 0);
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t from = (head_ + i) % n;
      b[n + i] = buf_[from];
      if (timed_) {
        vis[n + i] = visible_[from];
        rd[n - 1 - i] = read_at_[(head_ + n - 1 - i) % n];
      }
    }
    buf_.swap(b);
    capacity_ = 2 * n;
    if (timed_) {
      visible_.swap(vis);
      read_at_.swap(rd);
    }
    head_ = n;
  }
  std::vector<T> buf_;
};

}  // namespace parallax::sim
