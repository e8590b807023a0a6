// Programmer-error reporting for PGT_CHECK.
#include "core/error.h"

#include <cstdio>

namespace pgt {

std::string printable(const std::string& text, size_t maxChars, bool keepNewlines) {
    std::string out;
    for (size_t i = 0; i < text.size(); ++i) {
        if (out.size() >= maxChars) {
            out += "...";
            break;
        }
        auto c = static_cast<unsigned char>(text[i]);
        if ((c < 0x20 && !(keepNewlines && c == '\n')) || c == 0x7f) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", c);
            out += buf;
        } else {
            out += char(c);
        }
    }
    return out;
}

}  // namespace pgt

namespace pgt::detail {

void checkFailed(const char* expr, const char* file, int line, const std::string& values) {
    std::ostringstream os;
    os << "internal check failed: " << expr << " at " << file << ":" << line;
    if (!values.empty()) os << " (" << values << ")";
    throw std::logic_error(os.str());
}

}  // namespace pgt::detail
