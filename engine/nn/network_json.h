// A network (network.h) as a JSON object inside a model file, and back.
//
//   json["network"] = th::nn::networkJson(net);
//   th::nn::Network net = th::nn::networkFromJson(json["network"], fields, "network");   // errors name the field
//
// The object: {"format": "float32-le-base64", "inputs": D, "input_mean": "...", "input_scale": "...",
// "layers": [{"rows": R, "cols": C, "weights": "...", "bias": "..."}, ...]}. Each array is its float32 values
// in little-endian byte order, base64-encoded (RFC 4648), weights row by row: exact, and a third of the size
// of decimal text. Every size is checked against the data, and every value must be finite.
// Thread contract: pure functions.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "core/json_reading.h"
#include "nn/network.h"

namespace th::nn {

Json networkJson(const Network& network);
Network networkFromJson(const Json& object, const JsonFields& fields, const std::string& field);

// RFC 4648 base64 of float32 values (little-endian), and back; decoding throws th::Error on a malformed text or
// a count that is not `expected`.
std::string encodeFloats(const float* values, std::size_t count);
std::vector<float> decodeFloats(std::string_view text, std::size_t expected);

}  // namespace th::nn
