// Staged output files (io/staged_files.h): hidden temporaries, checked writes, renamed
// into place together.
#include "io/staged_files.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <random>
#include <sstream>

#include "core/error.h"

namespace pgt {

namespace fs = std::filesystem;

namespace {

// Temporaries are hidden siblings named ".NAME.pgt-tmp.PID.RANDOM": the PID tells a later
// run whether the writer is still alive (kill(pid, 0)), so a killed run's leftovers are
// removed and a running one's are not.
constexpr const char* kTempTag = ".pgt-tmp.";

std::string tempName(const std::string& name) {
    static std::mt19937_64 rng(std::random_device{}());
    std::ostringstream os;
    os << "." << name << kTempTag << ::getpid() << "." << std::hex << (rng() & 0xffffff);
    return os.str();
}

// "STEM.tmpHEX.EXT" (1 to 6 hex digits; EXT exr, png, json or csv): what earlier pgt
// versions named their temporaries. Written out by hand: std::regex draws GCC 12 warnings.
bool isLegacyTemporary(const std::string& name) {
    auto dot = name.rfind('.');
    if (dot == std::string::npos) return false;
    std::string ext = name.substr(dot + 1), rest = name.substr(0, dot);
    if (ext != "exr" && ext != "png" && ext != "json" && ext != "csv") return false;
    auto tag = rest.rfind(".tmp");
    if (tag == std::string::npos || tag == 0) return false;
    std::string hex = rest.substr(tag + 4);
    return !hex.empty() && hex.size() <= 6 &&
           hex.find_first_not_of("0123456789abcdef") == std::string::npos;
}

// Removes temporaries of pgt processes that no longer run (killed mid-write), and the
// "NAME.tmpHEX.EXT" temporaries of earlier pgt versions.
void removeStaleTemporaries(const std::string& dir) {
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        bool stale = false;
        auto tag = name.find(kTempTag);
        if (!name.empty() && name[0] == '.' && tag != std::string::npos) {
            long pid = std::strtol(name.c_str() + tag + std::strlen(kTempTag), nullptr, 10);
            stale = pid > 0 && ::kill(pid_t(pid), 0) != 0 && errno == ESRCH;
        } else {
            stale = isLegacyTemporary(name);
        }
        std::error_code rm;
        if (stale && it->is_regular_file(rm)) fs::remove(it->path(), rm);
    }
}

}  // namespace

StagedFiles::StagedFiles(std::string dir) : dir_(std::move(dir)) {}

StagedFiles::~StagedFiles() {
    std::error_code ec;
    for (const Staged& s : staged_) fs::remove(s.tmp, ec);
}

StagedStream::StagedStream(const std::string& tmp, const std::string& shown)
    : IOProxy(shown, Write), tmp_(tmp), shown_(shown) {
    fd_ = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd_ < 0) throw OutputError("cannot create " + shown + ": " + std::strerror(errno));
}

StagedStream::~StagedStream() {
    if (fd_ >= 0) ::close(fd_);
}

size_t StagedStream::pwrite(const void* buf, size_t size, int64_t offset) {
    std::lock_guard<std::mutex> lock(mutex_);
    size_t done = 0;
    while (done < size && !err_) {
        ssize_t n = ::pwrite(fd_, static_cast<const char*>(buf) + done, size - done,
                             off_t(offset) + off_t(done));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0)
            err_ = n < 0 ? errno : EIO;
        else
            done += size_t(n);
    }
    end_ = std::max(end_, offset + int64_t(done));
    return done;
}

size_t StagedStream::write(const void* buf, size_t size) {
    size_t n = pwrite(buf, size, m_pos);
    m_pos += int64_t(n);
    return n;
}

void StagedStream::finish() {
    int err = err_;
    if (!err && ::fsync(fd_) != 0) err = errno;
    if (::close(fd_) != 0 && !err) err = errno;
    fd_ = -1;
    if (err) throw OutputError("cannot write " + shown_ + ": " + std::strerror(err));
}

StagedStream& StagedFiles::stream(const std::string& name) {
    const std::string tmp = (fs::path(dir_) / tempName(name)).string();
    const std::string path = (fs::path(dir_) / name).string();
    // Removed on destruction unless committed; by a signal's handler in the CLI.
    staged_.push_back({tmp, path, std::make_unique<CleanupPath>(tmp, CleanupPath::kFile)});
    streams_.push_back(std::make_unique<StagedStream>(tmp, path));
    return *streams_.back();
}

void StagedFiles::add(const std::string& name, const std::string& bytes) {
    StagedStream& out = stream(name);
    out.write(bytes.data(), bytes.size());
    out.finish();
}

