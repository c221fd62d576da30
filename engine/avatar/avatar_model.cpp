#include "avatar/avatar_model.h"

#include <algorithm>
#include <cctype>
#include <functional>
#include <string_view>

#include "core/error.h"
#include "formats/gltf_reading.h"

namespace th::avatar {

using formats::accessorFloats;
using formats::accessorIndices;
using formats::readGltf;

int MeshInstance::targetIndex(const std::string& target) const {
  const auto found = std::find(targetNames.begin(), targetNames.end(), target);
  return found == targetNames.end() ? -1 : static_cast<int>(found - targetNames.begin());
}

Eigen::Affine3f Node::local() const {
  Eigen::Affine3f transform = Eigen::Affine3f::Identity();
  transform.translate(translation);
  transform.rotate(rotation);
  transform.scale(scale);
  return transform;
}

std::vector<Eigen::Affine3f> globalTransforms(const Avatar& avatar, const std::vector<Eigen::Affine3f>& locals) {
  std::vector<Eigen::Affine3f> global(avatar.nodes.size(), Eigen::Affine3f::Identity());
  for (const int n : avatar.drawOrder) {
    const auto i = static_cast<std::size_t>(n);
    const int parent = avatar.nodes[i].parent;
    global[i] = parent < 0 ? locals[i] : global[static_cast<std::size_t>(parent)] * locals[i];
  }
  return global;
}

namespace {

using tinygltf::Value;

std::string lowered(std::string_view text) {
  std::string out(text);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

double numberOr(const Value& value, const char* key, double fallback) {
  if (!value.IsObject() || !value.Has(key)) return fallback;
  const Value& v = value.Get(key);
  return v.IsNumber() || v.IsInt() ? v.GetNumberAsDouble() : fallback;
}

int intOr(const Value& value, const char* key, int fallback) {
  if (!value.IsObject() || !value.Has(key)) return fallback;
  const Value& v = value.Get(key);
  return v.IsInt() || v.IsNumber() ? static_cast<int>(v.GetNumberAsDouble()) : fallback;
}

std::string stringOr(const Value& value, const char* key) {
  if (!value.IsObject() || !value.Has(key) || !value.Get(key).IsString()) return "";
  return value.Get(key).Get<std::string>();
}

std::vector<std::string> namesIn(const Value& extras) {
  std::vector<std::string> names;
  if (!extras.IsObject() || !extras.Has("targetNames") || !extras.Get("targetNames").IsArray()) return names;
  const Value& list = extras.Get("targetNames");
  for (std::size_t i = 0; i < list.ArrayLen(); ++i)
    names.push_back(list.Get(static_cast<int>(i)).IsString() ? list.Get(static_cast<int>(i)).Get<std::string>() : "");
  return names;
}

Node nodeOf(const tinygltf::Node& source) {
  Node node;
  node.name = source.name;
  if (source.matrix.size() == 16) {
    Eigen::Matrix4f m;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) m(r, c) = static_cast<float>(source.matrix[static_cast<std::size_t>(c * 4 + r)]);
    const Eigen::Affine3f transform(m);
    Eigen::Matrix3f rotation, scaling;
    transform.computeRotationScaling(&rotation, &scaling);
    node.translation = transform.translation();
    node.rotation = Eigen::Quaternionf(rotation);
    node.scale = scaling.diagonal();
    return node;
  }
  if (source.translation.size() == 3)
    node.translation =
        Eigen::Vector3d(source.translation[0], source.translation[1], source.translation[2]).cast<float>();
  if (source.rotation.size() == 4)
    node.rotation = Eigen::Quaternionf(static_cast<float>(source.rotation[3]), static_cast<float>(source.rotation[0]),
                                       static_cast<float>(source.rotation[1]), static_cast<float>(source.rotation[2]))
                        .normalized();
  if (source.scale.size() == 3)
    node.scale = Eigen::Vector3d(source.scale[0], source.scale[1], source.scale[2]).cast<float>();
  return node;
}

// Flat normals' average where the file has none.
Eigen::Matrix3Xf normalsOf(const Eigen::Matrix3Xf& positions, const std::vector<std::uint32_t>& indices) {
  Eigen::Matrix3Xf normals = Eigen::Matrix3Xf::Zero(3, positions.cols());
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
    const Eigen::Vector3f a = positions.col(indices[t]), b = positions.col(indices[t + 1]),
                          c = positions.col(indices[t + 2]);
    const Eigen::Vector3f n = (b - a).cross(c - a);
    for (int k = 0; k < 3; ++k) normals.col(indices[t + static_cast<std::size_t>(k)]) += n;
  }
  for (Eigen::Index v = 0; v < normals.cols(); ++v) {
    const float length = normals.col(v).norm();
    normals.col(v) = length > 0.0f ? Eigen::Vector3f(normals.col(v) / length) : Eigen::Vector3f::UnitY();
  }
  return normals;
}

Primitive primitiveOf(const std::filesystem::path& path, const tinygltf::Model& model,
                      const tinygltf::Primitive& source, const std::string& meshName) {
  const std::string what = path.string() + ": mesh " + meshName;
  Primitive primitive;
  const auto attribute = [&](const char* name) {
    const auto found = source.attributes.find(name);
    return found == source.attributes.end() ? -1 : found->second;
  };
  if (attribute("POSITION") < 0) throw fileError(path, "mesh " + meshName + " has a primitive without positions");
  primitive.positions = accessorFloats(model, attribute("POSITION"), what);
  const Eigen::Index vertices = primitive.positions.cols();
  const auto sized = [&](const Eigen::MatrixXf& m, Eigen::Index rows, const char* name) {
    if (m.rows() < rows || m.cols() != vertices)
      throw fileError(path, "mesh " + meshName + ": its " + name + " do not match its positions");
    return m.topRows(rows);
  };
  if (source.indices >= 0) {
    const auto indices = accessorIndices(model, source.indices, what);
    primitive.indices.assign(indices.data(), indices.data() + indices.size());
  } else {
    for (Eigen::Index v = 0; v < vertices; ++v) primitive.indices.push_back(static_cast<std::uint32_t>(v));
  }
  for (const std::uint32_t index : primitive.indices)
    if (index >= static_cast<std::uint32_t>(vertices))
      throw fileError(path, "mesh " + meshName + " has an index past its vertices");
  primitive.indices.resize(primitive.indices.size() / 3 * 3);
  primitive.normals = attribute("NORMAL") >= 0
                          ? Eigen::Matrix3Xf(sized(accessorFloats(model, attribute("NORMAL"), what), 3, "normals"))
                          : normalsOf(primitive.positions, primitive.indices);
  primitive.uv = attribute("TEXCOORD_0") >= 0
                     ? Eigen::Matrix2Xf(sized(accessorFloats(model, attribute("TEXCOORD_0"), what), 2, "UVs"))
                     : Eigen::Matrix2Xf::Zero(2, vertices);
  if (attribute("JOINTS_0") >= 0 && attribute("WEIGHTS_0") >= 0) {
    const auto joints = accessorIndices(model, attribute("JOINTS_0"), what);
    if (joints.rows() != 4 || joints.cols() != vertices)
      throw fileError(path, "mesh " + meshName + ": its joints do not match its positions");
    primitive.joints = joints.cast<std::uint16_t>();
    primitive.weights = sized(accessorFloats(model, attribute("WEIGHTS_0"), what), 4, "weights");
    for (Eigen::Index v = 0; v < vertices; ++v) {
      const float sum = primitive.weights.col(v).sum();
      if (sum > 0.0f) primitive.weights.col(v) /= sum;
    }
  }
  for (const auto& target : source.targets) {
    const auto position = target.find("POSITION");
    primitive.targetPositions.push_back(
        position == target.end()
            ? Eigen::Matrix3Xf::Zero(3, vertices)
            : Eigen::Matrix3Xf(sized(accessorFloats(model, position->second, what), 3, "target positions")));
    const auto normal = target.find("NORMAL");
    primitive.targetNormals.push_back(
        normal == target.end()
            ? Eigen::Matrix3Xf::Zero(3, vertices)
            : Eigen::Matrix3Xf(sized(accessorFloats(model, normal->second, what), 3, "target normals")));
  }
  primitive.material = source.material;
  return primitive;
}

Texture textureOf(const tinygltf::Model& model, const tinygltf::Texture& source) {
  Texture texture;
  if (source.source < 0 || source.source >= static_cast<int>(model.images.size())) return texture;
  const tinygltf::Image& image = model.images[static_cast<std::size_t>(source.source)];
  if (image.width <= 0 || image.height <= 0 || image.component < 1 || image.image.empty()) return texture;
  texture.width = image.width;
  texture.height = image.height;
  const std::size_t pixels = static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
  const std::size_t bytesPer = static_cast<std::size_t>(image.bits > 8 ? 2 : 1);
  if (image.image.size() < pixels * static_cast<std::size_t>(image.component) * bytesPer) return Texture{};
  texture.rgba.resize(pixels * 4);
  for (std::size_t p = 0; p < pixels; ++p) {
    std::uint8_t channel[4] = {0, 0, 0, 255};
    for (int c = 0; c < image.component && c < 4; ++c) {
      const std::size_t at = (p * static_cast<std::size_t>(image.component) + static_cast<std::size_t>(c)) * bytesPer;
      channel[c] = bytesPer == 2 ? image.image[at + 1] : image.image[at];  // 16-bit little-endian: the high byte
    }
    if (image.component == 1 || image.component == 2) {  // grey (and alpha)
      channel[3] = image.component == 2 ? channel[1] : 255;
      channel[1] = channel[2] = channel[0];
    }
    std::copy(channel, channel + 4, texture.rgba.begin() + static_cast<std::ptrdiff_t>(p * 4));
  }
  if (source.sampler >= 0 && source.sampler < static_cast<int>(model.samplers.size()))
    texture.repeat =
        model.samplers[static_cast<std::size_t>(source.sampler)].wrapS != TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
  return texture;
}

Material materialOf(const tinygltf::Material& source) {
  Material material;
  material.name = source.name;
  const auto& pbr = source.pbrMetallicRoughness;
  if (pbr.baseColorFactor.size() == 4)
    material.baseColour =
        Eigen::Vector4d(pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2], pbr.baseColorFactor[3])
            .cast<float>();
  material.baseColourTexture = pbr.baseColorTexture.index;
  material.metallic = static_cast<float>(pbr.metallicFactor);
  material.roughness = static_cast<float>(pbr.roughnessFactor);
  if (source.emissiveFactor.size() == 3)
    material.emissive =
        Eigen::Vector3d(source.emissiveFactor[0], source.emissiveFactor[1], source.emissiveFactor[2]).cast<float>();
  material.emissiveTexture = source.emissiveTexture.index;
  material.alpha = source.alphaMode == "MASK"    ? AlphaMode::kMask
                   : source.alphaMode == "BLEND" ? AlphaMode::kBlend
                                                 : AlphaMode::kOpaque;
  material.alphaCutoff = static_cast<float>(source.alphaCutoff);
  material.doubleSided = source.doubleSided;
  material.unlit =
      source.extensions.count("KHR_materials_unlit") > 0 || source.extensions.count("VRMC_materials_mtoon") > 0;
  return material;
}

