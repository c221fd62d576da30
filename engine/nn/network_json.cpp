#include "nn/network_json.h"

#include <array>
#include <cstdint>
#include <cstring>

#include "core/error.h"

namespace th::nn {
namespace {

constexpr std::string_view kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
constexpr const char* kFormat = "float32-le-base64";

std::string encodeBytes(const std::vector<std::uint8_t>& bytes) {
  std::string text;
  text.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::uint32_t a = bytes[i];
    const std::uint32_t b = i + 1 < bytes.size() ? bytes[i + 1] : 0;
    const std::uint32_t c = i + 2 < bytes.size() ? bytes[i + 2] : 0;
    const std::uint32_t triple = (a << 16) | (b << 8) | c;
    text.push_back(kAlphabet[(triple >> 18) & 63]);
    text.push_back(kAlphabet[(triple >> 12) & 63]);
    text.push_back(i + 1 < bytes.size() ? kAlphabet[(triple >> 6) & 63] : '=');
    text.push_back(i + 2 < bytes.size() ? kAlphabet[triple & 63] : '=');
  }
  return text;
}

std::vector<std::uint8_t> decodeBytes(std::string_view text) {
  if (text.size() % 4 != 0) throw Error("base64 text of " + std::to_string(text.size()) + " characters (not 4k)");
  std::array<int, 256> value{};
  value.fill(-1);
  for (std::size_t i = 0; i < kAlphabet.size(); ++i)
    value[static_cast<unsigned char>(kAlphabet[i])] = static_cast<int>(i);
  std::vector<std::uint8_t> bytes;
  bytes.reserve(text.size() / 4 * 3);
  for (std::size_t i = 0; i < text.size(); i += 4) {
    int padding = 0;
    std::uint32_t triple = 0;
    for (std::size_t k = 0; k < 4; ++k) {
      const char c = text[i + k];
      if (c == '=' && i + 4 == text.size() && k >= 2) {
        ++padding;
        triple <<= 6;
        continue;
      }
      const int v = value[static_cast<unsigned char>(c)];
      if (v < 0 || padding > 0)
        throw Error("base64 text holds '" + std::string(1, c) + "' at " + std::to_string(i + k));
      triple = (triple << 6) | static_cast<std::uint32_t>(v);
    }
    bytes.push_back(static_cast<std::uint8_t>(triple >> 16));
    if (padding < 2) bytes.push_back(static_cast<std::uint8_t>(triple >> 8));
    if (padding < 1) bytes.push_back(static_cast<std::uint8_t>(triple));
  }
  return bytes;
}

Json floatsJson(const float* values, std::size_t count) {
  return encodeFloats(values, count);
}

}  // namespace

std::string encodeFloats(const float* values, std::size_t count) {
  std::vector<std::uint8_t> bytes(count * 4);
  for (std::size_t i = 0; i < count; ++i) {
    std::uint32_t bits = 0;  // std::bit_cast, which the WebAssembly build's library lacks
    std::memcpy(&bits, &values[i], sizeof bits);
    for (int b = 0; b < 4; ++b) bytes[i * 4 + static_cast<std::size_t>(b)] = static_cast<std::uint8_t>(bits >> (8 * b));
  }
  return encodeBytes(bytes);
}

std::vector<float> decodeFloats(std::string_view text, std::size_t expected) {
  const std::vector<std::uint8_t> bytes = decodeBytes(text);
  if (bytes.size() != expected * 4)
    throw Error("holds " + std::to_string(bytes.size() / 4) + " values, not " + std::to_string(expected));
  std::vector<float> values(expected);
  for (std::size_t i = 0; i < expected; ++i) {
    std::uint32_t bits = 0;
    for (int b = 0; b < 4; ++b)
      bits |= static_cast<std::uint32_t>(bytes[i * 4 + static_cast<std::size_t>(b)]) << (8 * b);
    std::memcpy(&values[i], &bits, sizeof bits);
  }
  return values;
}

