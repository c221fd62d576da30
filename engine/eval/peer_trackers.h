// The F0 trackers we compare against, all Debian packages run as they ship: Praat's "To Pitch (ac)",
// SPTK's RAPT and SWIPE (`sptk pitch -a 0|1`), and aubio's yinfft (`aubiopitch`).
//
//   th::eval::F0Track track = th::eval::runPeerTracker(th::eval::PeerTracker::kPraat, wav, {0.005, 60, 500});
//
// Every peer reads the original file at its own sample rate; each returns frame times and F0 (0 = unvoiced).
// Thread contract: any thread; each call makes its own temporary files.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "eval/pitch_evaluation.h"

namespace th::eval {

enum class PeerTracker { kPraat, kRapt, kSwipe, kAubioYinFft };

struct PeerSettings {
  double hopSeconds = 0.005;
  double minF0Hz = 60.0;
  double maxF0Hz = 500.0;
};

std::vector<PeerTracker> allPeerTrackers();
std::string peerName(PeerTracker peer);
std::string peerProgram(PeerTracker peer);  // the executable it needs
F0Track runPeerTracker(PeerTracker peer, const std::filesystem::path& wav, const PeerSettings& settings);

}  // namespace th::eval
