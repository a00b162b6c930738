// Parallax's stand-in for the Vitis HLS header of the same name (see ap_int.h here): hls::stream
// for C simulation with g++. As in the vendor's C simulation, a stream is an unbounded queue and
// the functions of a DATAFLOW region run one after the other, each to completion; the STREAM
// depth pragmas matter only in hardware. Reading an empty stream, or a stream left holding
// tokens when it is destroyed, is a fatal error naming the stream: in this sequential model
// either means a producer and its consumer disagree on the token count.
//
// Built with PARALLAX_HLS_SUBSET_CHECK, the class only declares its members and has no storage:
// an object file of the synthesisable code then shows which symbols that code itself needs
// (the export's check for heap, recursion and standard containers).
#pragma once

#include <stddef.h>

#if !defined(PARALLAX_HLS_SUBSET_CHECK)
#include <deque>
#include <stdio.h>
#include <stdlib.h>
#include <string>
#endif

namespace hls {

template <class T, int DEPTH = 0>
class stream {
 public:
  stream();
  explicit stream(const char* name);
  ~stream();
  T read();
  void read(T& out);
  bool read_nb(T& out);
  void write(const T& v);
  bool write_nb(const T& v);
  bool empty() const;
  bool full() const;
  size_t size() const;
  void operator>>(T& out) { read(out); }
  void operator<<(const T& v) { write(v); }

#if !defined(PARALLAX_HLS_SUBSET_CHECK)
 private:
  stream(const stream&);
  stream& operator=(const stream&);
  std::deque<T> q_;
  std::string name_;
#endif
};

#if !defined(PARALLAX_HLS_SUBSET_CHECK)
template <class T, int DEPTH>
stream<T, DEPTH>::stream() : name_("(unnamed)") {}
template <class T, int DEPTH>
stream<T, DEPTH>::stream(const char* name) : name_(name) {}
template <class T, int DEPTH>
stream<T, DEPTH>::~stream() {
  if (!q_.empty()) {
    fprintf(stderr, "hls::stream '%s': %zu token(s) left unread at the end of the run\n", name_.c_str(), q_.size());
    abort();
  }
}
template <class T, int DEPTH>
T stream<T, DEPTH>::read() {
  if (q_.empty()) {
    fprintf(stderr, "hls::stream '%s': read while empty (the consumer wants more tokens than were written)\n",
            name_.c_str());
    abort();
  }
  T v = q_.front();
  q_.pop_front();
  return v;
}
template <class T, int DEPTH>
void stream<T, DEPTH>::read(T& out) {
  out = read();
}
template <class T, int DEPTH>
bool stream<T, DEPTH>::read_nb(T& out) {
  if (q_.empty()) return false;
  out = read();
  return true;
}
template <class T, int DEPTH>
void stream<T, DEPTH>::write(const T& v) {
  q_.push_back(v);
}
template <class T, int DEPTH>
bool stream<T, DEPTH>::write_nb(const T& v) {
  q_.push_back(v);
  return true;
}
template <class T, int DEPTH>
bool stream<T, DEPTH>::empty() const {
  return q_.empty();
}
template <class T, int DEPTH>
bool stream<T, DEPTH>::full() const {
  return false;
}
template <class T, int DEPTH>
size_t stream<T, DEPTH>::size() const {
  return q_.size();
}
#endif

}  // namespace hls
