// What a study's results.csv row may say, from its identity (study.json): per case its key
// columns, per label its method and params. The one check behind both a resumed study and a
// merge of shards: a hand-edited row is refused naming the file, the line and the field.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "core/json_fields.h"
#include "study/result_columns.h"

namespace pgt {

struct RowPlan {
    std::vector<const ResultColumn*> keys;                               // the key columns
    std::vector<std::vector<std::string>> caseColumns;                   // per case, `keys`
    std::map<std::string, std::pair<std::string, std::string>> configs;  // label -> method, params
    std::vector<std::string> labels;                                     // in the study's order
};

// The plan of the study `identity` (study.json at `path`, named in messages).
RowPlan planRows(const Json& identity, const std::string& path);

// One record of results.csv at `path` (`line`, 1-based), its columns by name (`head`),
// against the plan: its case index, or InputError naming the file, the line and the field
// (`hint` added to the reason). A shard (`shard` of `shards`) holds every shards-th case.
int checkRow(const std::vector<std::string>& fields, const ResultHeader& head, const RowPlan& plan,
             const std::string& path, size_t line, int shard = 0, int shards = 1,
             const std::string& hint = "");

}  // namespace pgt
