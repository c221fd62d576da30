#include "formats/gltf_reading.h"

#include <meshoptimizer.h>
#include <webp/decode.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <span>

#include "core/error.h"

namespace th::formats {
namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<unsigned char>;
using Json = nlohmann::json;

constexpr char kMeshopt[] = "EXT_meshopt_compression";

Bytes readBytes(const fs::path& path) {
  std::error_code error;
  if (!fs::exists(path, error)) throw fileError(path, "does not exist");
  if (fs::is_directory(path, error)) throw fileError(path, "is a folder, not a glTF file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw fileError(path, "cannot be read");
  Bytes bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw fileError(path, "cannot be read");
  return bytes;
}

std::uint32_t readU32(const Bytes& bytes, std::size_t at) {
  std::uint32_t value = 0;
  std::memcpy(&value, bytes.data() + at, 4);  // GLB is little-endian, as every machine this builds for
  return value;
}

void appendU32(Bytes& bytes, std::uint32_t value) {
  unsigned char raw[4];
  std::memcpy(raw, &value, 4);
  bytes.insert(bytes.end(), raw, raw + 4);
}

// Pads with zeros to a multiple of `alignment`: accessors need their component size, and 4 is glTF's rule for
// bufferViews of vertex attributes; GLB chunks pad their JSON with spaces instead (the caller's `fill`).

bool isGlb(const Bytes& bytes) {
  return bytes.size() >= 12 && std::memcmp(bytes.data(), "glTF", 4) == 0;
}

// One view's data by its mode (and filter), as meshoptimizer's decoders return: 0 when it decodes.
int decodeMeshoptView(const nlohmann::json& meshopt, const std::string& mode, unsigned char* destination,
                      std::size_t count, std::size_t stride, std::span<const unsigned char> compressed) {
  if (mode == "TRIANGLES")
    return meshopt_decodeIndexBuffer(destination, count, stride, compressed.data(), compressed.size());
  if (mode == "INDICES")
    return meshopt_decodeIndexSequence(destination, count, stride, compressed.data(), compressed.size());
  if (mode != "ATTRIBUTES") return -1;
  const int status = meshopt_decodeVertexBuffer(destination, count, stride, compressed.data(), compressed.size());
  const std::string filter = meshopt.value("filter", std::string("NONE"));
  if (status == 0 && filter == "OCTAHEDRAL") meshopt_decodeFilterOct(destination, count, stride);
  if (status == 0 && filter == "QUATERNION") meshopt_decodeFilterQuat(destination, count, stride);
  if (status == 0 && filter == "EXPONENTIAL") meshopt_decodeFilterExp(destination, count, stride);
  return status;
}

// A GLB of `json` and `bin`: the header, the JSON chunk padded with spaces, the BIN chunk padded with zeros.
Bytes packGlb(const nlohmann::json& json, Bytes bin) {
  std::string text = json.dump();
  while (text.size() % 4 != 0) text.push_back(' ');
  padBytes(bin, 4);
  Bytes out;
  out.reserve(28 + text.size() + bin.size());
  appendU32(out, 0x46546C67u);  // "glTF"
  appendU32(out, 2);
  appendU32(out, static_cast<std::uint32_t>(28 + text.size() + bin.size()));
  appendU32(out, static_cast<std::uint32_t>(text.size()));
  appendU32(out, 0x4E4F534Au);
  out.insert(out.end(), text.begin(), text.end());
  appendU32(out, static_cast<std::uint32_t>(bin.size()));
  appendU32(out, 0x004E4942u);
  out.insert(out.end(), bin.begin(), bin.end());
  return out;
}

// EXT_meshopt_compression, decoded into its fallback buffers: tinygltf reads a GLB's BIN chunk into the first
// buffer only, and the fallback buffers have no data of their own, so it refuses such a file. The decoded views are
// appended to the BIN chunk, the views point there, and the extension is dropped from the file.
Bytes decodeMeshoptJson(const fs::path& path, const Bytes& glb) {
  const auto bad = [&](const std::string& what) { return fileError(path, "not a valid glTF binary: " + what); };
  const std::uint32_t total = readU32(glb, 8);
  if (total > glb.size() || glb.size() < 20) throw bad("shorter than its header says");
  const std::uint32_t jsonLength = readU32(glb, 12);
  if (readU32(glb, 16) != 0x4E4F534Au || 20ull + jsonLength > total) throw bad("no JSON chunk");
  nlohmann::json json = nlohmann::json::parse(glb.begin() + 20, glb.begin() + 20 + jsonLength, nullptr, false);
  if (json.is_discarded() || !json.is_object()) throw bad("its JSON chunk does not parse");

  const auto usesMeshopt = [&] {
    const auto used = json.find("extensionsUsed");
    return used != json.end() && used->is_array() && std::find(used->begin(), used->end(), kMeshopt) != used->end();
  };
  if (!usesMeshopt()) return glb;

  Bytes bin;
  const std::size_t binAt = 20ull + jsonLength;
  if (binAt + 8 <= total && readU32(glb, binAt + 4) == 0x004E4942u) {
    const std::uint32_t binLength = readU32(glb, binAt);
    if (binAt + 8 + binLength > total) throw bad("its BIN chunk is cut short");
    bin.assign(glb.begin() + static_cast<std::ptrdiff_t>(binAt + 8),
               glb.begin() + static_cast<std::ptrdiff_t>(binAt + 8 + binLength));
  }
  auto& buffers = json.at("buffers");
  // Only the GLB's own buffer (the first, without a uri) is handled; a meshopt file whose compressed data lives in
  // external files is beyond this reader.
  for (std::size_t b = 0; b < buffers.size(); ++b) {
    const auto& buffer = buffers[b];
    const bool fallback = buffer.contains("extensions") && buffer["extensions"].contains(kMeshopt);
    if (buffer.contains("uri") || (b > 0 && !fallback))
      throw fileError(path, std::string(kMeshopt) + " with buffers outside the file is not supported");
  }

  // Where each fallback buffer's bytes start in the new BIN chunk.
  std::map<std::size_t, std::size_t> fallbackAt;
  const auto bufferLength = [&](std::size_t b) { return buffers[b].at("byteLength").get<std::size_t>(); };
  for (std::size_t b = 1; b < buffers.size(); ++b) {
    padBytes(bin, 16);
    fallbackAt[b] = bin.size();
    bin.resize(bin.size() + bufferLength(b), 0);
  }
  const std::size_t firstLength = bufferLength(0);

  for (auto& view : json.at("bufferViews")) {
    const std::size_t buffer = view.at("buffer").get<std::size_t>();
    if (buffer > 0) {
      if (!fallbackAt.count(buffer)) throw bad("a bufferView names a missing buffer");
      view["buffer"] = 0;
      view["byteOffset"] = view.value("byteOffset", std::size_t{0}) + fallbackAt[buffer];
    }
    if (!view.contains("extensions") || !view["extensions"].contains(kMeshopt)) continue;
    const auto& meshopt = view["extensions"][kMeshopt];
    const std::size_t source = meshopt.value("byteOffset", std::size_t{0});
    const std::size_t sourceLength = meshopt.at("byteLength").get<std::size_t>();
    const std::size_t count = meshopt.at("count").get<std::size_t>();
    const std::size_t stride = meshopt.at("byteStride").get<std::size_t>();
    const std::size_t target = view.value("byteOffset", std::size_t{0});
    if (meshopt.value("buffer", std::size_t{0}) != 0 || source + sourceLength > firstLength ||
        target + count * stride > bin.size())
      throw bad(std::string(kMeshopt) + " data out of range");
    unsigned char* destination = bin.data() + target;
    const unsigned char* compressed = bin.data() + source;
    const std::string mode = meshopt.at("mode").get<std::string>();
    if (decodeMeshoptView(meshopt, mode, destination, count, stride, {compressed, sourceLength}) != 0)
      throw bad(std::string(kMeshopt) + " data that does not decode (mode " + mode + ")");
    view["extensions"].erase(kMeshopt);
    if (view["extensions"].empty()) view.erase("extensions");
  }
  buffers = nlohmann::json::array({{{"byteLength", bin.size()}}});
  for (const char* list : {"extensionsUsed", "extensionsRequired"}) {
    if (!json.contains(list)) continue;
    auto& names = json[list];
    names.erase(std::remove(names.begin(), names.end(), kMeshopt), names.end());
    if (names.empty()) json.erase(list);
  }

  return packGlb(json, std::move(bin));
}

Bytes decodeMeshopt(const fs::path& path, const Bytes& glb) {
  try {
    return decodeMeshoptJson(path, glb);
  } catch (const nlohmann::json::exception& e) {
    // A field missing or of the wrong type in the JSON that says where the compressed data is.
    throw fileError(path, std::string("not a valid glTF binary: ") + e.what());
  }
}

void dropExtension(Json& json, const std::string& name) {
  for (const char* list : {"extensionsUsed", "extensionsRequired"}) {
    if (!json.contains(list) || !json[list].is_array()) continue;
    Json kept = Json::array();
    for (const auto& item : json[list])
      if (item != name) kept.push_back(item);
    json[list] = kept;
    if (kept.empty()) json.erase(list);
  }
}

// A texture whose image is WebP names it in EXT_texture_webp: made its plain source.
void adoptWebpSources(Json& json) {
  if (!json.contains("textures")) return;
  for (Json& texture : json["textures"]) {
    if (!texture.contains("extensions") || !texture["extensions"].contains("EXT_texture_webp")) continue;
    texture["source"] = texture["extensions"]["EXT_texture_webp"].value("source", -1);
    texture["extensions"].erase("EXT_texture_webp");
    if (texture["extensions"].empty()) texture.erase("extensions");
  }
  dropExtension(json, "EXT_texture_webp");
}

bool isWebp(const unsigned char* bytes, int size) {
  return size >= 12 && std::memcmp(bytes, "RIFF", 4) == 0 && std::memcmp(bytes + 8, "WEBP", 4) == 0;
}

bool loadImage(tinygltf::Image* image, const int index, std::string* error, std::string* warning, int width, int height,
               const unsigned char* bytes, int size, void* user) {
  if (!isWebp(bytes, size))
    return tinygltf::LoadImageData(image, index, error, warning, width, height, bytes, size, user);
  int w = 0, h = 0;
  std::uint8_t* rgba = WebPDecodeRGBA(bytes, static_cast<std::size_t>(size), &w, &h);
  if (rgba == nullptr) {
    if (error) *error += "image " + std::to_string(index) + " is WebP that does not decode\n";
    return false;
  }
  image->width = w;
  image->height = h;
  image->component = 4;
  image->bits = 8;
  image->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  image->image.assign(rgba, rgba + static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
  WebPFree(rgba);
  return true;
}

// A GLB's JSON chunk edited by `edit`, the rest as it was.
template <typename Edit>
Bytes editGlbJson(const fs::path& path, const Bytes& glb, Edit edit) {
  const std::uint32_t jsonLength = readU32(glb, 12);
  if (glb.size() < 20 || 20ull + jsonLength > glb.size())
    throw fileError(path, "not a valid glTF binary: no JSON chunk");
  Json json = Json::parse(glb.begin() + 20, glb.begin() + 20 + jsonLength, nullptr, false);
  if (json.is_discarded()) throw fileError(path, "not a valid glTF binary: its JSON chunk does not parse");
  edit(json);
  std::string text = json.dump();
  while (text.size() % 4 != 0) text.push_back(' ');
  const Bytes rest(glb.begin() + 20 + jsonLength, glb.end());
  Bytes out;
  appendU32(out, 0x46546C67u);  // "glTF"
  appendU32(out, 2);
  appendU32(out, static_cast<std::uint32_t>(20 + text.size() + rest.size()));
  appendU32(out, static_cast<std::uint32_t>(text.size()));
  appendU32(out, 0x4E4F534Au);
  out.insert(out.end(), text.begin(), text.end());
  out.insert(out.end(), rest.begin(), rest.end());
  return out;
}

bool keepImageBytes(tinygltf::Image*, const int index, std::string*, std::string*, int, int, const unsigned char* bytes,
                    int size, void* user) {
  auto& images = static_cast<GltfImageBytes*>(user)->images;
  if (index < 0) return false;
  if (images.size() <= static_cast<std::size_t>(index)) images.resize(static_cast<std::size_t>(index) + 1);
  images[static_cast<std::size_t>(index)].assign(bytes, bytes + size);
  return true;
}

}  // namespace

void padBytes(std::vector<unsigned char>& bytes, std::size_t alignment) {
  while (bytes.size() % alignment != 0) bytes.push_back(0);
}

tinygltf::Model readGltf(const fs::path& path, GltfImageBytes* images) {
  Bytes bytes = readBytes(path);
  tinygltf::TinyGLTF loader;
  if (images != nullptr)
    loader.SetImageLoader(keepImageBytes, images);
  else
    loader.SetImageLoader(loadImage, nullptr);
  tinygltf::Model model;
  std::string error, warning;
  const std::string folder = path.parent_path().string();
  bool ok = false;
  if (isGlb(bytes)) {
    bytes = decodeMeshopt(path, bytes);
    if (images == nullptr) bytes = editGlbJson(path, bytes, adoptWebpSources);
    ok = loader.LoadBinaryFromMemory(&model, &error, &warning, bytes.data(), static_cast<unsigned int>(bytes.size()),
                                     folder);
  } else {
    const auto first = std::find_if(bytes.begin(), bytes.end(), [](unsigned char c) { return !std::isspace(c); });
    if (first == bytes.end() || *first != '{') throw fileError(path, "not a glTF file (neither glTF binary nor JSON)");
    std::string text(bytes.begin(), bytes.end());
    if (images == nullptr) {
      Json json = Json::parse(text, nullptr, false);
      if (json.is_discarded()) throw fileError(path, "not a glTF file: its JSON does not parse");
      adoptWebpSources(json);
      text = json.dump();
    }
    ok = loader.LoadASCIIFromString(&model, &error, &warning, text.c_str(), static_cast<unsigned int>(text.size()),
                                    folder);
  }
  if (!ok) {
    std::string what = error.empty() ? std::string("unreadable") : error;
    std::replace(what.begin(), what.end(), '\n', ' ');
    while (!what.empty() && what.back() == ' ') what.pop_back();
    throw fileError(path, "not a readable glTF file: " + what);
  }
  return model;
}

namespace {

const tinygltf::Accessor& checkedAccessor(const tinygltf::Model& model, int index, const std::string& what) {
  if (index < 0 || index >= static_cast<int>(model.accessors.size()))
    throw Error(what + ": no accessor " + std::to_string(index));
  const tinygltf::Accessor& accessor = model.accessors[static_cast<std::size_t>(index)];
  if (accessor.bufferView < 0 || accessor.bufferView >= static_cast<int>(model.bufferViews.size()))
    throw Error(what + ": an accessor without data (sparse-only accessors are not supported)");
  const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(accessor.bufferView)];
  const int components = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(accessor.type));
  const int size = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(accessor.componentType));
  const std::size_t stride = accessor.ByteStride(view) > 0 ? static_cast<std::size_t>(accessor.ByteStride(view))
                                                           : static_cast<std::size_t>(components * size);
  const std::size_t end =
      view.byteOffset + accessor.byteOffset +
      (accessor.count == 0 ? 0 : (accessor.count - 1) * stride + static_cast<std::size_t>(components * size));
  if (view.buffer < 0 || view.buffer >= static_cast<int>(model.buffers.size()) ||
      end > model.buffers[static_cast<std::size_t>(view.buffer)].data.size())
    throw Error(what + ": an accessor runs past its buffer");
  if (accessor.sparse.isSparse) throw Error(what + ": sparse accessors are not supported");
  return accessor;
}

