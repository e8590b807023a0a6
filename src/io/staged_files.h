// Output files written whole or not at all. Each file goes to a hidden temporary in its
// directory (every write checked, then flushed to the disk), and the files of one output are
// renamed into place together, so a failure (a full disk) leaves nothing half-written and no
// final-looking file. A file can be given whole (add) or written piece by piece (stream:
// an OpenImageIO IOProxy, so an image encoder writes straight into it).
#pragma once

#include <OpenImageIO/filesystem.h>

#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "core/interrupt.h"

namespace pgt {

// A staged file being written. Writes are checked; the first error is kept and the file
// refuses further bytes (the encoder then sees a short write). finish() flushes it to the
// disk and throws OutputError naming the final path when anything failed.
class StagedStream : public OIIO_NAMESPACE::Filesystem::IOProxy {
  public:
    StagedStream(const std::string& tmp, const std::string& shown);
    ~StagedStream() override;
    const char* proxytype() const override { return "pgt-staged"; }
    size_t write(const void* buf, size_t size) override;
    size_t pwrite(const void* buf, size_t size, int64_t offset) override;
    size_t size() const override { return size_t(end_); }
    void close() override {}  // finish() closes
    bool finished() const { return fd_ < 0; }
    void finish();

  private:
    std::string tmp_, shown_;
    int fd_ = -1;
    int err_ = 0;
    int64_t end_ = 0;
    std::mutex mutex_;
};

// Files of one output, each written whole to a hidden temporary in `dir`, then renamed into
// place together by commit(); whatever is not committed is removed on destruction.
class StagedFiles {
  public:
    explicit StagedFiles(std::string dir);
    ~StagedFiles();
    StagedFiles(const StagedFiles&) = delete;
    StagedFiles& operator=(const StagedFiles&) = delete;
    // Writes `bytes` to a temporary for DIR/name; throws OutputError (the write, the flush
    // or the close failed, e.g. no space left) after removing it.
    void add(const std::string& name, const std::string& bytes);
    // A temporary for DIR/name to write piece by piece; finish() it before commit().
    StagedStream& stream(const std::string& name);
    void commit();

  private:
    struct Staged {
        std::string tmp, path;
        std::unique_ptr<CleanupPath> onSignal;  // a signal unlinks the temporary
    };
    std::string dir_;
    std::vector<Staged> staged_;
    std::vector<std::unique_ptr<StagedStream>> streams_;
};

// Replaces `path` atomically with `text`.
void writeTextFile(const std::string& path, const std::string& text);

// Creates `dir` (and its parents) and removes the temporaries that killed pgt processes left
// there. Throws OutputError naming `dir`.
void makeOutputDir(const std::string& dir);

// makeOutputDir, and checks that a file can be created in `dir`.
void prepareOutputDir(const std::string& dir);

// The output directory of a command whose files are all or nothing (render, fit, merge):
// prepared (prepareOutputDir) on construction; unless keep() is called, the directories it
// created (and only those: `dir` and any missing parents) are removed with what is in them
// on destruction, so a failed or cancelled run leaves no empty --out behind. A signal that
// ends the CLI removes them too when they hold only temporaries (core/interrupt.h).
class OutputDirectory {
  public:
    explicit OutputDirectory(const std::string& dir);
    ~OutputDirectory();
    OutputDirectory(const OutputDirectory&) = delete;
    OutputDirectory& operator=(const OutputDirectory&) = delete;
    void keep() { keep_ = true; }

  private:
    std::string created_;  // the topmost directory this made ("" if `dir` existed)
    std::vector<std::unique_ptr<CleanupPath>> onSignal_;
    bool keep_ = false;
};

}  // namespace pgt
