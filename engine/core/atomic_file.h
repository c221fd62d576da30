// Writing a file so that readers see either nothing or the complete file: data goes to a temporary file
// beside the target, which is renamed over the target only by commit(). Destroyed without commit() (an
// exception, a failed write), the temporary file is removed: no partial output is left behind.
//
//   th::AtomicFile out("features.csv");
//   out.stream() << "time_s,f0_hz\n";
//   out.commit();                         // throws th::Error naming the file if anything failed
//
// Thread contract: one thread per instance.
#pragma once

#include <filesystem>
#include <fstream>

namespace th {

class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path target);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ostream& stream() { return stream_; }
  const std::filesystem::path& temporaryPath() const { return temporary_; }
  void commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path temporary_;
  std::ofstream stream_;
  bool committed_ = false;
};

// Fails early, before any work, where an AtomicFile for `target` would fail at the end: its folder does not
// exist, or the target is a folder. Throws th::Error naming the target.
void checkOutputTarget(const std::filesystem::path& target);

}  // namespace th