template <typename Visit>
void forEachComponent(const tinygltf::Model& model, const tinygltf::Accessor& accessor, Visit visit) {
  const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(accessor.bufferView)];
  const unsigned char* base =
      model.buffers[static_cast<std::size_t>(view.buffer)].data.data() + view.byteOffset + accessor.byteOffset;
  const int components = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(accessor.type));
  const int size = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(accessor.componentType));
  const std::size_t stride = accessor.ByteStride(view) > 0 ? static_cast<std::size_t>(accessor.ByteStride(view))
                                                           : static_cast<std::size_t>(components * size);
  for (std::size_t e = 0; e < accessor.count; ++e)
    for (int c = 0; c < components; ++c) visit(e, c, base + e * stride + static_cast<std::size_t>(c * size));
}

template <typename T>
T load(const unsigned char* at) {
  T value;
  std::memcpy(&value, at, sizeof value);
  return value;
}

}  // namespace

Eigen::MatrixXf accessorFloats(const tinygltf::Model& model, int index, const std::string& what) {
  const tinygltf::Accessor& accessor = checkedAccessor(model, index, what);
  const int components = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(accessor.type));
  Eigen::MatrixXf out(components, static_cast<Eigen::Index>(accessor.count));
  const bool normalised = accessor.normalized;
  forEachComponent(model, accessor, [&](std::size_t e, int c, const unsigned char* at) {
    float value = 0.0f;
    switch (accessor.componentType) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT:
        value = load<float>(at);
        break;
      case TINYGLTF_COMPONENT_TYPE_BYTE:
        value = normalised ? std::max(load<std::int8_t>(at) / 127.0f, -1.0f) : load<std::int8_t>(at);
        break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        value = normalised ? load<std::uint8_t>(at) / 255.0f : load<std::uint8_t>(at);
        break;
      case TINYGLTF_COMPONENT_TYPE_SHORT:
        value = normalised ? std::max(load<std::int16_t>(at) / 32767.0f, -1.0f) : load<std::int16_t>(at);
        break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        value = normalised ? load<std::uint16_t>(at) / 65535.0f : load<std::uint16_t>(at);
        break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        value = static_cast<float>(load<std::uint32_t>(at));
        break;
      default:
        throw Error(what + ": an accessor of component type " + std::to_string(accessor.componentType));
    }
    out(c, static_cast<Eigen::Index>(e)) = value;
  });
  return out;
}

Eigen::Matrix<std::uint32_t, Eigen::Dynamic, Eigen::Dynamic> accessorIndices(const tinygltf::Model& model, int index,
                                                                             const std::string& what) {
  const tinygltf::Accessor& accessor = checkedAccessor(model, index, what);
  const int components = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(accessor.type));
  Eigen::Matrix<std::uint32_t, Eigen::Dynamic, Eigen::Dynamic> out(components,
                                                                   static_cast<Eigen::Index>(accessor.count));
  forEachComponent(model, accessor, [&](std::size_t e, int c, const unsigned char* at) {
    std::uint32_t value = 0;
    switch (accessor.componentType) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        value = load<std::uint8_t>(at);
        break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        value = load<std::uint16_t>(at);
        break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        value = load<std::uint32_t>(at);
        break;
      default:
        throw Error(what + ": indices of component type " + std::to_string(accessor.componentType));
    }
    out(c, static_cast<Eigen::Index>(e)) = value;
  });
  return out;
}

}  // namespace th::formats