// The bones by the usual rigs' node names: Mixamo/Ready Player Me (Neck, Head, LeftEye), Mixamo's prefix,
// VRoid (J_Bip_C_Neck, J_Bip_C_Head, J_Adj_L_FaceEye).
// The first node (without a mesh: a joint) with one of `names` (lower case, any "prefix:" dropped), or -1.
int jointNamed(const Avatar& avatar, const std::vector<std::string>& names) {
  for (const std::string& wanted : names)
    for (const int n : avatar.drawOrder) {
      std::string name = lowered(avatar.nodes[static_cast<std::size_t>(n)].name);
      if (const auto colon = name.rfind(':'); colon != std::string::npos) name = name.substr(colon + 1);
      // A mesh node can carry a bone's name ("EyeLeft" is Ready Player Me's eye mesh): only nodes without
      // a mesh count, which is what skins' joints are.
      const bool isMesh =
          std::any_of(avatar.meshes.begin(), avatar.meshes.end(), [&](const MeshInstance& m) { return m.node == n; });
      if (name == wanted && !isMesh) return n;
    }
  return -1;
}

void bonesByName(Avatar& avatar) {
  const std::array<std::vector<std::string>, kNumBones> names{{
      {"neck", "j_bip_c_neck", "neck1", "neck_01"},
      {"head", "j_bip_c_head", "head_01"},
      {"lefteye", "eye_l", "eyeleft", "j_adj_l_faceeye", "eye.l", "left_eye"},
      {"righteye", "eye_r", "eyeright", "j_adj_r_faceeye", "eye.r", "right_eye"},
  }};
  for (int bone = 0; bone < kNumBones; ++bone)
    if (avatar.bones[static_cast<std::size_t>(bone)] < 0)
      avatar.bones[static_cast<std::size_t>(bone)] = jointNamed(avatar, names[static_cast<std::size_t>(bone)]);
  // Mixamo and Ready Player Me call the upper arm "LeftArm"; VRoid J_Bip_L_UpperArm; Unreal upperarm_l.
  const std::array<std::vector<std::string>, 2> arms{{
      {"leftarm", "leftupperarm", "j_bip_l_upperarm", "upperarm_l", "upperarm.l", "left_upper_arm"},
      {"rightarm", "rightupperarm", "j_bip_r_upperarm", "upperarm_r", "upperarm.r", "right_upper_arm"},
  }};
  for (std::size_t side = 0; side < 2; ++side)
    if (avatar.upperArms[side] < 0) avatar.upperArms[side] = jointNamed(avatar, arms[side]);
}

