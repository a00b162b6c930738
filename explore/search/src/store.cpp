// The results store of sweeps (sweep.hpp, docs/explorer.md "The store"): SQLite, schema 2.
//
// A store is recognised by its header (application_id "PRLX", user_version 2) before SQLite
// opens it, so that another program's database, a file that is not SQLite, or a store of an
// older schema is refused without being touched. Read-only commands open it read-only. The
// journal is SQLite's default rollback journal (not WAL): a read-only connection then creates no
// side file. Lock waits never fail: the busy handler retries without limit and says so.
#include <sqlite3.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "parallax/eval/dataset.hpp"
#include "parallax/search/sweep.hpp"
#include "parallax/eval/text_util.hpp"

namespace parallax::search {

// The names this file takes from the other rooms (one namespace per room).
using eval::InputError;
using eval::detail::utc_now;

using json = nlohmann::json;
namespace fs = std::filesystem;

namespace {

constexpr int kApplicationId = 0x50524C58;  // "PRLX"
constexpr int kSchemaVersion = 2;
// A claim of another host (whose processes cannot be checked) is taken over after this long.
constexpr int64_t kForeignClaimStaleSeconds = 6 * 3600;

const char* kSchema =
    "CREATE TABLE IF NOT EXISTS sweeps(name TEXT PRIMARY KEY, spec TEXT NOT NULL, dataset TEXT NOT NULL DEFAULT '',"
    " measurement TEXT NOT NULL DEFAULT '', created_at TEXT NOT NULL, updated_at TEXT NOT NULL);"
    "CREATE TABLE IF NOT EXISTS results(key TEXT PRIMARY KEY, hash TEXT NOT NULL, measurement TEXT NOT NULL,"
    " sweep TEXT NOT NULL, config TEXT NOT NULL, status TEXT NOT NULL, reason TEXT NOT NULL DEFAULT '',"
    " metrics TEXT, model_version TEXT, started_at TEXT, finished_at TEXT);"
    "CREATE INDEX IF NOT EXISTS results_by_hash ON results(hash);"
    "CREATE TABLE IF NOT EXISTS frames(key TEXT NOT NULL, frame TEXT NOT NULL, metrics TEXT, PRIMARY KEY(key, frame));"
    "CREATE TABLE IF NOT EXISTS members(sweep TEXT NOT NULL, key TEXT NOT NULL, added_at TEXT NOT NULL,"
    " PRIMARY KEY(sweep, key));"
    "CREATE TABLE IF NOT EXISTS claims(key TEXT PRIMARY KEY, owner TEXT NOT NULL, host TEXT NOT NULL,"
    " pid INTEGER NOT NULL, started INTEGER NOT NULL, claimed_at INTEGER NOT NULL);";

int64_t unix_now() {
  return int64_t(std::time(nullptr));
}

std::string this_host() {
  char buf[256] = {};
  if (gethostname(buf, sizeof buf - 1) != 0) return "?";
  return buf;
}

// Start time of a process in clock ticks since boot (/proc/PID/stat field 22): with the pid it
// names one process, even after the pid is reused. 0 when unknown.
int64_t process_start(long pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string s;
  if (!std::getline(in, s)) return 0;
  const auto close = s.rfind(')');
  if (close == std::string::npos) return 0;
  std::istringstream fields(s.substr(close + 1));
  std::string f;
  for (int i = 3; i <= 22 && fields >> f; ++i)
    if (i == 22) return std::atoll(f.c_str());
  return 0;
}

bool process_alive(long pid, int64_t started) {
  if (pid <= 0) return false;
  if (started > 0 && fs::exists("/proc/self/stat")) return process_start(pid) == started;
  return kill(pid_t(pid), 0) == 0 || errno == EPERM;
}

std::string uri_escape(const std::string& path) {
  std::string o;
  for (unsigned char c : path) {
    if (c == '%' || c == '?' || c == '#' || c < 0x20 || c >= 0x7f) {
      char b[4];
      std::snprintf(b, sizeof b, "%%%02X", c);
      o += b;
    } else {
      o += char(c);
    }
  }
  return o;
}

// The first 100 bytes of a file, as SQLite's header.
struct Header {
  uintmax_t size = 0;
  bool sqlite = false, wal = false;
  uint32_t user_version = 0, application_id = 0;
};

uint32_t be32(const unsigned char* p) {
  return (uint32_t(p[0]) << 24) | (uint32_t(p[1]) << 16) | (uint32_t(p[2]) << 8) | p[3];
}

Header read_header(const std::string& path) {
  Header h;
  std::error_code ec;
  h.size = fs::file_size(path, ec);
  if (ec) throw InputError(path + ": cannot read: " + ec.message());
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot read: " + std::strerror(errno));
  unsigned char b[100] = {};
  in.read(reinterpret_cast<char*>(b), sizeof b);
  if (in.gcount() < 100) return h;
  h.sqlite = std::memcmp(b, "SQLite format 3", 16) == 0;
  h.wal = b[18] == 2 || b[19] == 2;
  h.user_version = be32(b + 60);
  h.application_id = be32(b + 68);
  return h;
}

// Why a file that is SQLite but not a Parallax store of this schema is refused. Looks inside
// with an immutable read-only connection (no lock, no journal, no side file).
std::string why_not_a_store(const std::string& path, const Header& h) {
  const std::string untouched = " The file was not changed.";
  if (h.application_id == uint32_t(kApplicationId)) {
    if (h.user_version > uint32_t(kSchemaVersion))
      return path + ": a results store of a newer Parallax (schema " + std::to_string(h.user_version) +
             "; this one reads schema " + std::to_string(kSchemaVersion) + "): use that version." + untouched;
    return path + ": a results store of unknown schema " + std::to_string(h.user_version) + "." + untouched;
  }
  std::set<std::string> tables;
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(("file:" + uri_escape(path) + "?mode=ro&immutable=1").c_str(), &db,
                      SQLITE_OPEN_READONLY | SQLITE_OPEN_URI, nullptr) == SQLITE_OK) {
    sqlite3_stmt* st = nullptr;
    if (sqlite3_prepare_v2(db, "SELECT name FROM sqlite_master WHERE type = 'table' ORDER BY name", -1, &st, nullptr) ==
        SQLITE_OK)
      while (sqlite3_step(st) == SQLITE_ROW) {
        const unsigned char* t = sqlite3_column_text(st, 0);
        if (t) tables.insert(reinterpret_cast<const char*>(t));
      }
    sqlite3_finalize(st);
  }
  sqlite3_close(db);
  if (h.application_id == 0 && tables.count("sweeps") && tables.count("designs") && tables.count("frames"))
    return path +
           ": a results store of an earlier Parallax (schema 1), whose results are keyed by design only: they do "
           "not say which dataset, frames and ground truth they were measured on, so they cannot be reused or "
           "trusted. Rerun the sweep into a new store (--db NEW.db); this version does not read or migrate "
           "schema 1." +
           untouched;
  std::string names;
  int n = 0;
  for (const auto& t : tables) {
    if (n++ == 6) {
      names += ", ...";
      break;
    }
    names += (names.empty() ? "" : ", ") + t;
  }
  return path + ": an SQLite database that is not a Parallax results store (" +
         (h.application_id ? "application_id " + std::to_string(h.application_id) + ", " : std::string()) +
         (names.empty() ? std::string("no tables") : "tables: " + names) +
         "). Give --db a store written by `parallax sweep`, or a new file." + untouched;
}

// Stored metrics: a JSON object of numbers; null (or a NULL column) is a metric the design has
// not. Returns what is wrong, "" when fine. Non-finite values cannot be stored and are absent.
std::string parse_metrics(const unsigned char* text, std::map<std::string, double>& out) {
  out.clear();
  if (!text) return "";
  json j;
  try {
    j = json::parse(reinterpret_cast<const char*>(text));
  } catch (const json::exception& e) {
    return std::string("not valid JSON (") + e.what() + ")";
  }
  if (j.is_null()) return "";
  if (!j.is_object()) return std::string("a JSON ") + j.type_name() + ", not an object of numbers";
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (it->is_null()) continue;
    if (!it->is_number()) return "'" + it.key() + "' is a " + it->type_name() + ", not a number";
    const double v = it->get<double>();
    if (std::isfinite(v)) out[it.key()] = v;
  }
  return "";
}

