// A stored design row as the reports read it (reports/src): its configuration fields as text, its
// metrics, and the number of paths of a `paths` value. Internal to the reports library.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "parallax/search/sweep.hpp"

namespace parallax::reports::rows {

// The names this file takes from the other rooms (one namespace per room).
using search::ResultStore;

// The configuration's fields in file order, as text; a list (paths) as "[a,b,...]". Empty for text
// that is not YAML.
std::vector<std::pair<std::string, std::string>> config_fields(const std::string& yaml);

// Field k of the row's configuration ("" when absent).
std::string field(const ResultStore::Row& r, const std::string& k);

// Metric k of the row (NaN when absent).
double metric(const ResultStore::Row& r, const std::string& k);

// Number of aggregation paths of a stored design ("4", "8" or a list of angles).
std::string path_count(const std::string& paths);

}  // namespace parallax::reports::rows
