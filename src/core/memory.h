// The memory budget for inputs that are valid but too large for the machine: every stage
// that allocates in proportion to an input (a map, a lattice, a refined mesh, a frame, a
// study's case list) estimates its need first and refuses, as bad input, past the limit.
#pragma once

#include <cstdint>
#include <string>

namespace pgt {

// Default limit: 8192 MiB, or three quarters of the machine's physical memory when that is
// less (`--memory-limit MB` sets another).
constexpr uint64_t kDefaultMemoryLimitMb = 8192;
uint64_t defaultMemoryLimitMb();

// The process's limit in MiB (set once by the CLI, before any work).
void setMemoryLimitMb(uint64_t mb);
uint64_t memoryLimitMb();

// Throws InputError(file, field, value) saying that `what` needs about `bytes` and what the
// limit is, when `bytes` exceeds it.
void checkMemory(double bytes, const std::string& file, const std::string& field,
                 const std::string& value, const std::string& what);

// glibc's malloc puts its large chunks on transparent huge pages when this tunable is 1 (or 2),
// read from GLIBC_TUNABLES only when a process starts (the `pgt` command restarts itself with
// it: cli/main.cpp; docs/performance.md).
inline constexpr const char* kHugePagesTunable = "glibc.malloc.hugetlb";
// Whether this process's environment names the tunable at all (a user's choice stands).
bool hugePagesTunableGiven();
// Whether it asks for huge pages (what summary.json's provenance reports).
bool mallocOnHugePages();

}  // namespace pgt
