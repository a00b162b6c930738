// The access-counting build of the kernels' arrays (access.hpp; issue 41). Never synthesised:
// C++14 with the standard library, used by the simulator's counting run and the exported
// project's C simulation.
//
// Counted<T, N...> stands for T[N0][N1]...: indexing records, at the first subscript, where in
// the source the access is written (AccessIndex captures the file and line of the subscript);
// reading or assigning the element records a read or a write of its bank. The tally keeps, per
// access site (the place times its execution count k within the firing, i.e. the k-th unrolled
// copy), the set of banks it reached; per firing, the sorted list of sites that executed. The
// report (access_report()) sums, per distinct list, each bank's reads and writes with every site
// counted on every bank it ever reached, and keeps the largest sum of any firing.
#pragma once

// The guard the export's source check relies on (tests/hls/csim_test.cpp): a synthesis or a
// subset check that reached this file stops here.
#if defined(__SYNTHESIS__) || defined(PARALLAX_HLS_SUBSET_CHECK)
#error "access_count.hpp is C-simulation only: include it through access.hpp"
#endif

#include <stdint.h>
#include <stdio.h>

#include <algorithm>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace parallax {
namespace kern {

// One subscript and where it is written: a kernel's `mem[i]` converts i to AccessIndex, whose
// default arguments take the subscript's own file and line.
struct AccessIndex {
  long i;
  const char* file;
  int line;
  // NOLINTNEXTLINE(google-explicit-constructor): the conversion is the point (see above)
  AccessIndex(long v, const char* f = __builtin_FILE(), int l = __builtin_LINE()) : i(v), file(f), line(l) {}
};

// What the report says of one memory of one stage (access_report()).
struct MemoryAccesses {
  std::string stage;
  std::string name;
  std::string kind;  // registers, ram_1p, ram_2p, ram_s2p, ram_t2p, default (counted as ram_t2p)
  int banks = 1;     // the banks the run reached (of the layout's; the design's, not a software capacity's)
  int read_ports = 0, write_ports = 0;  // per bank; 0 = unlimited (registers)
  bool shared_ports = false;            // the ports serve reads and writes alike (ram_1p, ram_t2p, default)
  int64_t firings = 0;                  // firings in which the memory was accessed
  int max_reads_per_bank_per_firing = 0;
  int max_writes_per_bank_per_firing = 0;
  int runtime_banked_sites = 0;            // sites that reached more than one bank
  int max_banks_per_site = 1;              // the widest such site: its mux (read) or demux (write) fan-in
  std::vector<std::string> runtime_sites;  // "file:line copy k reads|writes N banks"
  int ii_forced = 1;                       // the smallest II the counts fit the ports at
};

// The smallest II at which `reads` and `writes` per bank and firing fit a bank's ports.
inline int access_ii_forced(int storage, int reads, int writes) {
  const auto ceil_div = [](int a, int b) { return (a + b - 1) / b; };
  switch (storage) {
    case kStorageRegisters:
      return 1;
    case kStorageRam1p:
      return std::max(1, reads + writes);
    case kStorageRam2p:  // one read-or-write port and one read port
      return std::max(1, std::max(writes, ceil_div(reads + writes, 2)));
    case kStorageRamS2p:
      return std::max(1, std::max(reads, writes));
    default:  // ram_t2p and unbound arrays
      return std::max(1, ceil_div(reads + writes, 2));
  }
}

inline const char* access_storage_name(int storage) {
  return storage == kStorageRegisters ? "registers"
         : storage == kStorageRam1p   ? "ram_1p"
         : storage == kStorageRam2p   ? "ram_2p"
         : storage == kStorageRamS2p  ? "ram_s2p"
         : storage == kStorageRamT2p  ? "ram_t2p"
                                      : "default";
}
// The StorageType of access_storage_name()'s text (kStorageDefault for any other).
inline int access_storage_kind(const std::string& name) {
  for (int k = kStorageRegisters; k <= kStorageRamT2p; ++k)
    if (name == access_storage_name(k)) return k;
  return kStorageDefault;
}

class AccessTally;

// The counting run's state on this thread: the stage firing now (AccessFiring), the firings of
// every stage, the reports of arrays already destroyed and the arrays alive.
class AccessRegistry {
 public:
  static AccessRegistry& get() {
    static thread_local AccessRegistry r;
    return r;
  }
  const char* stage() const { return stage_; }
  uint64_t firing() const { return firing_; }
  void begin_firing(const char* stage) {
    stage_ = stage;
    firing_ = ++serial_;
    ++firings_[stage];
  }
  void end_firing() {
    stage_ = nullptr;
    firing_ = 0;
  }
  const std::map<std::string, int64_t>& stage_firings() const { return firings_; }
  void add_live(AccessTally* t) { live_.insert(t); }
  void remove_live(AccessTally* t) { live_.erase(t); }
  void add_finished(MemoryAccesses m) { finished_.push_back(std::move(m)); }
  // Every counted memory so far, one entry per stage and name (several arrays of one name in one
  // stage, e.g. one per frame of a C simulation, merged by their largest counts).
  std::vector<MemoryAccesses> report() const;
  // Whether firings that begin from now on are counted (a C simulation counts its first frame
  // and runs the others uncounted).
  bool enabled() const { return enabled_; }
  void set_enabled(bool on) { enabled_ = on; }
  // Forget everything (a new counting run).
  void reset() {
    firings_.clear();
    finished_.clear();
    live_.clear();
    stage_ = nullptr;
    firing_ = 0;
    enabled_ = true;
  }

