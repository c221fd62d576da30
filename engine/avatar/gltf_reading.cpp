#include "avatar/gltf_reading.h"

#include <meshoptimizer.h>
#include <webp/decode.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/error.h"

namespace th::avatar {
namespace {

using Json = nlohmann::json;
using Bytes = std::vector<unsigned char>;

constexpr std::uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr std::uint32_t kJsonChunk = 0x4E4F534A;
constexpr std::uint32_t kBinChunk = 0x004E4942;

std::uint32_t readU32(const Bytes& bytes, std::size_t at) {
  std::uint32_t value = 0;
  std::memcpy(&value, bytes.data() + at, 4);
  return value;
}

void appendU32(Bytes& out, std::uint32_t value) {
  const auto* p = reinterpret_cast<const unsigned char*>(&value);
  out.insert(out.end(), p, p + 4);
}

struct Glb {
  Json json;
  Bytes bin;
};

// A GLB's two chunks; nullopt-like empty json when the bytes are not a GLB.
bool splitGlb(const std::filesystem::path& path, const Bytes& bytes, Glb& glb) {
  if (bytes.size() < 12 || readU32(bytes, 0) != kGlbMagic) return false;
  if (readU32(bytes, 4) != 2)
    throw fileError(path, "is a binary glTF of version " + std::to_string(readU32(bytes, 4)) + ", not 2");
  std::size_t at = 12;
  bool haveJson = false;
  while (at + 8 <= bytes.size()) {
    const std::uint32_t length = readU32(bytes, at);
    const std::uint32_t type = readU32(bytes, at + 4);
    if (at + 8 + length > bytes.size())
      throw fileError(path, "is a binary glTF whose chunk runs past the end of the file");
    const auto begin = bytes.begin() + static_cast<std::ptrdiff_t>(at + 8);
    if (type == kJsonChunk) {
      glb.json = Json::parse(begin, begin + length, nullptr, false);
      if (glb.json.is_discarded()) throw fileError(path, "is a binary glTF whose JSON chunk does not parse");
      haveJson = true;
    } else if (type == kBinChunk) {
      glb.bin.assign(begin, begin + length);
    }
    at += 8 + length;
  }
  if (!haveJson) throw fileError(path, "is a binary glTF without a JSON chunk");
  return true;
}

Bytes joinGlb(const Glb& glb) {
  std::string text = glb.json.dump();
  while (text.size() % 4 != 0) text.push_back(' ');
  Bytes bin = glb.bin;
  while (bin.size() % 4 != 0) bin.push_back(0);
  Bytes out;
  appendU32(out, kGlbMagic);
  appendU32(out, 2);
  appendU32(out, static_cast<std::uint32_t>(12 + 8 + text.size() + (bin.empty() ? 0 : 8 + bin.size())));
  appendU32(out, static_cast<std::uint32_t>(text.size()));
  appendU32(out, kJsonChunk);
  out.insert(out.end(), text.begin(), text.end());
  if (!bin.empty()) {
    appendU32(out, static_cast<std::uint32_t>(bin.size()));
    appendU32(out, kBinChunk);
    out.insert(out.end(), bin.begin(), bin.end());
  }
  return out;
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

// Every EXT_meshopt_compression view decoded into the binary chunk; the buffers only such views used (the
// fallbacks, which have no data in the file) dropped. Only the GLB's own buffer (0) may hold compressed data.
void decompressMeshopt(const std::filesystem::path& path, Glb& glb) {
  Json& views = glb.json["bufferViews"];
  if (!views.is_array()) return;
  std::vector<bool> bufferStillUsed(glb.json.value("buffers", Json::array()).size(), false);
  for (Json& view : views) {
    if (!view.contains("extensions") || !view["extensions"].contains("EXT_meshopt_compression")) {
      const std::size_t buffer = view.value("buffer", 0);
      if (buffer < bufferStillUsed.size()) bufferStillUsed[buffer] = true;
      continue;
    }
    const Json& ext = view["extensions"]["EXT_meshopt_compression"];
    if (ext.value("buffer", -1) != 0 || glb.bin.empty())
      throw fileError(path,
                      "has compressed data outside its binary chunk (EXT_meshopt_compression), which is not supported");
    const std::size_t offset = ext.value("byteOffset", 0), length = ext.value("byteLength", 0);
    const std::size_t stride = ext.value("byteStride", 0), count = ext.value("count", 0);
    const std::string mode = ext.value("mode", ""), filter = ext.value("filter", "NONE");
    if (offset + length > glb.bin.size() || stride == 0 || count == 0)
      throw fileError(path, "has a compressed buffer view out of its binary chunk's range");
    Bytes decoded(count * stride);
    const unsigned char* source = glb.bin.data() + offset;
    int status = -1;
    if (mode == "ATTRIBUTES") {
      status = meshopt_decodeVertexBuffer(decoded.data(), count, stride, source, length);
      if (status == 0 && filter == "OCTAHEDRAL") meshopt_decodeFilterOct(decoded.data(), count, stride);
      if (status == 0 && filter == "QUATERNION") meshopt_decodeFilterQuat(decoded.data(), count, stride);
      if (status == 0 && filter == "EXPONENTIAL") meshopt_decodeFilterExp(decoded.data(), count, stride);
    } else if (mode == "TRIANGLES") {
      status = meshopt_decodeIndexBuffer(decoded.data(), count, stride, source, length);
    } else if (mode == "INDICES") {
      status = meshopt_decodeIndexSequence(decoded.data(), count, stride, source, length);
    }
    if (status != 0) throw fileError(path, "has a compressed buffer view that does not decode (mode " + mode + ")");
    while (glb.bin.size() % 4 != 0) glb.bin.push_back(0);
    view["buffer"] = 0;
    view["byteOffset"] = glb.bin.size();
    view["byteLength"] = decoded.size();
    view["extensions"].erase("EXT_meshopt_compression");
    if (view["extensions"].empty()) view.erase("extensions");
    glb.bin.insert(glb.bin.end(), decoded.begin(), decoded.end());
    bufferStillUsed[0] = true;
  }
  // Drop the unused buffers and renumber the views' references.
  Json& buffers = glb.json["buffers"];
  std::vector<int> renumbered(bufferStillUsed.size(), -1);
  Json kept = Json::array();
  for (std::size_t b = 0; b < bufferStillUsed.size(); ++b) {
    if (!bufferStillUsed[b] && b != 0) continue;
    renumbered[b] = static_cast<int>(kept.size());
    kept.push_back(buffers[b]);
  }
  kept[0]["byteLength"] = glb.bin.size();
  buffers = kept;
  for (Json& view : views) view["buffer"] = renumbered[view.value("buffer", 0)];
  dropExtension(glb.json, "EXT_meshopt_compression");
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

std::string firstLine(const std::string& text) {
  std::string line = text.substr(0, text.find('\n'));
  while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
  return line;
}

}  // namespace

tinygltf::Model readGltf(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw fileError(path, "cannot be opened");
  const Bytes bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(loadImage, nullptr);
  tinygltf::Model model;
  std::string error, warning;
  bool ok = false;
  Glb glb;
  if (splitGlb(path, bytes, glb)) {
    decompressMeshopt(path, glb);
    adoptWebpSources(glb.json);
    const Bytes rewritten = joinGlb(glb);
    ok = loader.LoadBinaryFromMemory(&model, &error, &warning, rewritten.data(),
                                     static_cast<unsigned int>(rewritten.size()), path.parent_path().string());
  } else {
    const std::string text(bytes.begin(), bytes.end());
    Json json = Json::parse(text, nullptr, false);
    if (json.is_discarded() || !json.is_object() || !json.contains("asset"))
      throw fileError(path, "is not a glTF file (neither a binary glTF nor glTF JSON with an \"asset\")");
    adoptWebpSources(json);
    const std::string rewritten = json.dump();
    ok = loader.LoadASCIIFromString(&model, &error, &warning, rewritten.c_str(),
                                    static_cast<unsigned int>(rewritten.size()), path.parent_path().string());
  }
  if (!ok) throw fileError(path, "is not a glTF file tinygltf can read: " + firstLine(error.empty() ? warning : error));
  for (const std::string& required : model.extensionsRequired)
    if (required != "KHR_mesh_quantization" && required != "KHR_materials_unlit" && required != "KHR_texture_transform")
      throw fileError(path, "requires the glTF extension " + required + ", which is not supported");
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

}  // namespace th::avatar
