// Real speech for the feature tests, read once per process from the shared data folder.
#pragma once

#include <vector>

namespace th::test {

// The first `seconds` of the BEAT2 recording (16 kHz mono), the speaker every model trains on.
const std::vector<float>& beat2Speech(double seconds);

}  // namespace th::test
