#include "formats/gltf_animation.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <utility>

#include "core/atomic_file.h"
#include "core/error.h"
#include "formats/gltf_reading.h"

namespace th::formats {
namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<unsigned char>;

std::string lowerExtension(const fs::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

struct LoadedAvatar {
  tinygltf::Model model;
  GltfImageBytes images;
};

LoadedAvatar loadAvatar(const fs::path& path) {
  LoadedAvatar loaded;
  loaded.model = readGltf(path, &loaded.images);
  return loaded;
}

int targetCountOf(const tinygltf::Model& model, int mesh) {
  if (mesh < 0 || mesh >= static_cast<int>(model.meshes.size()) || model.meshes[mesh].primitives.empty()) return 0;
  return static_cast<int>(model.meshes[mesh].primitives.front().targets.size());
}

std::vector<std::string> targetNamesOf(const tinygltf::Model& model, int mesh) {
  std::vector<std::string> names;
  if (mesh < 0 || mesh >= static_cast<int>(model.meshes.size())) return names;
  const tinygltf::Value& extras = model.meshes[mesh].extras;
  if (!extras.IsObject() || !extras.Has("targetNames")) return names;
  const tinygltf::Value& list = extras.Get("targetNames");
  if (!list.IsArray()) return names;
  for (std::size_t i = 0; i < list.ArrayLen(); ++i)
    names.push_back(list.Get(static_cast<int>(i)).IsString() ? list.Get(static_cast<int>(i)).Get<std::string>() : "");
  return names;
}

std::string nodeLabel(const tinygltf::Model& model, int node) {
  const std::string& name = model.nodes[node].name;
  return "node " + std::to_string(node) + (name.empty() ? std::string() : " (" + name + ")");
}

// The frame count every track agrees on; throws th::Error naming `out` or `avatar`.
int checkTracks(const tinygltf::Model& model, const GltfAnimationTracks& tracks, const fs::path& avatar,
                const fs::path& out) {
  if (!std::isfinite(tracks.framesPerSecond) || tracks.framesPerSecond <= 0)
    throw fileError(out, "the frame rate must be positive and finite");
  if (tracks.morphs.empty() && tracks.rotations.empty()) throw fileError(out, "no tracks to animate");
  int frames = -1;
  const auto sameFrames = [&](int count, const std::string& track) {
    if (frames < 0) frames = count;
    if (count != frames)
      throw fileError(out, track + " has " + std::to_string(count) + " frames, the first track " +
                               std::to_string(frames) + ": every track needs the same count");
  };
  const auto checkNode = [&](int node, const std::string& track) {
    if (node < 0 || node >= static_cast<int>(model.nodes.size()))
      throw fileError(avatar, track + " is on node " + std::to_string(node) + ", but the avatar has " +
                                  std::to_string(model.nodes.size()) + " nodes");
  };
  std::set<int> morphed, rotated;
  for (std::size_t i = 0; i < tracks.morphs.size(); ++i) {
    const auto& track = tracks.morphs[i];
    const std::string label = "morph track " + std::to_string(i);
    checkNode(track.node, label);
    const int targets = targetCountOf(model, model.nodes[track.node].mesh);
    if (targets == 0) throw fileError(avatar, label + ": " + nodeLabel(model, track.node) + " has no morph targets");
    if (track.weights.rows() != targets)
      throw fileError(avatar, label + ": " + nodeLabel(model, track.node) + " has " + std::to_string(targets) +
                                  " morph targets, the track " + std::to_string(track.weights.rows()) + " rows");
    if (!morphed.insert(track.node).second)
      throw fileError(out, label + ": " + nodeLabel(model, track.node) + " already has a morph track");
    sameFrames(static_cast<int>(track.weights.cols()), label);
    if (!track.weights.allFinite()) throw fileError(out, label + " has a weight that is not finite");
  }
  for (std::size_t i = 0; i < tracks.rotations.size(); ++i) {
    const auto& track = tracks.rotations[i];
    const std::string label = "rotation track " + std::to_string(i);
    checkNode(track.node, label);
    if (model.nodes[track.node].matrix.size() == 16)
      throw fileError(
          avatar, label + ": " + nodeLabel(model, track.node) + " is placed by a matrix, which glTF forbids animating");
    if (!rotated.insert(track.node).second)
      throw fileError(out, label + ": " + nodeLabel(model, track.node) + " already has a rotation track");
    sameFrames(static_cast<int>(track.rotations.size()), label);
    for (const auto& q : track.rotations)
      if (!q.coeffs().allFinite() || q.coeffs().norm() < 1e-6f)
        throw fileError(out, label + " has a rotation that is not finite or not a rotation (zero length)");
  }
  if (frames < 1) throw fileError(out, "the tracks have no frames");
  return frames;
}

// Appends `size` bytes to the model's single buffer as a new view (`target`: its GPU use, 0 for none); returns
// the view's index.
int appendView(tinygltf::Model& model, const unsigned char* bytes, std::size_t size, int target = 0) {
  if (model.buffers.empty()) model.buffers.emplace_back();
  Bytes& data = model.buffers.front().data;
  padBytes(data, 4);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = data.size();
  view.byteLength = size;
  view.target = target;
  data.insert(data.end(), bytes, bytes + size);
  model.bufferViews.push_back(view);
  return static_cast<int>(model.bufferViews.size()) - 1;
}

// Appends `values` to the model's single buffer as a new view and a float accessor.
// `target`: the view's GPU use (vertex data), 0 for animation data, which never goes to the GPU.
int addFloatAccessor(tinygltf::Model& model, const std::vector<float>& values, int type, std::size_t count,
                     std::vector<double> min = {}, std::vector<double> max = {}, int target = 0) {
  tinygltf::Accessor accessor;
  accessor.bufferView =
      appendView(model, reinterpret_cast<const unsigned char*>(values.data()), values.size() * sizeof(float), target);
  accessor.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  accessor.type = type;
  accessor.count = count;
  accessor.minValues = std::move(min);
  accessor.maxValues = std::move(max);
  model.accessors.push_back(accessor);
  return static_cast<int>(model.accessors.size()) - 1;
}

void addAnimation(tinygltf::Model& model, const GltfAnimationTracks& tracks, int frames) {
  std::vector<float> times(static_cast<std::size_t>(frames));
  for (int i = 0; i < frames; ++i) times[static_cast<std::size_t>(i)] = static_cast<float>(i / tracks.framesPerSecond);
  // min and max as the floats stored, so that a reader comparing them with the data finds them equal.
  const int input = addFloatAccessor(model, times, TINYGLTF_TYPE_SCALAR, times.size(), {times.front()}, {times.back()});

  tinygltf::Animation animation;
  animation.name = tracks.name;
  const auto addChannel = [&](int node, const std::string& path, int output) {
    tinygltf::AnimationSampler sampler;
    sampler.input = input;
    sampler.output = output;
    sampler.interpolation = "LINEAR";
    animation.samplers.push_back(sampler);
    tinygltf::AnimationChannel channel;
    channel.sampler = static_cast<int>(animation.samplers.size()) - 1;
    channel.target_node = node;
    channel.target_path = path;
    animation.channels.push_back(channel);
  };
  for (const auto& track : tracks.morphs) {
    // Frame-major: frame 0's weight for every target, then frame 1's, ...
    std::vector<float> weights(static_cast<std::size_t>(track.weights.size()));
    Eigen::Map<Eigen::MatrixXf>(weights.data(), track.weights.rows(), track.weights.cols()) = track.weights;
    addChannel(track.node, "weights", addFloatAccessor(model, weights, TINYGLTF_TYPE_SCALAR, weights.size()));
  }
  for (const auto& track : tracks.rotations) {
    std::vector<float> rotations;
    rotations.reserve(4 * track.rotations.size());
    Eigen::Vector4f previous = Eigen::Vector4f::Zero();
    for (const auto& rotation : track.rotations) {
      Eigen::Vector4f q = rotation.coeffs().normalized();  // Eigen's coefficients are x, y, z, w, as glTF's
      // q and -q are one rotation; the one nearer the previous keyframe makes LINEAR (slerp) turn the short way.
      if (q.dot(previous) < 0) q = -q;
      previous = q;
      rotations.insert(rotations.end(), q.data(), q.data() + 4);
    }
    addChannel(track.node, "rotation", addFloatAccessor(model, rotations, TINYGLTF_TYPE_VEC4, track.rotations.size()));
  }
  model.animations.push_back(std::move(animation));
}

std::string mimeTypeOf(const Bytes& bytes, const std::string& uri) {
  const auto starts = [&](const char* magic, std::size_t at = 0) {
    const std::size_t length = std::strlen(magic);
    return bytes.size() >= at + length && std::memcmp(bytes.data() + at, magic, length) == 0;
  };
  if (starts("\x89PNG")) return "image/png";
  if (starts("\xFF\xD8\xFF")) return "image/jpeg";
  if (starts("RIFF") && starts("WEBP", 8)) return "image/webp";
  if (starts("\xABKTX 20")) return "image/ktx2";
  const std::size_t colon = uri.find(':'), semicolon = uri.find(';');
  if (uri.rfind("data:", 0) == 0 && semicolon != std::string::npos) return uri.substr(colon + 1, semicolon - colon - 1);
  return "application/octet-stream";
}

// One buffer (a GLB holds one; tinygltf writes the others of a .glb as data URIs), images in it: the written file
// then stands alone, whatever the avatar had beside it.
void gatherIntoOneBuffer(tinygltf::Model& model, const GltfImageBytes& images) {
  if (model.buffers.size() > 1) {
    Bytes all;
    std::vector<std::size_t> start;
    for (const auto& buffer : model.buffers) {
      padBytes(all, 16);
      start.push_back(all.size());
      all.insert(all.end(), buffer.data.begin(), buffer.data.end());
    }
    for (auto& view : model.bufferViews) {
      view.byteOffset += start.at(static_cast<std::size_t>(view.buffer));
      view.buffer = 0;
    }
    model.buffers.resize(1);
    model.buffers.front().data = std::move(all);
  }
  if (!model.buffers.empty()) {
    model.buffers.front().uri.clear();
    model.buffers.front().name.clear();
  }
  for (std::size_t i = 0; i < model.images.size(); ++i) {
    auto& image = model.images[i];
    if (image.bufferView >= 0) {
      image.uri.clear();
    } else if (i < images.images.size() && !images.images[i].empty()) {
      const Bytes& bytes = images.images[i];
      image.bufferView = appendView(model, bytes.data(), bytes.size());
      image.mimeType = mimeTypeOf(bytes, image.uri);
      image.uri.clear();
    }
    // Pixels tinygltf may have decoded are not written back (the bytes above are).
    image.image.clear();
  }
}

enum class Container { kBinary, kJson };

Container containerFor(const fs::path& out, bool allowVrm) {
  const std::string extension = lowerExtension(out);
  if (extension == ".glb" || (allowVrm && extension == ".vrm")) return Container::kBinary;
  if (extension == ".gltf") return Container::kJson;
  throw fileError(out,
                  std::string("the extension picks the container: .glb") + (allowVrm ? ", .vrm" : "") + " or .gltf");
}

void writeModel(tinygltf::Model& model, const fs::path& out, Container container) {
  if (!model.buffers.empty()) padBytes(model.buffers.front().data, 4);
  AtomicFile file(out);
  tinygltf::TinyGLTF writer;
  // Images are bytes in the buffer by now; should one still name a file, its uri is written as it was rather
  // than tinygltf re-encoding pixels it never decoded.
  writer.SetImageWriter(
      [](const std::string*, const std::string*, const tinygltf::Image*, bool, std::string*, void*) { return false; },
      nullptr);
  const bool binary = container == Container::kBinary;
  if (!writer.WriteGltfSceneToStream(&model, file.stream(), /*prettyPrint=*/!binary, binary))
    throw fileError(out, "cannot be written");
  file.commit();
}

void setAsset(tinygltf::Model& model) {
  if (model.asset.version.empty()) model.asset.version = "2.0";
  const std::string us = "talkinghead";
  if (model.asset.generator.find(us) == std::string::npos)
    model.asset.generator = model.asset.generator.empty() ? us : model.asset.generator + ", " + us;
}

}  // namespace

int GltfAvatar::findNode(std::string_view name) const {
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (nodes[i].name == name) return static_cast<int>(i);
  return -1;
}

std::vector<int> GltfAvatar::morphNodes() const {
  std::vector<int> found;
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (nodes[i].targetCount > 0) found.push_back(static_cast<int>(i));
  return found;
}

int GltfAvatar::targetIndex(int node, std::string_view target) const {
  if (node < 0 || node >= static_cast<int>(nodes.size())) return -1;
  const auto& names = nodes[static_cast<std::size_t>(node)].targetNames;
  const auto at = std::find(names.begin(), names.end(), target);
  return at == names.end() ? -1 : static_cast<int>(at - names.begin());
}

GltfAvatar readGltfAvatar(const fs::path& avatar) {
  const tinygltf::Model model = loadAvatar(avatar).model;
  GltfAvatar read;
  read.nodes.resize(model.nodes.size());
  for (std::size_t i = 0; i < model.nodes.size(); ++i) {
    const auto& node = model.nodes[i];
    auto& out = read.nodes[i];
    out.name = node.name;
    out.mesh = node.mesh;
    out.targetCount = targetCountOf(model, node.mesh);
    out.targetNames = targetNamesOf(model, node.mesh);
    const auto f = [](double value) { return static_cast<float>(value); };
    if (node.translation.size() == 3)
      out.translation = {f(node.translation[0]), f(node.translation[1]), f(node.translation[2])};
    if (node.rotation.size() == 4)
      out.rotation =
          Eigen::Quaternionf(f(node.rotation[3]), f(node.rotation[0]), f(node.rotation[1]), f(node.rotation[2]));
    if (node.scale.size() == 3) out.scale = {f(node.scale[0]), f(node.scale[1]), f(node.scale[2])};
    out.placedByMatrix = node.matrix.size() == 16;
    for (const int child : node.children)
      if (child >= 0 && child < static_cast<int>(model.nodes.size()))
        read.nodes[static_cast<std::size_t>(child)].parent = static_cast<int>(i);
  }
  return read;
}

void writeAvatarAnimation(const fs::path& avatar, const GltfAnimationTracks& tracks, const fs::path& out) {
  const Container container = containerFor(out, /*allowVrm=*/true);
  checkOutputTarget(out);
  LoadedAvatar loaded = loadAvatar(avatar);
  tinygltf::Model& model = loaded.model;
  const int frames = checkTracks(model, tracks, avatar, out);
  gatherIntoOneBuffer(model, loaded.images);
  addAnimation(model, tracks, frames);
  setAsset(model);
  writeModel(model, out, container);
}

void writeAnimationOnly(const fs::path& avatar, const GltfAnimationTracks& tracks, const fs::path& out) {
  const Container container = containerFor(out, /*allowVrm=*/false);
  checkOutputTarget(out);
  const tinygltf::Model source = loadAvatar(avatar).model;
  const int frames = checkTracks(source, tracks, avatar, out);

  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "talkinghead";
  model.scenes = source.scenes;
  for (auto& scene : model.scenes) {
    scene.extensions.clear();
    scene.extras = {};
  }
  model.defaultScene = source.defaultScene;
  model.nodes.reserve(source.nodes.size());
  for (const auto& from : source.nodes) {
    tinygltf::Node node;
    node.name = from.name;
    node.children = from.children;
    node.translation = from.translation;
    node.rotation = from.rotation;
    node.scale = from.scale;
    node.matrix = from.matrix;
    model.nodes.push_back(std::move(node));
  }
  if (model.scenes.empty()) {
    // Without scenes every root is shown; one scene of the roots says the same to readers that want a scene.
    std::vector<bool> child(model.nodes.size(), false);
    for (const auto& node : model.nodes)
      for (const int c : node.children) child.at(static_cast<std::size_t>(c)) = true;
    tinygltf::Scene scene;
    for (std::size_t i = 0; i < model.nodes.size(); ++i)
      if (!child[i]) scene.nodes.push_back(static_cast<int>(i));
    model.scenes.push_back(scene);
    model.defaultScene = 0;
  }

  // The stand-in meshes' vertices: one triangle with every corner at the origin, shared by every target (which
  // moves nothing): the weights are what is carried, not the shapes.
  const std::vector<float> zeros(9, 0.0f);
  int corners = -1;
  for (const auto& track : tracks.morphs) {
    if (corners < 0)
      corners = addFloatAccessor(model, zeros, TINYGLTF_TYPE_VEC3, 3, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0},
                                 TINYGLTF_TARGET_ARRAY_BUFFER);
    const auto& from = source.meshes[static_cast<std::size_t>(source.nodes[static_cast<std::size_t>(track.node)].mesh)];
    const int targets = static_cast<int>(track.weights.rows());
    tinygltf::Mesh mesh;
    mesh.name = from.name;
    tinygltf::Primitive primitive;
    primitive.attributes["POSITION"] = corners;
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    primitive.targets.assign(static_cast<std::size_t>(targets), {{"POSITION", corners}});
    mesh.primitives.push_back(primitive);
    mesh.weights = from.weights;
    if (static_cast<int>(mesh.weights.size()) != targets) mesh.weights.assign(static_cast<std::size_t>(targets), 0.0);
    const auto names = targetNamesOf(source, source.nodes[static_cast<std::size_t>(track.node)].mesh);
    if (static_cast<int>(names.size()) == targets) {
      tinygltf::Value::Array list;
      for (const auto& name : names) list.emplace_back(name);
      tinygltf::Value::Object extras;
      extras["targetNames"] = tinygltf::Value(std::move(list));
      mesh.extras = tinygltf::Value(std::move(extras));
    }
    model.meshes.push_back(std::move(mesh));
    model.nodes[static_cast<std::size_t>(track.node)].mesh = static_cast<int>(model.meshes.size()) - 1;
  }
  addAnimation(model, tracks, frames);
  writeModel(model, out, container);
}

}  // namespace th::formats
