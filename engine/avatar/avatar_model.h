// A user's character, read from a glTF file (.glb, .gltf) or a VRM (0.x or 1.0, glTF with an extension): its
// meshes with their morph targets, its skeleton, materials and textures, in the CPU's memory, ready to be posed
// (avatar_pose.h) and drawn (render/avatar_renderer.h, render/animated_avatar.h).
//
//   const th::avatar::Avatar character = th::avatar::loadAvatar("brunette-t.glb");
//   const int head = character.bones[th::avatar::kHead];        // a node index, -1 if it has none
//
// What drives a face is found by name: morph targets by their names (the mesh's extras.targetNames, or the
// primitive's), the neck, head and eye bones by VRM's humanoid map where the file has one, else by the node
// names most rigs use (Neck, Head, LeftEye, RightEye; Mixamo's "mixamorig:" prefix and VRoid's J_Bip_C_*
// names too), and VRM's expressions (0.x blend shape groups, 1.0 expressions) as lists of weighted targets.
// The scene's default pose is the bind pose it is posed from. Errors (th::Error) name the file.
// Thread contract: an Avatar is a value.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace th::avatar {

struct Texture {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba;  // width x height x 4, top row first
  bool repeat = true;              // wrap mode: repeat (else clamp to edge)
};

enum class AlphaMode { kOpaque, kMask, kBlend };

// glTF's metallic-roughness material; VRM's MToon read as its base colour and texture (unlit shading).
struct Material {
  std::string name;
  Eigen::Vector4f baseColour = Eigen::Vector4f::Ones();  // linear RGBA factor
  int baseColourTexture = -1;                            // index into Avatar::textures
  float metallic = 1.0f;
  float roughness = 1.0f;
  Eigen::Vector3f emissive = Eigen::Vector3f::Zero();
  int emissiveTexture = -1;
  AlphaMode alpha = AlphaMode::kOpaque;
  float alphaCutoff = 0.5f;
  bool doubleSided = false;
  bool unlit = false;  // KHR_materials_unlit or MToon
};

struct Primitive {
  Eigen::Matrix3Xf positions;                              // 3 x V, the mesh's own space
  Eigen::Matrix3Xf normals;                                // 3 x V (made from the triangles where the file has none)
  Eigen::Matrix2Xf uv;                                     // 2 x V (zeros where the file has none)
  Eigen::Matrix<std::uint16_t, 4, Eigen::Dynamic> joints;  // 4 x V, indices into the skin's joints (empty: unskinned)
  Eigen::Matrix4Xf weights;                                // 4 x V, summing to 1
  std::vector<std::uint32_t> indices;                      // triangles
  std::vector<Eigen::Matrix3Xf> targetPositions;           // per morph target: 3 x V displacements
  std::vector<Eigen::Matrix3Xf> targetNormals;             // per morph target (zeros where the file has none)
  int material = -1;
};

// A mesh where the scene uses it: its node, its skin and its morph targets' names.
struct MeshInstance {
  std::string name;
  int node = -1;
  int skin = -1;
  std::vector<Primitive> primitives;
  std::vector<std::string> targetNames;            // one per target ("" where the file names none)
  std::vector<float> restWeights;                  // the mesh's default weights
  int targetIndex(const std::string& name) const;  // -1 if absent
};

struct Node {
  std::string name;
  int parent = -1;
  Eigen::Vector3f translation = Eigen::Vector3f::Zero();
  Eigen::Quaternionf rotation = Eigen::Quaternionf::Identity();
  Eigen::Vector3f scale = Eigen::Vector3f::Ones();
  Eigen::Affine3f local() const;
};

struct Skin {
  std::vector<int> joints;  // node indices
  std::vector<Eigen::Matrix4f> inverseBind;
};

enum Bone { kNeck, kHead, kLeftEye, kRightEye, kNumBones };

// One target of one mesh at a weight: what a VRM expression moves.
struct TargetBind {
  int mesh = -1;  // index into Avatar::meshes
  int target = -1;
  float weight = 1.0f;
};

enum class AvatarFormat { kGltf, kVrm0, kVrm1 };

struct Avatar {
  std::string name;  // the file's stem
  AvatarFormat format = AvatarFormat::kGltf;
  std::vector<Node> nodes;
  std::vector<int> drawOrder;  // the scene's nodes, parents first
  std::vector<MeshInstance> meshes;
  std::vector<Skin> skins;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::array<int, kNumBones> bones{-1, -1, -1, -1};
  // The upper arms, left and right (VRM's leftUpperArm and rightUpperArm, else the usual names), -1 where none:
  // a character made in its T-pose is shown with its arms lowered (avatar_pose.h).
  std::array<int, 2> upperArms{-1, -1};
  // VRM's expressions by preset name in VRM 1.0's words (aa ih ou ee oh blink blinkLeft blinkRight lookUp ...;
  // VRM 0.x's a i u e o blink blink_l blink_r are renamed to them).
  std::map<std::string, std::vector<TargetBind>> expressions;
  // The model's forward: +z for glTF (and VRM 1.0), -z for VRM 0.x.
  bool facesMinusZ() const { return format == AvatarFormat::kVrm0; }
};

Avatar loadAvatar(const std::filesystem::path& path);

// Every node's transform in the scene (parents first), from local transforms (one per node).
std::vector<Eigen::Affine3f> globalTransforms(const Avatar& avatar, const std::vector<Eigen::Affine3f>& locals);

}  // namespace th::avatar