int meshOfNode(const Avatar& avatar, int node) {
  for (std::size_t m = 0; m < avatar.meshes.size(); ++m)
    if (avatar.meshes[m].node == node) return static_cast<int>(m);
  return -1;
}

void readVrm0(const tinygltf::Model& model, const std::vector<int>& meshOfGltfMesh, Avatar& avatar) {
  const Value& vrm = model.extensions.at("VRM");
  avatar.format = AvatarFormat::kVrm0;
  if (vrm.Has("humanoid") && vrm.Get("humanoid").Has("humanBones")) {
    const Value& bones = vrm.Get("humanoid").Get("humanBones");
    for (std::size_t i = 0; bones.IsArray() && i < bones.ArrayLen(); ++i) {
      const Value& bone = bones.Get(static_cast<int>(i));
      const std::string name = stringOr(bone, "bone");
      const int node = intOr(bone, "node", -1);
      if (node < 0 || node >= static_cast<int>(avatar.nodes.size())) continue;
      if (name == "neck") avatar.bones[kNeck] = node;
      if (name == "head") avatar.bones[kHead] = node;
      if (name == "leftEye") avatar.bones[kLeftEye] = node;
      if (name == "rightEye") avatar.bones[kRightEye] = node;
      if (name == "leftUpperArm") avatar.upperArms[0] = node;
      if (name == "rightUpperArm") avatar.upperArms[1] = node;
    }
  }
  static const std::map<std::string, std::string> kRenamed = {{"a", "aa"},
                                                              {"i", "ih"},
                                                              {"u", "ou"},
                                                              {"e", "ee"},
                                                              {"o", "oh"},
                                                              {"blink", "blink"},
                                                              {"blink_l", "blinkLeft"},
                                                              {"blink_r", "blinkRight"}};
  if (!vrm.Has("blendShapeMaster") || !vrm.Get("blendShapeMaster").Has("blendShapeGroups")) return;
  const Value& groups = vrm.Get("blendShapeMaster").Get("blendShapeGroups");
  for (std::size_t g = 0; groups.IsArray() && g < groups.ArrayLen(); ++g) {
    const Value& group = groups.Get(static_cast<int>(g));
    std::string preset = lowered(stringOr(group, "presetName"));
    if (const auto renamed = kRenamed.find(preset); renamed != kRenamed.end()) preset = renamed->second;
    if (preset.empty() || preset == "unknown") preset = stringOr(group, "name");
    std::vector<TargetBind> binds;
    if (group.Has("binds") && group.Get("binds").IsArray()) {
      const Value& list = group.Get("binds");
      for (std::size_t b = 0; b < list.ArrayLen(); ++b) {
        const Value& bind = list.Get(static_cast<int>(b));
        const int gltfMesh = intOr(bind, "mesh", -1);
        if (gltfMesh < 0 || gltfMesh >= static_cast<int>(meshOfGltfMesh.size()) ||
            meshOfGltfMesh[static_cast<std::size_t>(gltfMesh)] < 0)
          continue;
        binds.push_back({meshOfGltfMesh[static_cast<std::size_t>(gltfMesh)], intOr(bind, "index", -1),
                         static_cast<float>(numberOr(bind, "weight", 100.0) / 100.0)});
      }
    }
    if (!binds.empty()) avatar.expressions[preset] = binds;
  }
}

