// CSV tables declared once: each column's name beside how a row writes it, so a header and
// its rows cannot drift apart; fields quoted as RFC 4180 says; the reader for resuming.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace pgt {

// `s` between double quotes, inner quotes doubled.
std::string csvQuote(const std::string& s);
// `s` as is, or quoted when it holds a comma, a quote or a line break.
std::string csvField(const std::string& s);

// Splits CSV text from byte `from` into records of fields (quoted fields may hold commas,
// quotes and line breaks). `torn` (where given) is set when the text does not end with a
// whole record.
std::vector<std::vector<std::string>> splitCsvRecords(const std::string& text, size_t from,
                                                      bool* torn);

template <class Row>
struct CsvColumn {
    std::string name;
    std::function<std::string(const Row&)> value;
    bool quoted = false;  // always quoted (a JSON value), not only when it must be
};

template <class Row>
class CsvTable {
  public:
    explicit CsvTable(std::vector<CsvColumn<Row>> columns) : columns_(std::move(columns)) {}

    std::vector<std::string> names() const {
        std::vector<std::string> out;
        for (const auto& c : columns_) out.push_back(c.name);
        return out;
    }
    std::string header() const {
        std::vector<std::string> n = names();
        return join(n, false);
    }
    std::string line(const Row& row) const {
        std::vector<std::string> fields;
        for (const auto& c : columns_) fields.push_back(c.value(row));
        return join(fields, true);
    }
    // A record read back (splitCsvRecords), written exactly as line() wrote it.
    std::string line(const std::vector<std::string>& fields) const { return join(fields, true); }
    size_t size() const { return columns_.size(); }

  private:
    std::string join(const std::vector<std::string>& fields, bool quoteAsDeclared) const {
        std::string out;
        for (size_t k = 0; k < fields.size(); ++k) {
            bool always = quoteAsDeclared && k < columns_.size() && columns_[k].quoted;
            if (k) out.push_back(',');  // not "," + string: GCC 12 warns falsely (-Wrestrict)
            out.append(always ? csvQuote(fields[k]) : csvField(fields[k]));
        }
        return out + "\n";
    }
    std::vector<CsvColumn<Row>> columns_;
};

}  // namespace pgt
