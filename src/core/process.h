// Child processes that die with pgt: another program (the report script) started with an
// argument vector and no shell (a quote or `;` in an output path is a path), and work that
// may crash, hang or swell (a shader compiler on hostile input) run in a forked child, where a
// crash is a message and a limit can stop it. Every child has PR_SET_PDEATHSIG(SIGKILL) set
// before anything else, so no child outlives pgt, even when pgt is killed with SIGKILL
// (docs/testing.md "What pgt promises").
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace pgt {

// What pgt holds a child to while it waits for it.
struct ChildLimits {
    double seconds = 0;   // wall-clock limit; 0: none
    double memoryMb = 0;  // the child's own memory (private pages, polled); 0: none
};

enum class ChildEnd { Exited, Signalled, TimedOut, OverMemory };

struct ChildStatus {
    ChildEnd end = ChildEnd::Exited;
    int code = 0;        // the exit status (Exited) or the signal (Signalled)
    double peakMb = 0;   // the largest private memory seen while polling
    double seconds = 0;  // how long it ran
};

// Forks a child that runs `body(fd)` and exits with its return value; fd is the write end of
// a pipe whose every byte the parent collects into `*out`. While waiting the parent polls the
// cancel flag (core/interrupt.h: a cancel kills the child and throws Cancelled), the clock and
// the child's memory (a limit reached kills it with SIGKILL and says which). The body runs in
// a copy of this process: it must not return into the caller's stack (it is called, then the
// child _exits) and should use what exists already.
ChildStatus runInChild(const std::function<int(int fd)>& body, const ChildLimits& limits,
                       std::string* out);

// Runs argv[0] (an absolute path) with `argv` and waits. Returns the exit status, or -1
// when it could not be started or ended by a signal. `quiet` sends its stdout and stderr
// to /dev/null. A cancel kills it and throws Cancelled.
int runProgram(const std::vector<std::string>& argv, bool quiet = false);

}  // namespace pgt