void readVrm1(const tinygltf::Model& model, Avatar& avatar) {
  const Value& vrm = model.extensions.at("VRMC_vrm");
  avatar.format = AvatarFormat::kVrm1;
  if (vrm.Has("humanoid") && vrm.Get("humanoid").Has("humanBones")) {
    const Value& bones = vrm.Get("humanoid").Get("humanBones");
    const std::array<std::pair<const char*, Bone>, 4> wanted{
        {{"neck", kNeck}, {"head", kHead}, {"leftEye", kLeftEye}, {"rightEye", kRightEye}}};
    for (const auto& [name, bone] : wanted) {
      if (!bones.Has(name)) continue;
      const int node = intOr(bones.Get(name), "node", -1);
      if (node >= 0 && node < static_cast<int>(avatar.nodes.size()))
        avatar.bones[static_cast<std::size_t>(bone)] = node;
    }
    for (const auto& [name, side] : {std::pair{"leftUpperArm", 0}, std::pair{"rightUpperArm", 1}})
      if (bones.Has(name))
        if (const int node = intOr(bones.Get(name), "node", -1);
            node >= 0 && node < static_cast<int>(avatar.nodes.size()))
          avatar.upperArms[static_cast<std::size_t>(side)] = node;
  }
  if (!vrm.Has("expressions")) return;
  for (const char* kind : {"preset", "custom"}) {
    if (!vrm.Get("expressions").Has(kind)) continue;
    const Value& expressions = vrm.Get("expressions").Get(kind);
    for (const std::string& name : expressions.Keys()) {
      const Value& expression = expressions.Get(name);
      std::vector<TargetBind> binds;
      if (expression.Has("morphTargetBinds") && expression.Get("morphTargetBinds").IsArray()) {
        const Value& list = expression.Get("morphTargetBinds");
        for (std::size_t b = 0; b < list.ArrayLen(); ++b) {
          const Value& bind = list.Get(static_cast<int>(b));
          const int mesh = meshOfNode(avatar, intOr(bind, "node", -1));
          if (mesh >= 0)
            binds.push_back({mesh, intOr(bind, "index", -1), static_cast<float>(numberOr(bind, "weight", 1.0))});
        }
      }
      if (!binds.empty()) avatar.expressions[name] = binds;
    }
  }
}