 private:
  bool enabled_ = true;
  const char* stage_ = nullptr;
  uint64_t firing_ = 0, serial_ = 0;
  std::map<std::string, int64_t> firings_;
  std::vector<MemoryAccesses> finished_;
  std::set<AccessTally*> live_;
};

// One firing of `stage` (a name that outlives the count, e.g. a literal): the accesses between
// construction and destruction belong to it. Nothing while counting is disabled.
class AccessFiring {
 public:
  explicit AccessFiring(const char* stage) : counted_(AccessRegistry::get().enabled()) {
    if (counted_) AccessRegistry::get().begin_firing(stage);
  }
  ~AccessFiring() {
    if (counted_) AccessRegistry::get().end_firing();
  }
  AccessFiring(const AccessFiring&) = delete;
  AccessFiring& operator=(const AccessFiring&) = delete;

 private:
  bool counted_;
};

// The counts of one array (see the top of this file).
class AccessTally {
 public:
  AccessTally(const int* dims, int rank) : rank_(rank) {
    for (int k = 0; k < rank; ++k) {
      dims_[k] = dims[k];
      part_[k] = kPartitionNone;
      factor_[k] = 1;
      reshape_[k] = 1;
    }
  }
  AccessTally(const AccessTally&) = delete;
  AccessTally& operator=(const AccessTally&) = delete;
  ~AccessTally() {
    if (!registered_) return;
    AccessRegistry& r = AccessRegistry::get();
    r.remove_live(this);
    r.add_finished(summary());
  }

  // dim: 1-based, 0 = every dimension (ARRAY_PARTITION's dim=0).
  void partition(const char* name, int type, int factor, int dim) {
    name_ = name;
    for (int k = 0; k < rank_; ++k)
      if (dim == 0 || dim == k + 1) {
        part_[k] = type;
        factor_[k] = factor < 1 ? 1 : factor;
      }
    complete_ = true;
    for (int k = 0; k < rank_; ++k) complete_ = complete_ && part_[k] == kPartitionComplete;
  }
  // The name the report gives the array (a member shared by several objects, e.g. two line buffers).
  void rename(const char* name) { name_ = name; }
  void bind(const char* name, int storage) {
    name_ = name;
    storage_ = storage;
  }
  // ARRAY_RESHAPE cyclic of dimension dim (1-based): element i in word i / factor; factor 0:
  // complete (the whole dimension one word).
  void reshape(const char* name, int factor, int dim) {
    name_ = name;
    if (dim >= 1 && dim <= rank_) reshape_[dim - 1] = factor == 0 ? dims_[dim - 1] : factor < 1 ? 1 : factor;
  }

