// Interrupts (Ctrl-C, SIGTERM) end a long job cleanly: the job's loop sees the flag and stops (export: throws,
// and the writers' destructors remove their temporary files; live: stops listening and writes what it has).
// The handler only sets the flag (async-signal-safe).
//
//   InterruptGuard guard;                  // installs the handlers; the previous ones come back with it
//   while (...) { InterruptGuard::check(); ... }     or     if (InterruptGuard::requested()) break;
//
// Thread contract: the flag may be read from any thread.
#pragma once

#include <atomic>
#include <csignal>

#include "core/error.h"

namespace th::app {

inline std::atomic<bool> interruptRequested{false};
extern "C" inline void onInterrupt(int) {
  interruptRequested.store(true);
}

class InterruptGuard {
 public:
  InterruptGuard() {
    interruptRequested.store(false);
    previousInt_ = std::signal(SIGINT, onInterrupt);
    previousTerm_ = std::signal(SIGTERM, onInterrupt);
  }
  ~InterruptGuard() {
    std::signal(SIGINT, previousInt_);
    std::signal(SIGTERM, previousTerm_);
  }
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;
  static bool requested() { return interruptRequested.load(); }
  static void check() {
    if (requested()) throw Error("interrupted; no output was written");
  }

 private:
  void (*previousInt_)(int) = nullptr;
  void (*previousTerm_)(int) = nullptr;
};

}  // namespace th::app