// The meshes of the scene's nodes, in draw order, with their triangle primitives and morph targets; returns each
// glTF mesh's first instance (-1: none), which VRM 0's blend shapes name.
std::vector<int> readSceneMeshes(const std::filesystem::path& path, const tinygltf::Model& model, Avatar& avatar) {
  std::vector<int> meshOfGltfMesh(model.meshes.size(), -1);
  for (const int n : avatar.drawOrder) {
    const tinygltf::Node& node = model.nodes[static_cast<std::size_t>(n)];
    if (node.mesh < 0 || node.mesh >= static_cast<int>(model.meshes.size())) continue;
    const tinygltf::Mesh& source = model.meshes[static_cast<std::size_t>(node.mesh)];
    MeshInstance mesh;
    mesh.name = source.name.empty() ? node.name : source.name;
    mesh.node = n;
    mesh.skin = node.skin;
    for (const tinygltf::Primitive& primitive : source.primitives) {
      if (primitive.mode != -1 && primitive.mode != TINYGLTF_MODE_TRIANGLES) continue;  // lines and points: not a face
      mesh.primitives.push_back(primitiveOf(path, model, primitive, mesh.name));
    }
    if (mesh.primitives.empty()) continue;
    const std::size_t targets = mesh.primitives.front().targetPositions.size();
    for (const Primitive& p : mesh.primitives)
      if (p.targetPositions.size() != targets)
        throw fileError(path, "mesh " + mesh.name + " has primitives with different morph targets");
    mesh.targetNames = namesIn(source.extras);
    if (mesh.targetNames.empty() && !source.primitives.empty())
      mesh.targetNames = namesIn(source.primitives.front().extras);
    mesh.targetNames.resize(targets);
    for (double w : source.weights) mesh.restWeights.push_back(static_cast<float>(w));
    mesh.restWeights.resize(targets, 0.0f);
    if (meshOfGltfMesh[static_cast<std::size_t>(node.mesh)] < 0)
      meshOfGltfMesh[static_cast<std::size_t>(node.mesh)] = static_cast<int>(avatar.meshes.size());
    avatar.meshes.push_back(std::move(mesh));
  }
  return meshOfGltfMesh;
}

