// A uniquely named file, or folder, in the system's temporary folder, removed when the object goes out of scope.
//
//   th::TemporaryFile script(".praat");
//   std::ofstream(script.path()) << text;
//   th::TemporaryFolder folder;                 // removed with everything in it, read-only sub-folders too
//
// Thread contract: names are unique across threads and processes (pid + atomic counter).
#pragma once

#include <filesystem>
#include <string>

namespace th {

class TemporaryFile {
 public:
  explicit TemporaryFile(const std::string& suffix);
  ~TemporaryFile();
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

class TemporaryFolder {
 public:
  TemporaryFolder();
  ~TemporaryFolder();
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace th