  void record(long flat, bool write, const char* file, int line) {
    AccessRegistry& r = AccessRegistry::get();
    if (r.firing() == 0) return;  // outside a firing: set-up, not the pipelined loop
    if (!registered_) {
      registered_ = true;
      r.add_live(this);
      stage_ = r.stage();
      stage_name_ = r.stage();
    } else if (r.stage() != stage_name_ && stage_ != r.stage()) {  // reused by another stage (two passes)
      r.add_finished(summary());
      reset_counts();
      stage_ = r.stage();
      stage_name_ = r.stage();
    }
    if (r.firing() != firing_) {
      close_firing();
      firing_ = r.firing();
    }
    const int base = base_site(file, line, write);
    BaseSite& b = bases_[std::size_t(base)];
    if (b.stamp != firing_) {
      b.stamp = firing_;
      b.count = 0;
      b.words.clear();
    }
    const int copy = b.count++;
    if (copy >= int(b.sites.size())) {
      b.sites.push_back(int(sites_.size()));
      sites_.push_back(Site{base, copy, false, {}});
    }
    const int site = b.sites[std::size_t(copy)];
    Site& st = sites_[std::size_t(site)];
    int bank = 0;
    long word = 0;
    locate(flat, bank, word);
    if (bank != st.last_bank) {
      st.banks.insert(bank);
      st.last_bank = bank;
    }
    // A reshaped word read or written by several copies of one place at the same address is one
    // access of the word (the lanes of an ARRAY_RESHAPE): a copy that, in some firing, is the
    // first of its place to address its word is an access; one that only ever follows another
    // copy to the same word is part of that access.
    if (std::find(b.words.begin(), b.words.end(), word) == b.words.end()) {
      b.words.push_back(word);
      st.leads = true;
    }
    current_.push_back(site);
  }

  MemoryAccesses summary() {
    close_firing();
    MemoryAccesses m;
    m.stage = stage_;
    m.name = name_.empty() ? "(unnamed)" : name_;
    const int storage = complete_ ? kStorageRegisters : storage_;
    m.kind = access_storage_name(storage);
    std::set<int> reached;  // the banks this configuration uses (software capacities are larger)
    for (const Site& s : sites_) reached.insert(s.banks.begin(), s.banks.end());
    m.banks = int(reached.size());
    m.read_ports = storage == kStorageRegisters ? 0
                   : storage == kStorageRam2p   ? 2
                   : storage == kStorageRam1p   ? 1
                   : storage == kStorageRamS2p  ? 1
                                                : 2;
    m.write_ports = storage == kStorageRegisters ? 0
                    : storage == kStorageRam2p   ? 1
                    : storage == kStorageRam1p   ? 1
                    : storage == kStorageRamS2p  ? 1
                                                 : 2;
    m.shared_ports =
        storage == kStorageRam1p || storage == kStorageRamT2p || storage == kStorageDefault || storage == kStorageRam2p;
    for (const auto& sig : signatures_) {
      m.firings += sig.second;
      std::map<int, int> reads, writes;
      for (int site : sig.first) {
        const Site& s = sites_[std::size_t(site)];
        if (!s.leads) continue;  // part of another copy's word access
        std::map<int, int>& tally = bases_[std::size_t(s.base)].write ? writes : reads;
        for (int bank : s.banks) ++tally[bank];
      }
      for (const auto& b : reads) m.max_reads_per_bank_per_firing = std::max(m.max_reads_per_bank_per_firing, b.second);
      for (const auto& b : writes)
        m.max_writes_per_bank_per_firing = std::max(m.max_writes_per_bank_per_firing, b.second);
    }
    for (const Site& s : sites_) {
      if (s.banks.size() <= 1 || !s.leads) continue;
      ++m.runtime_banked_sites;
      m.max_banks_per_site = std::max(m.max_banks_per_site, int(s.banks.size()));
      const BaseSite& b = bases_[std::size_t(s.base)];
      if (m.runtime_sites.size() < 16)
        m.runtime_sites.push_back(short_file(b.file) + ":" + std::to_string(b.line) + " copy " +
                                  std::to_string(s.copy) + (b.write ? " writes " : " reads ") +
                                  std::to_string(s.banks.size()) + " banks");
    }
    m.ii_forced = access_ii_forced(storage, m.max_reads_per_bank_per_firing, m.max_writes_per_bank_per_firing);
    return m;
  }