std::string metrics_text(const std::map<std::string, double>& m) {
  json j = json::object();
  for (const auto& kv : m)
    if (std::isfinite(kv.second)) j[kv.first] = kv.second;
  return j.dump();
}

void warn(const std::string& what) {
  std::fprintf(stderr, "parallax: warning: %s\n", what.c_str());
}

bool reusable_status(const std::string& s) {
  return s == "ok" || s == "invalid" || s == "peer";  // peer: a baseline stored beside a sweep
}

}  // namespace

struct ResultStore::Impl {
  sqlite3* db = nullptr;
  std::string path;
  bool read_only = false;
  std::mutex mu;
  // Claims.
  std::string owner, host;
  long pid = 0;
  int64_t started = 0;
  // Lock waits.
  int64_t notice_ms = 2000;
  std::chrono::steady_clock::time_point busy_since, last_notice;
  bool noticed = false;

  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(path + ": SQLite: " + what + ": " + sqlite3_errmsg(db));
  }
  void wait_notice() {
    const auto now = std::chrono::steady_clock::now();
    const auto waited = std::chrono::duration_cast<std::chrono::milliseconds>(now - busy_since).count();
    if (waited < notice_ms) return;
    if (noticed && now - last_notice < std::chrono::seconds(30)) return;
    std::fprintf(stderr,
                 "parallax: waiting for lock on %s (held by another connection for %.1f s; waiting without limit)\n",
                 path.c_str(), double(waited) / 1000.0);
    noticed = true;
    last_notice = now;
  }
  // Statements and transactions that meet a lock the busy handler could not wait for (SQLite
  // returns SQLITE_BUSY at once where waiting could deadlock) are retried here.
  void exec(const std::string& sql) {
    busy_since = std::chrono::steady_clock::now();
    noticed = false;
    for (;;) {
      char* err = nullptr;
      const int rc = sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &err);
      if (rc == SQLITE_OK) return;
      const std::string msg = err ? err : sqlite3_errstr(rc);
      sqlite3_free(err);
      if ((rc & 0xff) == SQLITE_BUSY || (rc & 0xff) == SQLITE_LOCKED) {
        wait_notice();
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        continue;
      }
      throw InputError(path + ": SQLite: " + msg +
                       ((rc & 0xff) == SQLITE_READONLY && !read_only ? " (is the file or its folder read-only?)" : ""));
    }
  }
};

