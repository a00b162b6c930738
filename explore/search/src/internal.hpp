// Declarations shared by the sources of explore/search and no one else: the identity hash of a
// design, and the pieces of NSGA-II (Deb et al. 2002) that run_sweep's generational loop uses.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "parallax/search/sweep.hpp"

namespace parallax::search {
namespace detail {

// FNV-1a 64-bit hash of a text as 16 hex digits: a design's identity (its canonical YAML).
std::string fnv1a_hex(const std::string& text);

}  // namespace detail

namespace nsga2 {

// A design as the index of its value on every axis.
using Genome = std::vector<std::size_t>;

// The design point of a genome.
DesignPoint point_of(const SweepSpec& s, const Genome& g);
// The spec's objectives of a stored row as values to maximise (-infinity when absent, failed or
// breaking a constraint); every objective -infinity when r is null.
std::vector<double> objective_vector(const SweepSpec& s, const ResultStore::Row* r);
// Non-dominated sorting: rank 0 is the front; crowding distance within each rank.
void rank_and_crowd(const std::vector<std::vector<double>>& f, std::vector<int>& rank, std::vector<double>& crowd);

}  // namespace nsga2
}  // namespace parallax::search
