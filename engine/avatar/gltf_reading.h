// glTF files as tinygltf models, including what tinygltf 2.7 cannot read by itself but avatar tools write:
// meshopt-compressed buffer views (EXT_meshopt_compression, gltfpack's output), WebP textures
// (EXT_texture_webp) and quantised attributes (KHR_mesh_quantization: integer accessors, read by accessorFloats).
//
//   const tinygltf::Model model = th::avatar::readGltf("vroid.glb");          // .glb, .vrm or .gltf
//   const Eigen::MatrixXf positions = th::avatar::accessorFloats(model, primitive.attributes.at("POSITION"));
//
// A compressed file is rewritten in memory before tinygltf parses it: each compressed view is decoded with
// meshoptimizer into a plain one at the end of the binary chunk, and the fallback buffer it replaced is dropped,
// so the model looks as if it had never been compressed. WebP images are decoded with libwebp, the rest by
// tinygltf (stb_image). Errors (th::Error) name the file and say what is wrong.
// Thread contract: pure functions.
#pragma once

#include <tiny_gltf.h>

#include <Eigen/Core>
#include <filesystem>

namespace th::avatar {

tinygltf::Model readGltf(const std::filesystem::path& path);

// An accessor's elements as floats, one column per element (rows: its component count), with glTF's rules for
// normalised integers; throws th::Error (naming `what`) for an accessor out of range.
Eigen::MatrixXf accessorFloats(const tinygltf::Model& model, int accessor, const std::string& what = "an accessor");
// An accessor of unsigned integers (indices, joints) as 32-bit values, one column per element.
Eigen::Matrix<std::uint32_t, Eigen::Dynamic, Eigen::Dynamic> accessorIndices(const tinygltf::Model& model, int accessor,
                                                                             const std::string& what = "an accessor");

}  // namespace th::avatar