namespace {

int on_busy(void* arg, int count) {
  auto* impl = static_cast<ResultStore::Impl*>(arg);
  if (count == 0) {
    impl->busy_since = std::chrono::steady_clock::now();
    impl->noticed = false;
  }
  impl->wait_notice();
  std::this_thread::sleep_for(std::chrono::milliseconds(count < 5 ? 2 << count : 100));
  return 1;  // never give up
}

struct Stmt {
  sqlite3_stmt* s = nullptr;
  ResultStore::Impl& impl;
  bool stepped = false;
  Stmt(ResultStore::Impl& i, const char* sql) : impl(i) {
    if (sqlite3_prepare_v2(impl.db, sql, -1, &s, nullptr) != SQLITE_OK) impl.fail("preparing a statement");
  }
  ~Stmt() { sqlite3_finalize(s); }
  Stmt(const Stmt&) = delete;
  Stmt& operator=(const Stmt&) = delete;
  Stmt& text(int i, const std::string& v) {
    sqlite3_bind_text(s, i, v.c_str(), int(v.size()), SQLITE_TRANSIENT);
    return *this;
  }
  Stmt& integer(int i, int64_t v) {
    sqlite3_bind_int64(s, i, v);
    return *this;
  }
  // true: a row; false: done. The first step waits out locks (see Impl::exec).
  bool step() {
    for (;;) {
      const int rc = sqlite3_step(s);
      if (rc == SQLITE_ROW) {
        stepped = true;
        return true;
      }
      if (rc == SQLITE_DONE) return false;
      if (!stepped && ((rc & 0xff) == SQLITE_BUSY || (rc & 0xff) == SQLITE_LOCKED)) {
        sqlite3_reset(s);
        impl.wait_notice();
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        continue;
      }
      impl.fail("reading or writing");
    }
  }
  void run() {
    while (step()) {
    }
  }
  std::string col(int i) {
    const unsigned char* t = sqlite3_column_text(s, i);
    return t ? reinterpret_cast<const char*>(t) : "";
  }
  const unsigned char* raw(int i) { return sqlite3_column_text(s, i); }
  int64_t num(int i) { return sqlite3_column_int64(s, i); }
};

// A transaction that rolls back unless committed.
struct Transaction {
  ResultStore::Impl& impl;
  bool done = false;
  explicit Transaction(ResultStore::Impl& i) : impl(i) { impl.exec("BEGIN IMMEDIATE"); }
  void commit() {
    impl.exec("COMMIT");
    done = true;
  }
  ~Transaction() {
    if (!done) sqlite3_exec(impl.db, "ROLLBACK", nullptr, nullptr, nullptr);
  }
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;
};

bool reusable_row(ResultStore::Impl& impl, const std::string& key) {
  Stmt st(impl, "SELECT status, metrics FROM results WHERE key = ?1");
  st.text(1, key);
  if (!st.step()) return false;
  std::map<std::string, double> m;
  return reusable_status(st.col(0)) && parse_metrics(st.raw(1), m).empty();
}

void check_schema(ResultStore::Impl& impl) {
  Stmt a(impl, "PRAGMA application_id");
  const int64_t app = a.step() ? a.num(0) : 0;
  Stmt v(impl, "PRAGMA user_version");
  const int64_t ver = v.step() ? v.num(0) : 0;
  if (app == kApplicationId && ver == kSchemaVersion) return;
  Header h;
  h.sqlite = true;
  h.application_id = uint32_t(app);
  h.user_version = uint32_t(ver);
  throw InputError(why_not_a_store(impl.path, h));
}

}  // namespace

