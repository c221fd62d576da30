// Where the shared, read-only recordings live.
//
//   auto wav = th::sharedDataPath("speech/arctic/arctic_a0001.wav");
//
// The environment variable TALKINGHEAD_DATA overrides the folder fixed at build time (../shared/data).
// Thread contract: reads the environment only; safe from any thread.
#pragma once

#include <filesystem>

namespace th {

std::filesystem::path sharedDataDir();
std::filesystem::path sharedDataPath(const std::filesystem::path& relative);

}  // namespace th