// The skins, their joints checked, and each mesh's joint indices checked against its skin.
void readAvatarSkins(const std::filesystem::path& path, const tinygltf::Model& model, Avatar& avatar) {
  for (const tinygltf::Skin& source : model.skins) {
    Skin skin;
    skin.joints = source.joints;
    for (const int joint : skin.joints)
      if (joint < 0 || joint >= static_cast<int>(avatar.nodes.size()))
        throw fileError(path, "has a skin joint that is not a node");
    if (source.inverseBindMatrices >= 0) {
      const Eigen::MatrixXf matrices = accessorFloats(model, source.inverseBindMatrices, path.string() + ": a skin");
      if (matrices.rows() != 16 || matrices.cols() != static_cast<Eigen::Index>(skin.joints.size()))
        throw fileError(path, "has a skin whose inverse bind matrices do not match its joints");
      for (Eigen::Index j = 0; j < matrices.cols(); ++j)
        skin.inverseBind.push_back(Eigen::Map<const Eigen::Matrix4f>(matrices.col(j).data()));
    } else {
      skin.inverseBind.assign(skin.joints.size(), Eigen::Matrix4f::Identity());
    }
    avatar.skins.push_back(std::move(skin));
  }
  for (const MeshInstance& mesh : avatar.meshes) {
    if (mesh.skin >= static_cast<int>(avatar.skins.size()))
      throw fileError(path, "mesh " + mesh.name + " names a skin it does not have");
    for (const Primitive& p : mesh.primitives) {
      if (mesh.skin < 0 || p.joints.size() == 0) continue;
      if (p.joints.maxCoeff() >= avatar.skins[static_cast<std::size_t>(mesh.skin)].joints.size())
        throw fileError(path, "mesh " + mesh.name + " has a joint index past its skin's joints");
    }
  }
}

}  // namespace

Avatar loadAvatar(const std::filesystem::path& path) {
  const tinygltf::Model model = readGltf(path);
  Avatar avatar;
  avatar.name = path.stem().string();
  for (const tinygltf::Node& node : model.nodes) avatar.nodes.push_back(nodeOf(node));
  for (std::size_t n = 0; n < model.nodes.size(); ++n)
    for (const int child : model.nodes[n].children) {
      if (child < 0 || child >= static_cast<int>(model.nodes.size()) ||
          avatar.nodes[static_cast<std::size_t>(child)].parent >= 0)
        throw fileError(path, "has a node hierarchy that is not a tree");
      avatar.nodes[static_cast<std::size_t>(child)].parent = static_cast<int>(n);
    }
  // The scene's nodes, parents first.
  std::vector<int> roots;
  const int scene = model.defaultScene >= 0 ? model.defaultScene : 0;
  if (scene < static_cast<int>(model.scenes.size()))
    roots = model.scenes[static_cast<std::size_t>(scene)].nodes;
  else
    for (std::size_t n = 0; n < avatar.nodes.size(); ++n)
      if (avatar.nodes[n].parent < 0) roots.push_back(static_cast<int>(n));
  std::vector<bool> seen(avatar.nodes.size(), false);
  std::function<void(int)> visit = [&](int n) {
    if (n < 0 || n >= static_cast<int>(avatar.nodes.size()) || seen[static_cast<std::size_t>(n)]) return;
    seen[static_cast<std::size_t>(n)] = true;
    avatar.drawOrder.push_back(n);
    for (const int child : model.nodes[static_cast<std::size_t>(n)].children) visit(child);
  };
  for (const int root : roots) visit(root);

  const std::vector<int> meshOfGltfMesh = readSceneMeshes(path, model, avatar);
  if (avatar.meshes.empty()) throw fileError(path, "has no triangle mesh in its scene");
  readAvatarSkins(path, model, avatar);
  for (const tinygltf::Material& material : model.materials) avatar.materials.push_back(materialOf(material));
  for (const tinygltf::Texture& texture : model.textures) avatar.textures.push_back(textureOf(model, texture));
  if (model.extensions.count("VRMC_vrm") > 0)
    readVrm1(model, avatar);
  else if (model.extensions.count("VRM") > 0)
    readVrm0(model, meshOfGltfMesh, avatar);
  if (avatar.format == AvatarFormat::kVrm0 && model.extensions.at("VRM").Has("materialProperties")) {
    const Value& properties = model.extensions.at("VRM").Get("materialProperties");
    for (std::size_t i = 0; properties.IsArray() && i < properties.ArrayLen() && i < avatar.materials.size(); ++i)
      if (lowered(stringOr(properties.Get(static_cast<int>(i)), "shader")).find("mtoon") != std::string::npos)
        avatar.materials[i].unlit = true;
  }
  bonesByName(avatar);
  return avatar;
}

}  // namespace th::avatar