void StagedFiles::commit() {
    for (const auto& s : streams_) PGT_CHECK(s->finished());  // every stream finished
    // Every target a file or absent before anything moves: a directory in the way fails the
    // whole set, the earlier files untouched.
    for (const Staged& s : staged_) {
        std::error_code ec;
        const fs::file_status st = fs::symlink_status(s.path, ec);
        if (fs::exists(st) && !fs::is_regular_file(st) && !fs::is_symlink(st))
            throw OutputError("cannot write " + s.path + ": " +
                              (fs::is_directory(st) ? "a directory is in the way"
                                                    : "something other than a file is in the way") +
                              " (nothing of this output was written)");
    }
    // Each file already there is linked to a hidden backup first, so that a rename failing
    // part-way puts every earlier one back: the set is replaced whole or not at all.
    std::vector<std::string> backups(staged_.size());
    std::vector<bool> existed(staged_.size(), false);
    std::vector<std::unique_ptr<CleanupPath>> guards;
    for (size_t k = 0; k < staged_.size(); ++k) {
        std::error_code ec;
        existed[k] = fs::exists(fs::symlink_status(staged_[k].path, ec));
        if (!fs::is_regular_file(fs::symlink_status(staged_[k].path, ec))) continue;
        const std::string backup =
            (fs::path(dir_) / tempName(fs::path(staged_[k].path).filename().string())).string();
        fs::create_hard_link(staged_[k].path, backup, ec);
        if (ec) continue;  // no hard links here: that file alone is not restorable
        backups[k] = backup;
        guards.push_back(std::make_unique<CleanupPath>(backup, CleanupPath::kFile));
    }
    for (size_t k = 0; k < staged_.size(); ++k) {
        std::error_code ec;
        fs::rename(staged_[k].tmp, staged_[k].path, ec);
        if (!ec) continue;
        const std::string why = ec.message();
        // Put the earlier ones back: a file that was there from its backup, a new one
        // removed; one that was there without a backup (no hard links, a symlink) stays
        // replaced, and the message says so.
        std::string replaced;
        for (size_t j = 0; j < k; ++j) {
            std::error_code back;
            if (!backups[j].empty())
                fs::rename(backups[j], staged_[j].path, back);
            else if (!existed[j])
                fs::remove(staged_[j].path, back);
            if (back || (existed[j] && backups[j].empty()))
                replaced += (replaced.empty() ? "" : ", ") + staged_[j].path;
        }
        for (const std::string& b : backups)
            if (!b.empty()) fs::remove(b, ec);
        throw OutputError("cannot write " + staged_[k].path + ": " + why +
                          (replaced.empty() ? " (nothing of this output was written)"
                                            : " (already replaced: " + replaced + ")"));
    }
    for (const std::string& b : backups) {
        std::error_code ec;
        if (!b.empty()) fs::remove(b, ec);
    }
    staged_.clear();
}

void makeOutputDir(const std::string& dir) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir))
        throw OutputError("cannot create output directory " + dir +
                          (ec ? ": " + ec.message() : std::string()));
    removeStaleTemporaries(dir);
}

void prepareOutputDir(const std::string& dir) {
    makeOutputDir(dir);
    StagedFiles probe(dir);  // a file can be created there (removed again, uncommitted)
    probe.add("probe", "");
}

OutputDirectory::OutputDirectory(const std::string& dir) {
    // The topmost missing component: what creating `dir` makes.
    std::error_code ec;
    fs::path p = fs::absolute(dir, ec).lexically_normal();
    std::vector<fs::path> missing;
    std::error_code missingOk;  // status of a path that is not there: an error code too
    for (; !ec && !p.empty() && !fs::exists(fs::symlink_status(p, missingOk));
         p = p.parent_path()) {
        missing.push_back(p);
        if (p == p.parent_path()) break;
    }
    if (!missing.empty()) created_ = missing.back().string();
    for (auto it = missing.rbegin(); it != missing.rend(); ++it)
        onSignal_.push_back(
            std::make_unique<CleanupPath>(it->string(), CleanupPath::kEmptyDirectory));
    try {
        prepareOutputDir(dir);
    } catch (...) {
        std::error_code rm;  // a destructor does not run for a throwing constructor
        if (!created_.empty()) fs::remove_all(created_, rm);
        throw;
    }
}

OutputDirectory::~OutputDirectory() {
    onSignal_.clear();
    if (keep_ || created_.empty()) return;
    std::error_code ec;
    fs::remove_all(created_, ec);
    created_.clear();
}

void writeTextFile(const std::string& path, const std::string& text) {
    fs::path p(path);
    StagedFiles files(p.parent_path().empty() ? "." : p.parent_path().string());
    files.add(p.filename().string(), text);
    files.commit();
}

}  // namespace pgt
