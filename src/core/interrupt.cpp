// The cancel flag and the signal-time cleanup (core/interrupt.h). The registry is read by a
// signal handler, so its entries are fixed buffers guarded by a sequence number: the handler
// copies a path and uses it only if the sequence did not move meanwhile.
#include "core/interrupt.h"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <mutex>

namespace pgt {

namespace {

std::atomic<bool> gCancel{false};

// A registry slot. seq's low two bits: 0 free, 1 being written, 2 in use; the rest counts
// generations, so a handler that reads a slot while it changes sees seq move.
struct Slot {
    std::atomic<uint64_t> seq{0};
    std::atomic<int> kind{0};
    char path[4096];
};
constexpr int kSlots = 1024;
Slot gSlots[kSlots];

// The handler's copy of a slot's path when the slot is in use and stayed so; false otherwise.
bool readSlot(const Slot& s, char (&out)[4096], int& kind) {
    const uint64_t before = s.seq.load(std::memory_order_acquire);
    if ((before & 3) != 2) return false;
    for (size_t k = 0; k < sizeof out; ++k) {  // by hand: memcpy is not async-signal-safe
        out[k] = s.path[k];
        if (!out[k]) break;
    }
    out[sizeof out - 1] = 0;
    kind = s.kind.load(std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_acquire);
    return s.seq.load(std::memory_order_relaxed) == before;
}

void cleanupOnSignal(int sig) {
    char path[4096];
    int kind = 0;
    for (int i = 0; i < kSlots; ++i)  // the files first
        if (readSlot(gSlots[i], path, kind) && kind == CleanupPath::kFile) ::unlink(path);
    // Then the directories, children before parents: each pass removes the empty ones.
    for (int pass = 0; pass < 16; ++pass)
        for (int i = 0; i < kSlots; ++i)
            if (readSlot(gSlots[i], path, kind) && kind == CleanupPath::kEmptyDirectory)
                ::rmdir(path);
    ::signal(sig, SIG_DFL);
    ::raise(sig);
}

}  // namespace

void requestCancel() { gCancel.store(true, std::memory_order_relaxed); }
void clearCancel() { gCancel.store(false, std::memory_order_relaxed); }
bool cancelRequested() { return gCancel.load(std::memory_order_relaxed); }

CleanupPath::CleanupPath(const std::string& path, Kind kind) {
    if (path.size() >= sizeof(Slot::path)) return;
    for (int i = 0; i < kSlots; ++i) {
        uint64_t s = gSlots[i].seq.load(std::memory_order_relaxed);
        if ((s & 3) != 0 || !gSlots[i].seq.compare_exchange_strong(s, s + 1)) continue;
        std::memcpy(gSlots[i].path, path.c_str(), path.size() + 1);
        gSlots[i].kind.store(int(kind), std::memory_order_relaxed);
        gSlots[i].seq.store(s + 2, std::memory_order_release);
        slot_ = i;
        return;
    }
}

CleanupPath::~CleanupPath() {
    if (slot_ < 0) return;
    const uint64_t s = gSlots[slot_].seq.load(std::memory_order_relaxed);
    gSlots[slot_].seq.store((s & ~uint64_t(3)) + 4, std::memory_order_release);
}

void installSignalCleanup() {
    struct sigaction sa {};
    sa.sa_handler = cleanupOnSignal;
    sigemptyset(&sa.sa_mask);
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&sa.sa_mask, sig);
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) ::sigaction(sig, &sa, nullptr);
}

namespace {
constexpr int kScopedSignals[2] = {SIGTERM, SIGHUP};
// Scopes alive (Python threads may call pgt at once): the first installs, the last restores.
std::mutex gScopeMutex;
int gScopes = 0;
struct sigaction gBefore[2];
bool gInstalled[2] = {false, false};
}  // namespace

SignalCleanupScope::SignalCleanupScope() {
    std::lock_guard<std::mutex> lock(gScopeMutex);
    if (gScopes++ > 0) return;
    for (int k = 0; k < 2; ++k) {
        gInstalled[k] = false;
        if (::sigaction(kScopedSignals[k], nullptr, &gBefore[k]) != 0 ||
            gBefore[k].sa_handler != SIG_DFL || (gBefore[k].sa_flags & SA_SIGINFO))
            continue;
        struct sigaction sa {};
        sa.sa_handler = cleanupOnSignal;
        sigemptyset(&sa.sa_mask);
        for (int sig : kScopedSignals) sigaddset(&sa.sa_mask, sig);
        gInstalled[k] = ::sigaction(kScopedSignals[k], &sa, nullptr) == 0;
    }
}

SignalCleanupScope::~SignalCleanupScope() {
    std::lock_guard<std::mutex> lock(gScopeMutex);
    if (--gScopes > 0) return;
    for (int k = 0; k < 2; ++k) {
        struct sigaction now {};
        // Restored only where pgt's handler is still the one: a handler the host set
        // meanwhile stays.
        if (gInstalled[k] && ::sigaction(kScopedSignals[k], nullptr, &now) == 0 &&
            now.sa_handler == cleanupOnSignal)
            ::sigaction(kScopedSignals[k], &gBefore[k], nullptr);
    }
}

}  // namespace pgt