Json networkJson(const Network& network) {
  Json layers = Json::array();
  for (const DenseLayer& layer : network.layers()) {
    // Row by row: Eigen stores column-major, so the transpose's storage is the rows in order.
    const Eigen::MatrixXf rowMajor = layer.weights.transpose();
    layers.push_back({{"rows", layer.weights.rows()},
                      {"cols", layer.weights.cols()},
                      {"weights", floatsJson(rowMajor.data(), static_cast<std::size_t>(rowMajor.size()))},
                      {"bias", floatsJson(layer.bias.data(), static_cast<std::size_t>(layer.bias.size()))}});
  }
  return {{"format", kFormat},
          {"inputs", network.inputs()},
          {"input_mean", floatsJson(network.inputMean().data(), static_cast<std::size_t>(network.inputs()))},
          {"input_scale", floatsJson(network.inputScale().data(), static_cast<std::size_t>(network.inputs()))},
          {"layers", layers}};
}

Network networkFromJson(const Json& object, const JsonFields& fields, const std::string& field) {
  fields.object(object, field);
  fields.onlyKnownFields(object, {"format", "inputs", "input_mean", "input_scale", "layers"}, field);
  const std::string format = fields.string(fields.member(object, "format", field), JsonFields::dotted(field, "format"));
  if (format != kFormat)
    fields.fail(JsonFields::dotted(field, "format"), "is \"" + format + "\", not \"" + kFormat + "\"");
  const auto count = [&](const Json& parent, std::string_view key, const std::string& parentField) {
    const std::int64_t n =
        fields.integer(fields.member(parent, key, parentField), JsonFields::dotted(parentField, key));
    if (n < 1 || n > 1'000'000) fields.fail(JsonFields::dotted(parentField, key), "must be 1..1000000");
    return static_cast<std::size_t>(n);
  };
  const auto floats = [&](const Json& parent, std::string_view key, const std::string& parentField, std::size_t n) {
    const std::string name = JsonFields::dotted(parentField, key);
    const std::string& text = fields.string(fields.member(parent, key, parentField), name);
    try {
      return decodeFloats(text, n);
    } catch (const Error& error) {
      fields.fail(name, error.what());
    }
  };
  const std::size_t inputs = count(object, "inputs", field);
  const std::vector<float> mean = floats(object, "input_mean", field, inputs);
  const std::vector<float> scale = floats(object, "input_scale", field, inputs);
  const std::string layersField = JsonFields::dotted(field, "layers");
  const Json& layersJson = fields.array(fields.member(object, "layers", field), layersField);
  if (layersJson.empty()) fields.fail(layersField, "is empty");
  std::vector<DenseLayer> layers;
  for (std::size_t i = 0; i < layersJson.size(); ++i) {
    const std::string layerField = JsonFields::indexed(layersField, i);
    const Json& layerJson = fields.object(layersJson[i], layerField);
    fields.onlyKnownFields(layerJson, {"rows", "cols", "weights", "bias"}, layerField);
    const std::size_t rows = count(layerJson, "rows", layerField);
    const std::size_t cols = count(layerJson, "cols", layerField);
    if (rows * cols > 50'000'000) fields.fail(layerField, "is too large");
    const std::vector<float> weights = floats(layerJson, "weights", layerField, rows * cols);
    const std::vector<float> bias = floats(layerJson, "bias", layerField, rows);
    DenseLayer layer;
    layer.weights = Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
        weights.data(), static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
    layer.bias = Eigen::Map<const Eigen::VectorXf>(bias.data(), static_cast<Eigen::Index>(rows));
    layers.push_back(std::move(layer));
  }
  try {
    return Network::fromParts(Eigen::Map<const Eigen::VectorXf>(mean.data(), static_cast<Eigen::Index>(inputs)),
                              Eigen::Map<const Eigen::VectorXf>(scale.data(), static_cast<Eigen::Index>(inputs)),
                              std::move(layers));
  } catch (const Error& error) {
    fields.fail(field, error.what());
  }
}

}  // namespace th::nn
