// libFuzzer target: arbitrary bytes through the model-file loader (th::hmm::parseModel, which loadModel uses).
//
//   scripts/fuzz.sh                       # builds build-fuzz/ with clang and runs every fuzzer for a bounded time
//
// Rejecting input with th::Error is the expected outcome for nearly every input; anything else that escapes (an
// nlohmann exception, std::bad_alloc from a forged size, a crash, an ASan/UBSan report, a hang) is a finding.
// An accepted model must also survive the writer: formatModel takes it, and its text reads back to a model that
// formats to the same text (the writer refusing what the reader accepted, or a number changing, is a finding).
//
// Byte-level mutation alone mostly breaks the JSON syntax and never gets past the parser to the model checks
// (measured: 92% of a 150 s corpus was invalid JSON). So half the mutations are structural: the input is parsed
// and one value in the tree is changed (a number pushed to an edge the loader guards, an element dropped or
// repeated, a type swapped), and the result is written back as JSON. The target still sees plain bytes, and a
// crash file reproduces without this mutator.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/error.h"
#include "hmm/model_file.h"

extern "C" size_t LLVMFuzzerMutate(uint8_t* data, size_t size, size_t maxSize);

namespace {

using Json = nlohmann::ordered_json;

// Changes one value of the document in place. False if the document is too deep to write back safely
// (nlohmann's dump() recurses; the loader refuses such input anyway).
bool mutateOneValue(Json& document, std::minstd_rand& random) {
  std::vector<Json*> values;
  std::vector<std::pair<Json*, int>> pending{{&document, 0}};
  while (!pending.empty() && values.size() < 100000) {
    const auto [value, depth] = pending.back();
    pending.pop_back();
    if (depth > 100) return false;
    values.push_back(value);
    if (value->is_structured()) {
      for (auto& child : *value) pending.emplace_back(&child, depth + 1);
    }
  }
  auto pick = [&](size_t n) { return static_cast<size_t>(random() % n); };
  Json& target = *values[pick(values.size())];
  static const double kNumbers[] = {0.0,
                                    -0.0,
                                    1.0,
                                    -1.0,
                                    0.5,
                                    2.0,
                                    3.0,
                                    10000.0,
                                    10001.0,
                                    1000.0,
                                    1001.0,
                                    1e-150,
                                    1e-151,
                                    1e150,
                                    1e151,
                                    1e-300,
                                    5e-324,
                                    1.7976931348623157e308,
                                    -1.7976931348623157e308,
                                    1e-6,
                                    1.000001,
                                    0.999999};
  switch (pick(8)) {
    case 0:
      if (target.is_number()) {
        const double x = target.get<double>();
        const double changed[] = {x * (1.0 + 1e-7), x * (1.0 + 1e-12), -x, x + 1.0, x * 1e100, x * 1e-100};
        target = changed[pick(std::size(changed))];
      } else {
        target = kNumbers[pick(std::size(kNumbers))];
      }
      break;
    case 1:
      target = kNumbers[pick(std::size(kNumbers))];
      break;
    case 2: {
      const int64_t integers[] = {
          -1, 0, 1, 2, 3, std::numeric_limits<int64_t>::min(), std::numeric_limits<int64_t>::max()};
      if (pick(4) == 0) {
        target = std::numeric_limits<uint64_t>::max();
      } else {
        target = integers[pick(std::size(integers))];
      }
      break;
    }
    case 3: {
      const Json others[] = {nullptr,           true,   "x",        Json::array(), Json::object(),
                             "talkinghead-hmm", "full", "diagonal", "audio",       ""};
      target = others[pick(std::size(others))];
      break;
    }
    case 4:  // drop an element or a field
      if (target.is_array() && !target.empty()) {
        target.erase(pick(target.size()));
      } else if (target.is_object() && !target.empty()) {
        target.erase(std::next(target.begin(), static_cast<std::ptrdiff_t>(pick(target.size()))).key());
      }
      break;
    case 5:  // repeat an element (a longer row, another state, another component)
      if (target.is_array() && !target.empty() && target.size() < 1000) {
        target.push_back(Json(target[pick(target.size())]));
      }
      break;
    case 6:  // an unknown field, or a field moved to where it does not belong
      if (target.is_object()) target[pick(2) ? "variances" : "extra"] = Json::array({1.0});
      break;
    default:  // a copy of another value: shapes that are valid somewhere else
      target = Json(*values[pick(values.size())]);
      break;
  }
  return true;
}

}  // namespace

extern "C" size_t LLVMFuzzerCustomMutator(uint8_t* data, size_t size, size_t maxSize, unsigned int seed) {
  std::minstd_rand random(seed);
  if (random() % 2 == 0) return LLVMFuzzerMutate(data, size, maxSize);
  Json document = Json::parse(data, data + size, nullptr, /*allow_exceptions=*/false);
  if (document.is_discarded()) return LLVMFuzzerMutate(data, size, maxSize);
  if (!mutateOneValue(document, random)) return LLVMFuzzerMutate(data, size, maxSize);
  const std::string text = document.dump(/*indent=*/-1, ' ', false, Json::error_handler_t::replace);
  if (text.size() > maxSize) return LLVMFuzzerMutate(data, size, maxSize);
  std::memcpy(data, text.data(), text.size());
  return text.size();
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  std::string training;
  th::hmm::HmmModel model;
  try {
    model = th::hmm::parseModel(text, "fuzz-input", &training);
  } catch (const th::Error&) {
    return 0;  // a clean rejection
  }
  try {
    const std::string written = th::hmm::formatModel(model, training);
    std::string trainingAgain;
    const th::hmm::HmmModel again = th::hmm::parseModel(written, "fuzz-rewritten", &trainingAgain);
    if (th::hmm::formatModel(again, trainingAgain) != written) __builtin_trap();
  } catch (const th::Error&) {
    __builtin_trap();
  }
  return 0;
}
