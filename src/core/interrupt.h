// Interruptions: a run stopped from outside (Ctrl-C in Python, a signal to the CLI) must stop
// within about a second and leave nothing behind (docs/testing.md "What pgt promises"). Two
// mechanisms: a cancel flag that long loops poll (the Python module sets it on
// KeyboardInterrupt; the work then unwinds, and destructors remove its temporaries), and,
// for the CLI, a signal handler that removes the registered temporaries and created
// directories itself and ends the process as the signal would have.
#pragma once

#include <stdexcept>
#include <string>

namespace pgt {

// Thrown by throwIfCancelled once a cancel was requested.
class Cancelled : public std::runtime_error {
  public:
    Cancelled() : std::runtime_error("cancelled") {}
};

// The process-wide cancel flag (thread-safe). requestCancel sets it; clearCancel resets it
// for the next call.
void requestCancel();
void clearCancel();
bool cancelRequested();
// Polled by long loops: bands, cases, map builds, timing passes. Cheap (one relaxed load).
inline void throwIfCancelled() {
    if (cancelRequested()) throw Cancelled();
}

// A path that a signal ending the process must not leave behind, registered while it
// exists: a staged file's temporary (unlinked), or an output directory this run created
// (removed when empty by then, i.e. holding only temporaries). At most 1024 at once; beyond
// that a path is not registered (a later run's stale-temporary sweep removes a temporary).
class CleanupPath {
  public:
    enum Kind { kFile, kEmptyDirectory };
    CleanupPath(const std::string& path, Kind kind);
    ~CleanupPath();  // unregisters; removes nothing
    CleanupPath(const CleanupPath&) = delete;
    CleanupPath& operator=(const CleanupPath&) = delete;

  private:
    int slot_ = -1;
};

// The CLI's handlers for SIGINT, SIGTERM and SIGHUP: unlink the registered files, remove the
// registered directories (deepest first; only empty ones), then end the process by the same
// signal with its default action (exit status 128 + signal in a shell).
void installSignalCleanup();

// The same handler for SIGTERM and SIGHUP while one is alive, where their action is the
// default (the process ends): the Python module's calls, so that a terminated interpreter
// leaves no temporary or created --out behind. A handler the host installed stays its own;
// scopes nest and may overlap across threads (the last one alive restores).
class SignalCleanupScope {
  public:
    SignalCleanupScope();
    ~SignalCleanupScope();
    SignalCleanupScope(const SignalCleanupScope&) = delete;
    SignalCleanupScope& operator=(const SignalCleanupScope&) = delete;
};

}  // namespace pgt