 private:
  struct BaseSite {
    const char* file;
    int line;
    bool write;
    uint64_t stamp;
    int count;
    std::vector<int> sites;   // by copy
    std::vector<long> words;  // the words its copies addressed in this firing
  };
  struct Site {
    int base;
    int copy;
    bool leads;  // the first of its place to address its word, in some firing
    std::set<int> banks;
    int last_bank = -1;  // the bank of its last access (most sites keep to one)
  };

  static std::string short_file(const char* f) {
    const std::string s(f);
    const std::size_t k = s.rfind("/kernels/");
    return k == std::string::npos ? s : s.substr(k + 1);
  }

  // An array is indexed at a handful of places: a linear search over them (the file names are
  // the compiler's literals, compared by address), starting with the last one found.
  int base_site(const char* file, int line, bool write) {
    const int n = int(bases_.size());
    for (int k = 0, i = last_base_; k < n; ++k, i = i + 1 == n ? 0 : i + 1) {
      const BaseSite& b = bases_[std::size_t(i)];
      if (b.line == line && b.write == write && b.file == file) return last_base_ = i;
    }
    bases_.push_back(BaseSite{file, line, write, 0, 0, {}, {}});
    return last_base_ = n;
  }

  // The coordinates of element `flat` (row-major).
  void coordinates(long flat, long* idx) const {
    if (rank_ == 1) {
      idx[0] = flat;
      return;
    }
    for (int k = rank_ - 1; k >= 0; --k) {
      idx[k] = flat % dims_[k];
      flat /= dims_[k];
    }
  }

  // Where element `flat` (row-major) lives: its word after the reshapes (its index with each
  // reshaped dimension's coordinate divided by the factor) and its bank (per dimension, the
  // partition's bank coordinate of that word: the partition splits words).
  void locate(long flat, int& bank_out, long& word_out) const {
    long idx[kMaxRank];
    coordinates(flat, idx);
    long word = 0, bank = 0;
    for (int k = 0; k < rank_; ++k) {
      const int r = reshape_[k];
      const long w = r == 1 ? idx[k] : idx[k] / r;
      const int words = r == 1 ? dims_[k] : (dims_[k] + r - 1) / r;
      word = word * words + w;
      int n = 1, c = 0;
      if (part_[k] == kPartitionComplete) {
        n = words;
        c = int(w);
      } else if (part_[k] == kPartitionCyclic) {
        n = factor_[k];
        c = int(w % factor_[k]);
      } else if (part_[k] == kPartitionBlock) {
        n = factor_[k];
        const int size = (words + factor_[k] - 1) / factor_[k];
        c = int(w / size);
      }
      bank = bank * n + c;
    }
    bank_out = int(bank);
    word_out = word;
  }

  void reset_counts() {
    firing_ = 0;
    bases_.clear();
    last_base_ = 0;
    sites_.clear();
    current_.clear();
    signatures_.clear();
    last_signature_ = signatures_.end();
  }

  void close_firing() {
    if (current_.empty()) return;
    std::sort(current_.begin(), current_.end());
    if (last_signature_ == signatures_.end() || last_signature_->first != current_)
      last_signature_ = signatures_.emplace(current_, 0).first;
    ++last_signature_->second;
    current_.clear();
  }

