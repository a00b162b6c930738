// One JSON form per result type of the explorer room (nlohmann::json's to_json, found by
// argument-dependent lookup: `json j = front;`): what pareto prints with --json, built here once
// instead of field by field in the command. Objects are plain nlohmann::json (keys in alphabetical
// order when dumped).
#pragma once

#include <nlohmann/json.hpp>

#include "parallax/search/sweep.hpp"

namespace parallax::search {

// A stored design: hash, configuration (its YAML as stored) and metrics (the pooled figures under
// their column keys; non-finite figures are absent from the store). The sweep, status, frames,
// times and measurement are not part of it (`parallax report --json` writes the whole row).
void to_json(nlohmann::json& j, const ResultStore::Row& r);

}  // namespace parallax::search
