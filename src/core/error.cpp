// Programmer-error reporting for PGT_CHECK.
#include "core/error.h"

namespace pgt::detail {

void checkFailed(const char* expr, const char* file, int line, const std::string& values) {
    std::ostringstream os;
    os << "internal check failed: " << expr << " at " << file << ":" << line;
    if (!values.empty()) os << " (" << values << ")";
    throw std::logic_error(os.str());
}

}  // namespace pgt::detail
