// A file being written that appears under its target's name only when complete: for writers that need a path
// of their own to write to (FFmpeg's muxer reopens the file by name), where core/atomic_file.h's stream will not
// do. All or nothing, as AtomicFile: a writer that fails or is destroyed before commit() leaves no file and the
// old target untouched.
//
//   th::PendingFile file("talk.mp4", /*unnamed=*/true);
//   writeTo(file.url());     // "file:/proc/self/fd/N", or "file:.talk.mp4.PID.0.tmp" beside the target
//   file.commit();           // only now is talk.mp4 there, replacing what was, in one step
//
// Preferably an unnamed O_TMPFILE in the target's folder, which the kernel frees if the process dies, opened as
// /proc/self/fd/N; where O_TMPFILE or /proc is missing, a hidden named file beside the target, removed by the
// destructor. Errors are th::Error naming the target ("cannot be written: ...").
// Thread contract: one thread per instance.
#pragma once

#include <filesystem>
#include <string>

#include "core/error.h"

namespace th {

class PendingFile {
 public:
  PendingFile(std::filesystem::path target, bool unnamed);
  ~PendingFile();
  PendingFile(const PendingFile&) = delete;
  PendingFile& operator=(const PendingFile&) = delete;

  // What FFmpeg opens ("file:" keeps a name with a colon in it from being read as a protocol).
  std::string url() const { return "file:" + path_.string(); }
  // Gives the complete file the target's name, replacing whatever was there in one step.
  void commit();

 private:
  bool openUnnamed();  // an O_TMPFILE that can be opened through /proc; false where the system lacks either
  std::filesystem::path hiddenName(int attempt) const;
  Error cannotWrite(int code) const;

  std::filesystem::path target_;
  std::filesystem::path folder_;
  std::filesystem::path path_;  // /proc/self/fd/N of the unnamed file, or the hidden named file
  int descriptor_ = -1;         // keeps the unnamed file alive
  bool named_ = false;
  bool committed_ = false;
};

}  // namespace th
