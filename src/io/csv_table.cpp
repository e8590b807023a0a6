// RFC 4180 quoting and reading for the CSV tables of io/csv_table.h.
#include "io/csv_table.h"

namespace pgt {

std::string csvQuote(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        if (c == '"') out += '"';
        out += c;
    }
    return out + "\"";
}

std::string csvField(const std::string& s) {
    return s.find_first_of(",\"\r\n") == std::string::npos ? s : csvQuote(s);
}

std::vector<std::vector<std::string>> splitCsvRecords(const std::string& text, size_t from,
                                                      bool* torn) {
    std::vector<std::vector<std::string>> records;
    std::vector<std::string> fields;
    std::string cur;
    bool quoted = false;
    for (size_t i = from; i < text.size(); ++i) {
        char ch = text[i];
        if (quoted) {
            if (ch == '"' && i + 1 < text.size() && text[i + 1] == '"')
                cur += '"', ++i;
            else if (ch == '"')
                quoted = false;
            else
                cur += ch;
        } else if (ch == '"') {
            quoted = true;
        } else if (ch == ',') {
            fields.push_back(std::move(cur)), cur.clear();
        } else if (ch == '\n') {
            fields.push_back(std::move(cur)), cur.clear();
            records.push_back(std::move(fields)), fields.clear();
        } else {
            cur += ch;
        }
    }
    if (torn) *torn = quoted || !cur.empty() || !fields.empty();
    return records;
}

}  // namespace pgt
