// Starting another program (the report script) with an argument vector: no shell, so no
// argument is ever parsed as shell syntax (a quote or `;` in an output path is a path).
#pragma once

#include <string>
#include <vector>

namespace pgt {

// Runs argv[0] (an absolute path) with `argv` and waits. Returns the exit status, or -1
// when it could not be started or ended by a signal. `quiet` sends its stdout and stderr
// to /dev/null.
int runProgram(const std::vector<std::string>& argv, bool quiet = false);

}  // namespace pgt