ResultStore::ResultStore(const std::string& path, Access access) : impl_(new Impl) {
  std::unique_ptr<Impl> guard(impl_);
  Impl& im = *impl_;
  im.path = path;
  im.read_only = access == Access::read;
  if (const char* e = std::getenv("PARALLAX_LOCK_NOTICE_MS")) im.notice_ms = std::max<int64_t>(0, std::atoll(e));
  std::error_code ec;
  const bool exists = fs::exists(path, ec);
  if (!exists && im.read_only) throw InputError(path + ": results store not found");
  if (exists && fs::is_directory(path, ec)) throw InputError(path + ": a folder, not a results store");
  if (exists) {
    const Header h = read_header(path);
    if (h.size == 0) {
      if (im.read_only) throw InputError(path + ": an empty file, not a Parallax results store");
    } else if (!h.sqlite) {
      throw InputError(path +
                       ": not an SQLite file, so not a Parallax results store (give --db a store written by "
                       "`parallax sweep`, or a new file). The file was not changed.");
    } else if (h.application_id != uint32_t(kApplicationId) || h.user_version != uint32_t(kSchemaVersion)) {
      throw InputError(why_not_a_store(path, h));
    }
  }
  const int flags = im.read_only ? SQLITE_OPEN_READONLY : SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE;
  if (sqlite3_open_v2(path.c_str(), &im.db, flags, nullptr) != SQLITE_OK) {
    const std::string msg = im.db ? sqlite3_errmsg(im.db) : "out of memory";
    sqlite3_close(im.db);
    throw InputError(path + ": cannot open the results store: " + msg);
  }
  sqlite3_busy_handler(im.db, on_busy, impl_);
  try {
    if (im.read_only) {
      check_schema(im);
    } else {
      Transaction t(im);
      Stmt v(im, "PRAGMA user_version");
      const int64_t ver = v.step() ? v.num(0) : 0;
      Stmt n(im, "SELECT COUNT(*) FROM sqlite_master");
      const int64_t objects = n.step() ? n.num(0) : 0;
      if (ver == 0 && objects == 0) {
        // New (or empty) file: ours from now on.
        im.exec(kSchema);
        im.exec("PRAGMA application_id = " + std::to_string(kApplicationId) +
                "; PRAGMA user_version = " + std::to_string(kSchemaVersion));
      } else {
        check_schema(im);
      }
      t.commit();
    }
  } catch (...) {
    sqlite3_close(im.db);
    if (!exists) {
      // Nothing to keep in a file this constructor created.
      std::error_code rm;
      if (fs::exists(path, rm) && fs::file_size(path, rm) == 0) fs::remove(path, rm);
    }
    throw;
  }
  im.host = this_host();
  im.pid = long(getpid());
  im.started = process_start(im.pid);
  static std::atomic<int> instances{0};
  im.owner =
      im.host + ":" + std::to_string(im.pid) + ":" + std::to_string(im.started) + ":" + std::to_string(++instances);
  (void)guard.release();  // constructed: the store owns impl_ from here on
}