  static constexpr int kMaxRank = 4;
  int rank_;
  int dims_[kMaxRank];
  int part_[kMaxRank];
  int factor_[kMaxRank];
  int reshape_[kMaxRank];
  bool complete_ = false;
  int storage_ = kStorageDefault;
  std::string name_, stage_;
  const char* stage_name_ = nullptr;  // the registry's pointer to stage_'s text (a cheap first test)
  bool registered_ = false;
  uint64_t firing_ = 0;
  std::vector<BaseSite> bases_;
  int last_base_ = 0;
  std::vector<Site> sites_;
  std::vector<int> current_;
  std::map<std::vector<int>, int64_t> signatures_;
  std::map<std::vector<int>, int64_t>::iterator last_signature_ = signatures_.end();
};

inline std::vector<MemoryAccesses> AccessRegistry::report() const {
  std::vector<MemoryAccesses> all = finished_;
  for (AccessTally* t : live_) all.push_back(t->summary());
  std::vector<MemoryAccesses> out;
  for (MemoryAccesses& m : all) {
    auto it = std::find_if(out.begin(), out.end(),
                           [&](const MemoryAccesses& o) { return o.stage == m.stage && o.name == m.name; });
    if (it == out.end()) {
      out.push_back(std::move(m));
      continue;
    }
    it->firings += m.firings;
    it->max_reads_per_bank_per_firing = std::max(it->max_reads_per_bank_per_firing, m.max_reads_per_bank_per_firing);
    it->max_writes_per_bank_per_firing = std::max(it->max_writes_per_bank_per_firing, m.max_writes_per_bank_per_firing);
    it->runtime_banked_sites = std::max(it->runtime_banked_sites, m.runtime_banked_sites);
    it->max_banks_per_site = std::max(it->max_banks_per_site, m.max_banks_per_site);
    it->ii_forced = std::max(it->ii_forced, m.ii_forced);
  }
  std::sort(out.begin(), out.end(), [](const MemoryAccesses& a, const MemoryAccesses& b) {
    return a.stage != b.stage ? a.stage < b.stage : a.name < b.name;
  });
  return out;
}

// What the report adds to the counts of one stage: the II its pipelined loop declares and the
// loop-carried recurrences with the delay of their operator chains (the simulator's schedule).
struct AccessRecurrence {
  std::string name;
  std::vector<std::string> operators;  // e.g. "add 8 bits x 2"
  double delay_ns = 0;
  double budget_ns = 0;  // the clock period less the uncertainty
  int distance = 1;
  int ii_forced = 1;
};
struct AccessStage {
  std::string name;
  int ii_declared = 1;
  std::vector<AccessRecurrence> recurrences;
};

namespace access_detail {
inline std::string json_string(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\';
    o += c;
  }
  return o + "\"";
}
inline std::string json_number(double v) {
  char buf[32];
  snprintf(buf, sizeof buf, "%.3f", v);
  return buf;
}
}  // namespace access_detail

