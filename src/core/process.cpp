// Children that die with pgt (core/process.h): fork with PR_SET_PDEATHSIG, a pipe read while
// the cancel flag, the clock and the child's memory are polled.
#include "core/process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <stdexcept>

#include "core/interrupt.h"

namespace pgt {

namespace {

// The child's own memory in MB: its private pages (/proc/PID/smaps_rollup). A forked child
// shares every page of pgt until it writes one, so its resident set would count pgt's.
double privateMb(pid_t pid) {
    char path[64];
    std::snprintf(path, sizeof path, "/proc/%d/smaps_rollup", int(pid));
    FILE* f = std::fopen(path, "r");
    if (!f) return 0;
    char line[256];
    unsigned long kb = 0, v = 0;
    while (std::fgets(line, sizeof line, f))
        if (std::sscanf(line, "Private_Clean: %lu kB", &v) == 1 ||
            std::sscanf(line, "Private_Dirty: %lu kB", &v) == 1)
            kb += v;
    std::fclose(f);
    return double(kb) / 1024.0;
}

// In the child, first thing: die with the parent (SIGKILL when the thread that forked exits),
// and leave pgt's signal cleanup to pgt (a terminal's Ctrl-C reaches the whole group).
void becomeChild(pid_t parent) {
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(126);  // the parent died before the line above
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) ::signal(sig, SIG_DFL);
}

void reap(pid_t pid, int* status) {
    while (::waitpid(pid, status, 0) < 0 && errno == EINTR) {
    }
}

}  // namespace

namespace {

// Reads the child's pipe to its end and reaps it, polling the cancel flag, the clock and the
// child's memory meanwhile (a limit reached kills it with SIGKILL and says which).
ChildStatus waitForChild(pid_t pid, int fd, const ChildLimits& limits, std::string* out) {
    const auto t0 = std::chrono::steady_clock::now();
    auto elapsed = [&] {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    };
    ChildStatus st;
    bool eof = false, killed = false;
    int status = 0;
    double lastMemoryPoll = -1;
    for (;;) {
        if (!eof) {
            pollfd p{fd, POLLIN, 0};
            if (::poll(&p, 1, 20) > 0) {
                char buf[65536];
                const ssize_t n = ::read(fd, buf, sizeof buf);
                if (n > 0 && out) out->append(buf, size_t(n));
                if (n == 0 || (n < 0 && errno != EINTR && errno != EAGAIN)) eof = true;
            }
        } else {
            const pid_t w = ::waitpid(pid, &status, WNOHANG);
            if (w == pid || (w < 0 && errno != EINTR)) break;
            ::usleep(10000);
        }
        if (killed) continue;
        if (cancelRequested()) {
            ::kill(pid, SIGKILL);
            reap(pid, &status);
            throw Cancelled();
        }
        const double now = elapsed();
        if (limits.seconds > 0 && now > limits.seconds) {
            ::kill(pid, SIGKILL);
            killed = true, st.end = ChildEnd::TimedOut;
        } else if (limits.memoryMb > 0 && now - lastMemoryPoll >= 0.05) {
            lastMemoryPoll = now;
            st.peakMb = std::max(st.peakMb, privateMb(pid));
            if (st.peakMb > limits.memoryMb) {
                ::kill(pid, SIGKILL);
                killed = true, st.end = ChildEnd::OverMemory;
            }
        }
    }
    st.seconds = elapsed();
    if (!killed) {
        st.end = WIFEXITED(status) ? ChildEnd::Exited : ChildEnd::Signalled;
        st.code = WIFEXITED(status)     ? WEXITSTATUS(status)
                  : WIFSIGNALED(status) ? WTERMSIG(status)
                                        : -1;
    }
    return st;
}

}  // namespace

ChildStatus runInChild(const std::function<int(int fd)>& body, const ChildLimits& limits,
                       std::string* out) {
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error("cannot make a pipe for a child");
    const pid_t parent = ::getpid();
    const pid_t pid = ::fork();
    if (pid < 0) {
        ::close(fds[0]);
        ::close(fds[1]);
        throw std::runtime_error("cannot start a child process");
    }
    if (pid == 0) {  // no exception, no return: the caller's stack belongs to the parent
        becomeChild(parent);
        ::close(fds[0]);
        int code = 125;
        try {
            code = body(fds[1]);
        } catch (...) {
        }
        ::_exit(code);
    }
    ::close(fds[1]);
    try {
        const ChildStatus st = waitForChild(pid, fds[0], limits, out);
        ::close(fds[0]);
        return st;
    } catch (...) {
        ::close(fds[0]);
        throw;
    }
}

int runProgram(const std::vector<std::string>& argv, bool quiet) {
    if (argv.empty()) return -1;
    // Everything the child touches is made before the fork (no allocation after it).
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    const int devNull = quiet ? ::open("/dev/null", O_WRONLY | O_CLOEXEC) : -1;
    const ChildStatus st = runInChild(
        [&](int) {
            if (devNull >= 0) ::dup2(devNull, 1), ::dup2(devNull, 2);
            ::execv(args[0], args.data());
            return 127;  // not started
        },
        {}, nullptr);
    if (devNull >= 0) ::close(devNull);
    if (st.end != ChildEnd::Exited || st.code == 127) return -1;
    return st.code;
}

}  // namespace pgt