ResultStore::~ResultStore() {
  if (!impl_->read_only) {
    sqlite3_stmt* st = nullptr;
    if (sqlite3_prepare_v2(impl_->db, "DELETE FROM claims WHERE owner = ?1", -1, &st, nullptr) == SQLITE_OK) {
      sqlite3_bind_text(st, 1, impl_->owner.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_step(st);
    }
    sqlite3_finalize(st);
  }
  sqlite3_close(impl_->db);
  delete impl_;
}

const std::string& ResultStore::path() const {
  return impl_->path;
}

bool ResultStore::put_sweep(const SweepSpec& s, const std::string& dataset, const std::string& measurement) {
  std::lock_guard<std::mutex> lock(impl_->mu);
  Transaction t(*impl_);
  std::string before;
  bool existed = false;
  {
    Stmt q(*impl_, "SELECT measurement FROM sweeps WHERE name = ?1");
    q.text(1, s.name);
    if (q.step()) {
      existed = true;
      before = q.col(0);
    }
  }
  const bool changed = existed && !before.empty() && before != measurement;
  Stmt st(*impl_,
          "INSERT INTO sweeps(name, spec, dataset, measurement, created_at, updated_at) VALUES(?1, ?2, ?3, ?4, ?5, ?5)"
          " ON CONFLICT(name) DO UPDATE SET spec = ?2, dataset = ?3, measurement = ?4, updated_at = ?5");
  st.text(1, s.name).text(2, sweep_to_yaml(s)).text(3, dataset).text(4, measurement).text(5, utc_now()).run();
  if (changed) {
    Stmt del(*impl_,
             "DELETE FROM members WHERE sweep = ?1 AND key NOT IN (SELECT key FROM results WHERE measurement = ?2)");
    del.text(1, s.name).text(2, measurement).run();
  }
  t.commit();
  return changed;
}

std::string ResultStore::sweep_dataset(const std::string& sweep) {
  std::lock_guard<std::mutex> lock(impl_->mu);
  Stmt st(*impl_, "SELECT dataset FROM sweeps WHERE name = ?1");
  st.text(1, sweep);
  return st.step() ? st.col(0) : "";
}

bool ResultStore::has_result(const std::string& key) {
  std::lock_guard<std::mutex> lock(impl_->mu);
  return reusable_row(*impl_, key);
}

bool ResultStore::put_design(const Row& r) {
  const std::string key = r.key.empty() ? result_key(r.hash, r.measurement) : r.key;
  std::lock_guard<std::mutex> lock(impl_->mu);
  Transaction t(*impl_);
  const bool keep = reusable_row(*impl_, key);
  if (!keep) {
    Stmt del(*impl_, "DELETE FROM frames WHERE key = ?1");
    del.text(1, key).run();
    Stmt st(
        *impl_,
        "INSERT OR REPLACE INTO results(key, hash, measurement, sweep, config, status, reason, metrics, model_version,"
        " started_at, finished_at) VALUES(?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11)");
    st.text(1, key).text(2, r.hash).text(3, r.measurement).text(4, r.sweep).text(5, r.config_yaml).text(6, r.status);
    st.text(7, r.reason).text(8, metrics_text(r.metrics)).text(9, r.model_version).text(10, r.started_at);
    st.text(11, r.finished_at).run();
    for (const auto& f : r.frames) {
      Stmt fs(*impl_, "INSERT OR REPLACE INTO frames(key, frame, metrics) VALUES(?1, ?2, ?3)");
      fs.text(1, key).text(2, f.first).text(3, metrics_text(f.second)).run();
    }
  }
  if (!r.sweep.empty()) {
    Stmt m(*impl_, "INSERT OR IGNORE INTO members(sweep, key, added_at) VALUES(?1, ?2, ?3)");
    m.text(1, r.sweep).text(2, key).text(3, utc_now()).run();
  }
  Stmt c(*impl_, "DELETE FROM claims WHERE key = ?1 AND owner = ?2");
  c.text(1, key).text(2, impl_->owner).run();
  t.commit();
  return !keep;
}

void ResultStore::add_member(const std::string& sweep, const std::string& key) {
  std::lock_guard<std::mutex> lock(impl_->mu);
  Stmt m(*impl_, "INSERT OR IGNORE INTO members(sweep, key, added_at) VALUES(?1, ?2, ?3)");
  m.text(1, sweep).text(2, key).text(3, utc_now()).run();
}

std::vector<ResultStore::Claim> ResultStore::claim(const std::vector<std::string>& keys) {
  std::lock_guard<std::mutex> lock(impl_->mu);
  Impl& im = *impl_;
  std::vector<Claim> out;
  Transaction t(im);
  for (const auto& key : keys) {
    if (reusable_row(im, key)) {
      out.push_back(Claim::reusable);
      continue;
    }
    Stmt q(im, "SELECT owner, host, pid, started, claimed_at FROM claims WHERE key = ?1");
    q.text(1, key);
    if (q.step() && q.col(0) != im.owner) {
      const bool alive = q.col(1) == im.host ? process_alive(long(q.num(2)), q.num(3))
                                             : unix_now() - q.num(4) < kForeignClaimStaleSeconds;
      if (alive) {
        out.push_back(Claim::busy);
        continue;
      }
    }
    Stmt ins(
        im, "INSERT OR REPLACE INTO claims(key, owner, host, pid, started, claimed_at) VALUES(?1, ?2, ?3, ?4, ?5, ?6)");
    ins.text(1, key)
        .text(2, im.owner)
        .text(3, im.host)
        .integer(4, im.pid)
        .integer(5, im.started)
        .integer(6, unix_now())
        .run();
    out.push_back(Claim::mine);
  }
  t.commit();
  return out;
}

void ResultStore::release(const std::string& key) {
  std::lock_guard<std::mutex> lock(impl_->mu);
  Stmt c(*impl_, "DELETE FROM claims WHERE key = ?1 AND owner = ?2");
  c.text(1, key).text(2, impl_->owner).run();
}

std::vector<ResultStore::Row> ResultStore::designs(const std::string& sweep, bool with_frames) {
  return rows_of(sweep, with_frames, false);
}

std::vector<ResultStore::Row> ResultStore::peers(const std::string& sweep) {
  return rows_of(sweep, true, true);
}

std::vector<ResultStore::Row> ResultStore::rows_of(const std::string& sweep, bool with_frames, bool peers) {
  std::lock_guard<std::mutex> lock(impl_->mu);
  Impl& im = *impl_;
  // A sweep lists its members measured as the sweep was last run (a store written through the
  // API without put_sweep: every member). Peers (status peer) are listed apart from designs.
  const std::string status = peers ? "r.status = 'peer'" : "r.status <> 'peer'";
  const std::string sql = sweep.empty()
                              ? "SELECT r.rowid, r.key, r.hash, r.sweep, r.config, r.status, r.reason, "
                                "r.metrics, r.model_version, r.started_at, r.finished_at, r.measurement "
                                "FROM results r WHERE " +
                                    status + " ORDER BY r.rowid"
                              : "SELECT r.rowid, r.key, r.hash, r.sweep, r.config, r.status, r.reason, "
                                "r.metrics, r.model_version, r.started_at, r.finished_at, r.measurement "
                                "FROM members m JOIN results r ON r.key = m.key LEFT JOIN sweeps s ON s.name = "
                                "m.sweep WHERE m.sweep = ?1 AND " +
                                    status +
                                    " AND (s.name IS NULL OR s.measurement = '' OR r.measurement = "
                                    "s.measurement) ORDER BY r.rowid";
  Stmt st(im, sql.c_str());
  if (!sweep.empty()) st.text(1, sweep);
  std::vector<Row> out;
  std::map<std::string, std::size_t> index;
  std::set<std::string> flagged;
  // A row whose stored metrics cannot be read: an error row saying so, and a warning.
  auto unreadable = [&](Row& r, const std::string& where, const std::string& what) {
    if (!flagged.insert(r.key).second) return;
    warn(im.path + ": " + where + " (design " + r.hash + ", result " + r.key + "): " + what +
         "; shown as status error");
    r.status = "error";
    r.reason = "the store's " + where + " cannot be read: " + what;
    r.metrics.clear();
    r.frames.clear();
  };
  while (st.step()) {
    Row r;
    r.key = st.col(1);
    r.hash = st.col(2);
    r.sweep = sweep.empty() ? st.col(3) : sweep;
    r.config_yaml = st.col(4);
    r.status = st.col(5);
    r.reason = st.col(6);
    r.model_version = st.col(8);
    r.started_at = st.col(9);
    r.finished_at = st.col(10);
    r.measurement = st.col(11);
    const std::string bad = parse_metrics(st.raw(7), r.metrics);
    if (!bad.empty()) unreadable(r, "results row " + std::to_string(st.num(0)) + ", metrics", bad);
    index[r.key] = out.size();
    out.push_back(std::move(r));
  }
  if (!with_frames) return out;
  const char* fsql = sweep.empty() ? "SELECT key, frame, metrics FROM frames ORDER BY key, frame"
                                   : "SELECT f.key, f.frame, f.metrics FROM members m JOIN frames f ON f.key = m.key"
                                     " WHERE m.sweep = ?1 ORDER BY f.key, f.frame";
  Stmt fs(im, fsql);
  if (!sweep.empty()) fs.text(1, sweep);
  while (fs.step()) {
    const auto it = index.find(fs.col(0));
    if (it == index.end()) continue;
    Row& r = out[it->second];
    std::map<std::string, double> m;
    const std::string bad = parse_metrics(fs.raw(2), m);
    if (!bad.empty()) unreadable(r, "frame " + fs.col(1) + ", metrics", bad);
    if (!bad.empty() || flagged.count(r.key)) continue;
    r.frames.emplace_back(fs.col(1), std::move(m));
  }
  return out;
}

std::vector<SweepSpec> ResultStore::sweeps() {
  std::lock_guard<std::mutex> lock(impl_->mu);
  Stmt st(*impl_, "SELECT name, spec FROM sweeps ORDER BY rowid");
  std::vector<SweepSpec> out;
  while (st.step()) {
    const std::string where = impl_->path + ": sweep '" + st.col(0) + "'";
    try {
      out.push_back(parse_sweep(st.col(1), where));
    } catch (const InputError&) {
      throw;
    } catch (const std::exception& e) {
      throw InputError(where + ": the stored spec cannot be read: " + e.what());
    }
  }
  return out;
}

int64_t ResultStore::count_designs() {
  std::lock_guard<std::mutex> lock(impl_->mu);
  Stmt st(*impl_, "SELECT COUNT(*) FROM results");
  return st.step() ? st.num(0) : 0;
}

int64_t ResultStore::merge_from(const std::string& other) {
  if (impl_->read_only) throw InputError(impl_->path + ": opened read-only; cannot merge into it");
  {
    const ResultStore check(other, Access::read);  // a Parallax store of this schema, or InputError naming it
    std::error_code ec;
    if (fs::equivalent(other, impl_->path, ec)) throw InputError(other + ": is the store being merged into");
  }
  const int64_t before = count_designs();
  std::lock_guard<std::mutex> lock(impl_->mu);
  Impl& im = *impl_;
  {
    Stmt st(im, "ATTACH DATABASE ?1 AS src");
    st.text(1, other);
    if (sqlite3_step(st.s) != SQLITE_DONE) throw InputError(other + ": cannot attach: " + sqlite3_errmsg(im.db));
  }
  try {
    Transaction t(im);
    // A reusable result replaces a failed one; otherwise the store's own row is kept.
    im.exec(
        "DELETE FROM main.frames WHERE key IN (SELECT r.key FROM main.results r JOIN src.results s ON s.key = r.key"
        "  WHERE r.status NOT IN ('ok', 'invalid') AND s.status IN ('ok', 'invalid'));"
        "DELETE FROM main.results WHERE status NOT IN ('ok', 'invalid')"
        "  AND key IN (SELECT key FROM src.results WHERE status IN ('ok', 'invalid'));"
        "INSERT OR IGNORE INTO main.sweeps(name, spec, dataset, measurement, created_at, updated_at)"
        "  SELECT name, spec, dataset, measurement, created_at, updated_at FROM src.sweeps ORDER BY rowid;"
        "INSERT OR IGNORE INTO main.results(key, hash, measurement, sweep, config, status, reason, metrics, "
        "model_version,"
        "  started_at, finished_at) SELECT key, hash, measurement, sweep, config, status, reason, metrics, "
        "model_version,"
        "  started_at, finished_at FROM src.results ORDER BY rowid;"
        "INSERT OR IGNORE INTO main.frames(key, frame, metrics) SELECT key, frame, metrics FROM src.frames;"
        "INSERT OR IGNORE INTO main.members(sweep, key, added_at) SELECT sweep, key, added_at FROM src.members;");
    t.commit();
  } catch (...) {
    sqlite3_exec(im.db, "DETACH DATABASE src", nullptr, nullptr, nullptr);
    throw;
  }
  im.exec("DETACH DATABASE src");
  Stmt st(im, "SELECT COUNT(*) FROM results");
  const int64_t after = st.step() ? st.num(0) : before;
  return after - before;
}

}  // namespace parallax::search
