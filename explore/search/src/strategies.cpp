// The strategies that pick a sweep's designs (grid, random, Latin hypercube; NSGA-II's ranking)
// and the materialisation of a design point into a configuration with its identity.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <cstdio>
#include <cstdint>

#include "internal.hpp"
#include "parallax/config/config.hpp"
#include "parallax/search/sweep.hpp"

namespace parallax::search {

std::vector<DesignPoint> enumerate_designs(const SweepSpec& s) {
  std::vector<DesignPoint> out;
  if (s.strategy == "list") {
    for (const auto& d : s.designs) out.push_back(DesignPoint{d});
    return out;
  }
  if (s.axes.empty()) {
    out.push_back({});
    return out;
  }
  auto point = [&](const std::vector<std::size_t>& idx) {
    DesignPoint d;
    for (std::size_t a = 0; a < s.axes.size(); ++a) d.fields.emplace_back(s.axes[a].first, s.axes[a].second[idx[a]]);
    return d;
  };
  if (s.strategy == "grid") {
    std::vector<std::size_t> idx(s.axes.size(), 0);
    for (;;) {
      out.push_back(point(idx));
      std::size_t a = s.axes.size();
      while (a > 0) {
        --a;
        if (++idx[a] < s.axes[a].second.size()) break;
        idx[a] = 0;
        if (a == 0) return out;
      }
    }
  }
  std::mt19937 rng(s.seed);
  std::set<std::vector<std::size_t>> seen;
  const int n = s.samples;
  if (s.strategy == "random") {
    for (int k = 0; k < n * 20 && int(out.size()) < n; ++k) {
      std::vector<std::size_t> idx;
      for (const auto& a : s.axes)
        idx.push_back(std::uniform_int_distribution<std::size_t>(0, a.second.size() - 1)(rng));
      if (seen.insert(idx).second) out.push_back(point(idx));
    }
    return out;
  }
  // Latin hypercube over the axes' value indices: per axis, n strata in a random order.
  std::vector<std::vector<std::size_t>> columns;
  for (const auto& a : s.axes) {
    std::vector<std::size_t> col(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      const double u = (double(i) + std::uniform_real_distribution<double>(0.0, 1.0)(rng)) / double(n);
      col[std::size_t(i)] = std::min(a.second.size() - 1, std::size_t(u * double(a.second.size())));
    }
    std::shuffle(col.begin(), col.end(), rng);
    columns.push_back(col);
  }
  for (int i = 0; i < n; ++i) {
    std::vector<std::size_t> idx;
    for (const auto& col : columns) idx.push_back(col[std::size_t(i)]);
    if (seen.insert(idx).second) out.push_back(point(idx));
  }
  return out;
}

namespace detail {

std::string fnv1a_hex(const std::string& s) {
  uint64_t h = 1469598103934665603ull;
  for (unsigned char c : s) {
    h ^= c;
    h *= 1099511628211ull;
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

}  // namespace detail

MaterialisedDesign materialise(const config::PipelineConfig& base, const DesignPoint& d) {
  MaterialisedDesign m;
  m.config = base;
  for (const auto& f : d.fields) {
    try {
      config::set_field(m.config, f.first, f.second);
    } catch (const config::ConfigError& e) {
      m.errors.push_back(e.what());
    }
  }
  for (const auto& e : config::validate(m.config)) m.errors.push_back(e.field + ": " + e.message);
  std::string name;
  for (const auto& f : d.fields) name += (name.empty() ? "" : " ") + f.first + "=" + f.second;
  m.config.name = base.name + (name.empty() ? "" : " [" + name + "]");
  config::PipelineConfig anonymous = m.config;
  anonymous.name = "design";
  m.yaml = config::to_yaml(m.config);
  m.hash = detail::fnv1a_hex(config::to_yaml(anonymous));
  return m;
}

namespace nsga2 {

DesignPoint point_of(const SweepSpec& s, const Genome& g) {
  DesignPoint d;
  for (std::size_t a = 0; a < s.axes.size(); ++a) d.fields.emplace_back(s.axes[a].first, s.axes[a].second[g[a]]);
  return d;
}

// Objective vector, larger is better; infeasible designs get -inf everywhere (constrained
// domination: every feasible design dominates them), a missing metric -inf in its place.
std::vector<double> objective_vector(const SweepSpec& s, const ResultStore::Row* r) {
  std::vector<double> v;
  const bool feasible = r && meets_constraints(s, *r);
  for (const auto& o : s.objectives) {
    if (!feasible) {
      v.push_back(-std::numeric_limits<double>::infinity());
      continue;
    }
    v.push_back(objective_value(*r, o));
  }
  return v;
}

namespace {
bool dominates_vec(const std::vector<double>& a, const std::vector<double>& b) {
  bool strictly = false;
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (a[k] < b[k]) return false;
    if (a[k] > b[k]) strictly = true;
  }
  return strictly;
}
}  // namespace

// Fronts (indices) of non-dominated sorting, then crowding distance per index.
void rank_and_crowd(const std::vector<std::vector<double>>& f, std::vector<int>& rank, std::vector<double>& crowd) {
  const std::size_t n = f.size();
  rank.assign(n, 0);
  crowd.assign(n, 0.0);
  std::vector<std::vector<std::size_t>> dominated(n);
  std::vector<int> count(n, 0);
  std::vector<std::size_t> front;
  for (std::size_t p = 0; p < n; ++p) {
    for (std::size_t q = 0; q < n; ++q) {
      if (dominates_vec(f[p], f[q]))
        dominated[p].push_back(q);
      else if (dominates_vec(f[q], f[p]))
        ++count[p];
    }
    if (count[p] == 0) front.push_back(p);
  }
  int r = 0;
  while (!front.empty()) {
    for (std::size_t p : front) rank[p] = r;
    // Crowding distance inside this front.
    for (std::size_t k = 0; k < (f.empty() ? 0 : f[0].size()); ++k) {
      std::vector<std::size_t> order = front;
      std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return f[a][k] < f[b][k]; });
      const double lo = f[order.front()][k], hi = f[order.back()][k];
      crowd[order.front()] = crowd[order.back()] = std::numeric_limits<double>::infinity();
      if (!(hi > lo) || !std::isfinite(hi - lo)) continue;
      for (std::size_t i = 1; i + 1 < order.size(); ++i)
        crowd[order[i]] += (f[order[i + 1]][k] - f[order[i - 1]][k]) / (hi - lo);
    }
    std::vector<std::size_t> next;
    for (std::size_t p : front)
      for (std::size_t q : dominated[p])
        if (--count[q] == 0) next.push_back(q);
    front = next;
    ++r;
  }
}

}  // namespace nsga2

std::string seed_hash(const SweepSpec& spec) {
  try {
    return materialise(config::load_config(spec.base), DesignPoint{}).hash;
  } catch (const std::exception&) {
    return "";
  }
}

}  // namespace parallax::search
