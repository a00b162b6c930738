// The widths a kernel's storage members hold, against the widths its storage descriptor
// declares to the resource model (issue 41, N6). C++14; C simulation and software only, never
// synthesised (access.hpp includes it outside synthesis).
//
// StorageWidths is a storage visitor (resources.hpp: registers, registers_part, window, memory,
// unused):
// for each member it records the declared width of one element (a memory's word width over its
// lanes per word) and the width the member's element type stores (store.hpp: stored_bits). The
// exported top records every stage after configure() (PX_COUNT_STORAGE, under the access count
// of `make csim`); the testbench sets beside each row the width the resource model prices
// (apply_priced_widths, from the table `parallax export-hls` writes), writes
// tb/csim_storage.json, and fails when a memory's word is not the word the model prices its BRAM
// at, or a member has no price. Registers stored wider than priced are listed (the flip-flops they
// cost are issue 42's to price) but do not fail.
#pragma once

#if defined(__SYNTHESIS__) || defined(PARALLAX_HLS_SUBSET_CHECK)
#error "storage_widths.hpp is C-simulation only: include it through access.hpp"
#endif

#include <stdint.h>
#include <stdio.h>

#include <string>
#include <vector>

#include "parallax/kernels/store.hpp"

namespace parallax {
namespace kern {

struct StorageWidth {
  std::string stage;
  std::string name;
  bool memory = false;
  int per_word = 1;       // a memory's elements per word (its lanes)
  int declared_bits = 0;  // per element, as the kernel's storage descriptor states it
  int stored_bits = 0;    // per element, of the member's element type
  int priced_bits = -1;   // per word (memories) or register, as the resource model prices it; -1: not priced
  int stored_word_bits() const { return stored_bits * (memory ? per_word : 1); }
  // A memory must store the word the model prices; a register may not store less than priced.
  bool fits() const {
    if (priced_bits < 0) return false;
    return memory ? stored_word_bits() == priced_bits : stored_bits >= priced_bits;
  }
};

// One storage item of the resource model's inventory of the design (`parallax export-hls` writes
// the testbench's table of them): its stage, name, and width per word or register.
struct PricedWidth {
  const char* stage;
  const char* name;
  bool memory;
  int width_bits;
};

// Sets each row's priced_bits from the model's items of the same stage, kind and name (a kernel
// instantiated once for two stages, such as the cameras' rectification, is found under either).
inline void apply_priced_widths(std::vector<StorageWidth>& rows, const std::vector<PricedWidth>& priced) {
  for (StorageWidth& w : rows)
    for (const PricedWidth& p : priced)
      if (p.memory == w.memory && w.name == p.name &&
          (w.stage == p.stage || std::string(p.stage).compare(0, w.stage.size() + 1, w.stage + "_") == 0))
        w.priced_bits = p.width_bits;
}

class StorageWidths {
 public:
  explicit StorageWidths(const char* stage) : stage_(stage) {}
  template <class M>
  void registers(const char* name, const M&, int, int width_bits) {
    add(name, false, width_bits, StoredBits<M>::value);
  }
  template <class M>
  void registers_part(const char* name, const M&, int, int width_bits) {
    add(name, false, width_bits, StoredBits<M>::value);
  }
  template <class M>
  void window(const char* name, const M&, int, int, int width_bits) {
    add(name, false, width_bits, StoredBits<M>::value);
  }
  template <class M>
  void unused(const char*, const M&) {}
  template <class M>
  void memory(const char* name, const M&, int64_t, int width_bits, int, bool, int per_word) {
    add(name, true, per_word > 0 ? width_bits / per_word : width_bits, StoredBits<M>::value);
    rows_.back().per_word = per_word > 0 ? per_word : 1;
  }
  const std::vector<StorageWidth>& rows() const { return rows_; }

 private:
  void add(const char* name, bool memory, int declared, int stored) {
    StorageWidth w;
    w.stage = stage_;
    w.name = name;
    w.memory = memory;
    w.declared_bits = declared;
    w.stored_bits = stored;
    rows_.push_back(w);
  }
  const char* stage_;
  std::vector<StorageWidth> rows_;
};

// Every stage's rows, as the exported top's stage functions recorded them (one frame; a stage
// recorded again replaces its rows).
inline std::vector<StorageWidth>& storage_width_rows() {
  static std::vector<StorageWidth> rows;
  return rows;
}

template <class K, class... A>
void record_storage_widths(const char* stage, const K& kernel, const A&... a) {
  StorageWidths v(stage);
  kernel.storage(v, a...);
  std::vector<StorageWidth>& all = storage_width_rows();
  std::vector<StorageWidth> kept;
  for (const StorageWidth& w : all)
    if (w.stage != stage) kept.push_back(w);
  kept.insert(kept.end(), v.rows().begin(), v.rows().end());
  all.swap(kept);
}

// {"design": ..., "storage": [{"stage", "name", "kind", "lanes_per_word", "declared_bits",
// "stored_bits", "priced_word_bits", "stored_word_bits", "fits"}]}: bits per element, then per word
// (a memory's word of lanes, a register's own width).
inline std::string storage_widths_json(const std::string& design, const std::vector<StorageWidth>& rows) {
  std::string o = "{\n  \"design\": \"" + design + "\",\n  \"storage\": [";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const StorageWidth& w = rows[i];
    o += std::string(i ? ",\n" : "\n") + "    {\"stage\": \"" + w.stage + "\", \"name\": \"" + w.name +
         "\", \"kind\": \"" + (w.memory ? "memory" : "registers") +
         "\", \"lanes_per_word\": " + std::to_string(w.memory ? w.per_word : 1) +
         ", \"declared_bits\": " + std::to_string(w.declared_bits) +
         ", \"stored_bits\": " + std::to_string(w.stored_bits) +
         ", \"priced_word_bits\": " + std::to_string(w.priced_bits) +
         ", \"stored_word_bits\": " + std::to_string(w.stored_word_bits()) +
         ", \"fits\": " + (w.fits() ? "true" : "false") + "}";
  }
  return o + "\n  ]\n}\n";
}

}  // namespace kern
}  // namespace parallax
