// The row check a resume and a merge share (study/row_check.h).
#include "study/row_check.h"

#include "core/error.h"
#include "study/plan.h"

namespace pgt {

RowPlan planRows(const Json& identity, const std::string& path) {
    RowPlan p;
    for (const ResultColumn& c : resultSchema())
        if (c.caseField) p.keys.push_back(&c);
    for (const StudyCase& c : planCases(identity, path)) {
        p.caseColumns.emplace_back();
        for (const ResultColumn* k : p.keys)
            p.caseColumns.back().push_back(csvText(c.*k->caseField));
    }
    const Json configs = identity.value("configurations", Json());
    for (const Json& cfg : configs.is_array() ? configs : Json::array()) {
        Json params = cfg;
        params.erase("name");
        params.erase("label");
        p.labels.push_back(cfg.value("label", ""));
        p.configs[p.labels.back()] = {cfg.value("name", ""), params.dump()};
    }
    return p;
}

int checkRow(const std::vector<std::string>& f, const ResultHeader& head, const RowPlan& plan,
             const std::string& path, size_t line, int shard, int shards, const std::string& hint) {
    auto bad = [&](const std::string& field, const std::string& value, const std::string& why) {
        throw InputError(path, "line " + std::to_string(line) + ": " + field, value, why + hint);
    };
    if (f.size() != head.size())
        bad("columns", std::to_string(f.size()), "not a row of results.csv");
    const std::string& text = head.field(f, "case");
    if (text.empty() || text.size() > 9 ||
        text.find_first_not_of("0123456789") != std::string::npos)
        bad("case", text, "not a case index (digits only)");
    const int index = std::stoi(text);
    if (index >= int(plan.caseColumns.size()) || index % shards != shard)
        bad("case", text,
            shards == 1
                ? "not a case of the study (" + std::to_string(plan.caseColumns.size()) + " cases)"
                : "not a case of shard " + std::to_string(shard) + " of " + std::to_string(shards));
    const std::vector<std::string>& planned = plan.caseColumns[size_t(index)];
    for (size_t k = 0; k < planned.size(); ++k) {
        const std::string& name = plan.keys[k]->name;
        if (head.field(f, name) != planned[k])
            bad(name, head.field(f, name), "case " + text + " has " + planned[k]);
    }
    const std::string &label = head.field(f, "label"), &method = head.field(f, "method");
    auto it = plan.configs.find(label);
    if (it == plan.configs.end()) bad("label", label, "not a configuration of the study");
    if (method != it->second.first)
        bad("method", method, "label " + label + " is a " + it->second.first);
    if (head.field(f, "params") != it->second.second)
        bad("params", head.field(f, "params"), "not label " + label + "'s parameters");
    return index;
}

}  // namespace pgt
