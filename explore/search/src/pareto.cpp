// Pareto fronts of a sweep's stored designs under its constraints and objectives.
#include <cmath>
#include <limits>

#include "parallax/search/sweep.hpp"

namespace parallax::search {

bool meets_constraints(const SweepSpec& s, const ResultStore::Row& r) {
  if (r.status != "ok") return false;
  // A missing (or non-finite) metric meets no bound on it.
  auto get = [&](const char* k) {
    const auto it = r.metrics.find(k);
    return it == r.metrics.end() ? std::nan("") : it->second;
  };
  if (s.require_fit && !(get("fits_device") >= 0.5)) return false;
  if (s.min_fps > 0 && !(get("fps") >= s.min_fps)) return false;
  if (s.max_latency_ms > 0 && !(get("latency_ms") <= s.max_latency_ms)) return false;
  if (s.one_pass && !(get("passes") <= 1.0)) return false;
  return true;
}

double objective_value(const ResultStore::Row& r, const Objective& o) {
  const auto it = r.metrics.find(o.key);
  if (it == r.metrics.end() || !std::isfinite(it->second)) return -std::numeric_limits<double>::infinity();
  return o.maximise ? it->second : -it->second;
}

std::vector<ResultStore::Row> pareto_front(const SweepSpec& s, const std::vector<ResultStore::Row>& rows) {
  std::vector<const ResultStore::Row*> ok;
  for (const auto& r : rows)
    if (meets_constraints(s, r)) ok.push_back(&r);
  auto dominates = [&](const ResultStore::Row& a, const ResultStore::Row& b) {
    bool strictly = false;
    for (const auto& o : s.objectives) {
      const double va = objective_value(a, o), vb = objective_value(b, o);
      if (va < vb) return false;
      if (va > vb) strictly = true;
    }
    return strictly;
  };
  std::vector<ResultStore::Row> front;
  for (const auto* a : ok) {
    bool dominated = false;
    for (const auto* b : ok)
      if (b != a && dominates(*b, *a)) {
        dominated = true;
        break;
      }
    if (!dominated) front.push_back(*a);
  }
  return front;
}

std::string peer_name(const ResultStore::Row& peer) {
  const auto pos = peer.config_yaml.find("baseline: ");
  if (pos == std::string::npos) return peer.hash;
  return peer.config_yaml.substr(pos + 10, peer.config_yaml.find('\n', pos) - pos - 10);
}

int beaten_on_accuracy_by(const ResultStore::Row& reference, const std::vector<ResultStore::Row>& designs) {
  auto get = [](const ResultStore::Row& r, const char* k) {
    const auto it = r.metrics.find(k);
    return it == r.metrics.end() ? std::nan("") : it->second;
  };
  const double c = get(reference, "correct_3px_pct"), d = get(reference, "density_pct");
  int n = 0;
  for (const auto& r : designs) {
    const double rc = get(r, "correct_3px_pct"), rd = get(r, "density_pct");
    n += rc >= c && rd >= d && (rc > c || rd > d) ? 1 : 0;
  }
  return n;
}

}  // namespace parallax::search
