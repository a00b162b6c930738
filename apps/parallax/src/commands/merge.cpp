// parallax merge: merge results stores (the shards of a sweep) into one.
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "parallax/search/sweep.hpp"

namespace parallax::cli {

namespace {

using namespace parallax::eval;
using namespace parallax::search;

struct MergeOptions {
  std::string db;
  std::vector<std::string> inputs;
};

int run_merge(const MergeOptions& o, const Invocation&) {
  ResultStore out(o.db);
  for (const auto& in : o.inputs) {
    const int64_t added = out.merge_from(in);
    std::printf("%s: %lld designs added\n", in.c_str(), (long long)added);
  }
  std::printf("%s: %lld designs\n", o.db.c_str(), (long long)out.count_designs());
  return 0;
}

}  // namespace

Command add_merge(CLI::App& app) {
  auto o = std::make_shared<MergeOptions>();
  auto* mergec = app.add_subcommand("merge", "Merge results stores (shards of a sweep) into one");
  mergec->add_option("--db", o->db, "Store to merge into (created if absent)")->required();
  mergec->add_option("inputs", o->inputs, "Stores to merge from")->required();
  return bind_command(mergec, o, run_merge);
}

}  // namespace parallax::cli
