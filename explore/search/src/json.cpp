// The JSON forms of the explorer room's result types (json.hpp).
#include "parallax/search/json.hpp"

namespace parallax::search {

void to_json(nlohmann::json& j, const ResultStore::Row& r) {
  j = {{"hash", r.hash}, {"configuration", r.config_yaml}, {"metrics", r.metrics}};
}

}  // namespace parallax::search