// csim_accesses.json (issue 41): per stage its declared II, its firings, each counted memory and
// each recurrence with the II it forces. Stages are those given, then any other that fired.
inline std::string access_report_json(const std::string& design, const std::vector<AccessStage>& given) {
  using access_detail::json_number;
  using access_detail::json_string;
  const AccessRegistry& reg = AccessRegistry::get();
  const std::vector<MemoryAccesses> mems = reg.report();
  std::vector<AccessStage> stages = given;
  for (const auto& f : reg.stage_firings())
    if (std::none_of(stages.begin(), stages.end(), [&](const AccessStage& a) { return a.name == f.first; })) {
      AccessStage a;
      a.name = f.first;
      stages.push_back(a);
    }
  std::string o = "{\n  \"design\": " + json_string(design) + ",\n  \"stages\": [";
  for (std::size_t k = 0; k < stages.size(); ++k) {
    const AccessStage& st = stages[k];
    const auto fit = reg.stage_firings().find(st.name);
    int forced = 1;
    std::string m_json, r_json;
    for (const MemoryAccesses& m : mems) {
      if (m.stage != st.name) continue;
      forced = std::max(forced, m.ii_forced);
      std::string sites;
      for (std::size_t i = 0; i < m.runtime_sites.size(); ++i)
        sites += (i ? ", " : "") + json_string(m.runtime_sites[i]);
      m_json += std::string(m_json.empty() ? "" : ",") + "\n        {\"name\": " + json_string(m.name) +
                ", \"kind\": " + json_string(m.kind) + ", \"banks\": " + std::to_string(m.banks) +
                ", \"read_ports\": " + std::to_string(m.read_ports) +
                ", \"write_ports\": " + std::to_string(m.write_ports) +
                ", \"shared_ports\": " + (m.shared_ports ? "true" : "false") +
                ", \"max_reads_per_bank_per_firing\": " + std::to_string(m.max_reads_per_bank_per_firing) +
                ", \"max_writes_per_bank_per_firing\": " + std::to_string(m.max_writes_per_bank_per_firing) +
                ", \"runtime_banked_sites\": " + std::to_string(m.runtime_banked_sites) +
                ", \"max_banks_per_site\": " + std::to_string(m.max_banks_per_site) + ", \"runtime_sites\": [" + sites +
                "], \"ii_forced\": " + std::to_string(m.ii_forced) + "}";
    }
    for (const AccessRecurrence& r : st.recurrences) {
      forced = std::max(forced, r.ii_forced);
      std::string ops;
      for (std::size_t i = 0; i < r.operators.size(); ++i) ops += (i ? ", " : "") + json_string(r.operators[i]);
      r_json += std::string(r_json.empty() ? "" : ",") + "\n        {\"name\": " + json_string(r.name) +
                ", \"operators\": [" + ops + "], \"distance\": " + std::to_string(r.distance) +
                ", \"delay_ns\": " + json_number(r.delay_ns) + ", \"budget_ns\": " + json_number(r.budget_ns) +
                ", \"ii_forced\": " + std::to_string(r.ii_forced) + "}";
    }
    o += std::string(k ? "," : "") + "\n    {\"name\": " + json_string(st.name) +
         ", \"ii_declared\": " + std::to_string(st.ii_declared) + ", \"ii_forced\": " + std::to_string(forced) +
         ", \"firings\": " + std::to_string(fit == reg.stage_firings().end() ? 0 : fit->second) +
         ",\n      \"memories\": [" + m_json + (m_json.empty() ? "" : "\n      ") + "]" +
         ",\n      \"recurrences\": [" + r_json + (r_json.empty() ? "" : "\n      ") + "]}";
  }
  return o + "\n  ]\n}\n";
}

// A counted stand-in for T[N0][N1]...: the same elements, row-major, and a tally.
template <class T, int... N>
class Counted;

namespace access_detail {
constexpr long product() {
  return 1;
}
template <class... R>
constexpr long product(int a, R... r) {
  return long(a) * product(r...);
}
}  // namespace access_detail

// A partly subscripted counted array: L of its subscripts given, `flat` their row-major offset.
template <class A, int L, bool LAST = (L == A::kRank)>
class CountedRef;

template <class A, int L>
class CountedRef<A, L, false> {
 public:
  typedef typename A::value_type element_type;  // store.hpp: StoredBits
  CountedRef(A* a, long flat, const char* file, int line) : a_(a), flat_(flat), file_(file), line_(line) {}
  CountedRef<A, L + 1> operator[](long i) const {
    return CountedRef<A, L + 1>(a_, flat_ * A::dim(L) + i, file_, line_);
  }

 private:
  A* a_;
  long flat_;
  const char* file_;
  int line_;
};

