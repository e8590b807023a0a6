// results.csv's schema in one place (docs/outputs.md): every column's name, the part of a study
// it is, how a row writes it and, where summary.json says the same, its key there; and the
// reader that finds a file's columns by name, so that no reader depends on their order.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <variant>
#include <vector>

#include "frame/render.h"
#include "study/plan.h"

namespace pgt {

// One results.csv row: a case, its frame, one method configuration of it.
struct ResultRow {
    const StudyCase& c;
    const RenderResult& r;
    const MethodFrame& m;
};

// A column's value, typed. results.csv writes an integer as it is, a real with 9 significant
// digits (`nan` where it is not finite) and text as it is; summary.json writes the number
// (null where it is not finite) or the string.
using ColumnValue = std::variant<int64_t, double, std::string>;
std::string csvText(const ColumnValue& value);
nlohmann::json jsonValue(const ColumnValue& value);

// What part of a study a column is.
enum class ColumnPart {
    Case,           // the case's key: its index, view, surface and light (the plan's)
    Configuration,  // the method configuration: method, label, params (the plan's)
    Computed,       // what the frame shows: equal between runs of one study
    Measured,       // times and where they were taken: differ between runs
};

struct ResultColumn {
    std::string name;
    ColumnPart part = ColumnPart::Computed;
    std::function<ColumnValue(const ResultRow&)> value;
    bool quoted = false;  // always quoted (a JSON value), not only when it must be
    // A case's key column but `case`: the field of StudyCase it writes, and a resume reads.
    double StudyCase::*caseField = nullptr;
    // Where a method's entry in summary.json says the same, the path of keys to it
    // ({"error_texels", "mean"}): in toJson(FrameStats) (ofStats), or in the entry (ofMethod).
    std::vector<std::string> jsonKey;
    std::function<ColumnValue(const FrameStats&)> ofStats;
    std::function<ColumnValue(const MethodFrame&)> ofMethod;
};

// results.csv's columns, in the order pgt writes them. A new column is one entry here (its
// place in the order is free: every reader finds columns by name), one in docs/outputs.md,
// and, when measured, one in analysis/columns.py.
const std::vector<ResultColumn>& resultSchema();
// Their names, in order.
const std::vector<std::string>& resultColumns();
// Their measured ones (ColumnPart::Measured), in order: every other column is equal between
// runs of one study, whole, resumed or merged. The Python side's list (analysis/columns.py) is
// checked against this one by the tests.
const std::vector<std::string>& measuredResultColumns();

// results.csv's header line, and a row's line.
std::string resultHeader();
std::string resultLine(const ResultRow& row);

// The keys of summary.json that results.csv's columns say (ResultColumn::jsonKey), set in `j`:
// a frame's statistics (toJson(FrameStats)), and a method's entry.
void statsColumnsJson(const FrameStats& stats, nlohmann::json& j);
void methodColumnsJson(const MethodFrame& method, nlohmann::json& j);

// A results.csv as a file has it: the place of each column by name, from the file's own
// header line, so that a file whose columns are in another order, or which has columns this
// pgt does not write, is read right.
class ResultHeader {
  public:
    // Reads the header line of `text`, the results.csv at `path`. InputError naming the path
    // and the columns when it lacks any of resultColumns() (`hint`, if any, ends the message:
    // what to do about it), has a column twice, or has no whole header line.
    ResultHeader(const std::string& path, const std::string& text, const std::string& hint);

    size_t rowsFrom() const { return rowsFrom_; }  // the byte where the rows start
    size_t size() const { return names_.size(); }  // the fields of a whole row
    // The columns resultColumns() names, in its order, and no other: lines as pgt writes them.
    bool asWritten() const { return asWritten_; }
    const std::vector<std::string>& unknown() const { return unknown_; }  // not pgt's columns

    // `column`'s field of a whole row of the file (size() fields); `column` is one of
    // resultColumns().
    const std::string& field(const std::vector<std::string>& row, const std::string& column) const;
    // The case a whole row is of: its key columns read into `c` (ResultColumn::caseField);
    // false when one is not a number.
    bool readCase(const std::vector<std::string>& row, StudyCase* c) const;
    // A whole row written as pgt writes it: resultColumns()' order, unknown columns left out.
    std::string line(const std::vector<std::string>& row) const;

  private:
    std::vector<std::string> names_, unknown_;
    std::map<std::string, size_t> at_;
    size_t rowsFrom_ = 0;
    bool asWritten_ = false;
};

// "pgt: note: PATH: columns X, Y are not pgt's: left out of WHAT" on stderr, when the header
// has any.
void noteUnknownColumns(const std::string& path, const ResultHeader& head, const std::string& what);

}  // namespace pgt
