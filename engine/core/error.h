// Errors that cross the engine's set-up and I/O boundaries.
//
//   try { auto clip = th::audio::readAudioFile("in.wav"); }
//   catch (const th::Error& e) { std::cerr << e.what() << '\n'; }   // "in.wav: not an audio file (...)"
//
// Thread contract: plain value types, no shared state.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace th {

// One line of text that names the thing at fault and what is wrong with it.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A job stopped because its caller asked it to (a cancel hook, an interrupt): not a fault, and no output left.
class Cancelled : public Error {
 public:
  Cancelled() : Error("cancelled; no output was written") {}
};

// "PATH: what" — the form every file-related error takes, so the CLI can print it as is.
inline Error fileError(const std::filesystem::path& path, const std::string& what) {
  return Error(path.string() + ": " + what);
}

}  // namespace th