template <class A, int L>
class CountedRef<A, L, true> {
 public:
  typedef typename A::value_type T;
  typedef T element_type;  // store.hpp: StoredBits
  CountedRef(A* a, long flat, const char* file, int line) : a_(a), flat_(flat), file_(file), line_(line) {}
  // NOLINTNEXTLINE(google-explicit-constructor): reading the element is the conversion
  operator T() const { return a_->read(flat_, file_, line_); }
  const CountedRef& operator=(const T& v) const {
    a_->write(flat_, v, file_, line_);
    return *this;
  }
  // A proxy: assigning one element to another reads one and writes the other; self-assignment
  // reads and writes the same element, as the plain array would.
  // NOLINTNEXTLINE(bugprone-unhandled-self-assignment)
  const CountedRef& operator=(const CountedRef& o) const { return *this = T(o); }
  CountedRef(const CountedRef&) = default;

 private:
  A* a_;
  long flat_;
  const char* file_;
  int line_;
};

// The value a counted element holds (store.hpp: from_store reads through this).
template <class A, int L>
typename A::value_type store_value(const CountedRef<A, L, true>& r) {
  return r;
}

template <class T, int... N>
class Counted {
 public:
  typedef T value_type;
  typedef T element_type;  // store.hpp: StoredBits
  static constexpr int kRank = int(sizeof...(N));
  static constexpr long kSize = access_detail::product(N...);
  static int dim(int k) {
    static const int d[] = {N...};
    return d[k];
  }
  Counted() : v_(new T[std::size_t(kSize)]()), tally_(dims(), kRank) {}
  Counted(const Counted&) = delete;
  Counted& operator=(const Counted&) = delete;

  CountedRef<Counted, 1> operator[](AccessIndex i) { return CountedRef<Counted, 1>(this, i.i, i.file, i.line); }
  CountedRef<const Counted, 1> operator[](AccessIndex i) const {
    return CountedRef<const Counted, 1>(this, i.i, i.file, i.line);
  }

  T read(long flat, const char* file, int line) const {
    tally_.record(flat, false, file, line);
    return v_[flat];
  }
  void write(long flat, const T& v, const char* file, int line) const {
    tally_.record(flat, true, file, line);
    v_[flat] = v;
  }
  AccessTally& tally() const { return tally_; }

 private:
  static const int* dims() {
    static const int d[] = {N...};
    return d;
  }
  std::unique_ptr<T[]> v_;  // on the heap: software capacities make large arrays
  mutable AccessTally tally_;
};

template <class T, int... N>
inline void access_partition(Counted<T, N...>& a, const char* name, int type, int factor, int dim) {
  a.tally().partition(name, type, factor, dim);
}
template <class T, int... N>
inline void access_bind(Counted<T, N...>& a, const char* name, int storage) {
  a.tally().bind(name, storage);
}
template <class T, int... N>
inline void access_name(Counted<T, N...>& a, const char* name) {
  a.tally().rename(name);
}
template <class T, int... N>
inline void access_reshape(Counted<T, N...>& a, const char* name, int factor, int dim) {
  a.tally().reshape(name, factor, dim);
}

template <class T, int... N>
struct ArrayOf<true, T, N...> {
  typedef Counted<T, N...> type;
};

// The counted side of a shift register's N entries: a register per entry (complete
// partitioning), each at() or set() a read or a write of its entry at the caller's site.
template <int N>
class ShiftPorts<true, N> {
 public:
  typedef AccessIndex Index;
  ShiftPorts() { access_partition(entries_, "shift_register", kPartitionComplete, 0, 1); }
  int read(const AccessIndex& k) const {
    (void)entries_.read(k.i, k.file, k.line);
    return int(k.i);
  }
  int write(const AccessIndex& k) {
    entries_.write(k.i, 0, k.file, k.line);
    return int(k.i);
  }
  void name(const char* n) { access_name(entries_, n); }

 private:
  Counted<uint8_t, N> entries_;
};

}  // namespace kern
}  // namespace parallax
