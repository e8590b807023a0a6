// The process-wide memory budget and the one refusal message for estimates over it.
#include "core/memory.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>

#include "core/error.h"
#include "core/format.h"

namespace pgt {

namespace {
std::atomic<uint64_t> gLimitMb{0};  // 0: not set, use the default
}

uint64_t defaultMemoryLimitMb() {
    long pages = ::sysconf(_SC_PHYS_PAGES), pageSize = ::sysconf(_SC_PAGESIZE);
    if (pages <= 0 || pageSize <= 0) return kDefaultMemoryLimitMb;
    uint64_t physicalMb = uint64_t(pages) * uint64_t(pageSize) >> 20;
    return std::min(kDefaultMemoryLimitMb, physicalMb / 4 * 3);
}

void setMemoryLimitMb(uint64_t mb) { gLimitMb = mb; }

uint64_t memoryLimitMb() {
    uint64_t mb = gLimitMb;
    return mb ? mb : defaultMemoryLimitMb();
}

void checkMemory(double bytes, const std::string& file, const std::string& field,
                 const std::string& value, const std::string& what) {
    const double limit = double(memoryLimitMb()) * 1024 * 1024;
    if (!(bytes <= limit)) {  // also refuses a NaN estimate
        std::string need = std::isfinite(bytes)
                               ? formatNumber(std::ceil(bytes / (1024 * 1024)), 15) + " MB"
                               : std::string("an unbounded amount");
        throw InputError(file, field, value,
                         what + " needs about " + need + ", more than the memory limit of " +
                             std::to_string(memoryLimitMb()) +
                             " MB (raise it with --memory-limit MB)");
    }
}

namespace {
const char* tunables() { return std::getenv("GLIBC_TUNABLES"); }
}  // namespace

bool hugePagesTunableGiven() {
    const char* t = tunables();
    return t && std::strstr(t, kHugePagesTunable);
}

bool mallocOnHugePages() {
    const char* t = tunables();
    const std::string on = std::string(kHugePagesTunable) + "=";
    return t && (std::strstr(t, (on + "1").c_str()) || std::strstr(t, (on + "2").c_str()));
}

}  // namespace pgt
