// glTF files as tinygltf models, including what tinygltf 2.7 cannot read by itself but avatar tools write:
// meshopt-compressed buffer views (EXT_meshopt_compression, gltfpack's output), WebP textures
// (EXT_texture_webp) and quantised attributes (KHR_mesh_quantization: integer accessors, read by accessorFloats).
// The avatar stage reads characters through it, and the glTF animation writer the characters it writes into.
//
//   const tinygltf::Model model = th::formats::readGltf("vroid.glb");          // .glb, .vrm or .gltf
//   const Eigen::MatrixXf positions = th::formats::accessorFloats(model, primitive.attributes.at("POSITION"));
//
// A compressed GLB is rewritten in memory before tinygltf parses it: each compressed view is decoded with
// meshoptimizer into its fallback buffer's place, the fallback buffers join the binary chunk, and the
// extension is dropped, so the model looks as if it had never been compressed. Images are decoded to pixels
// (WebP by libwebp, the rest by tinygltf's stb_image), or kept encoded for writing them out again.
// Errors (th::Error) name the file and say what is wrong, on one line.
// Thread contract: pure functions.
#pragma once

#include <tiny_gltf.h>

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace th::formats {

// The encoded bytes of each image as the file has them (indexed like the model's images).
struct GltfImageBytes {
  std::vector<std::vector<unsigned char>> images;
};

// images null: every image decoded to 8-bit pixels (a texture naming a WebP image through EXT_texture_webp gets
// it as its source). Otherwise the images are kept encoded in *images, their pixels left empty, and the
// file's textures as they are.
tinygltf::Model readGltf(const std::filesystem::path& path, GltfImageBytes* images = nullptr);

// An accessor's elements as floats, one column per element (rows: its component count), with glTF's rules for
// normalised integers; throws th::Error (naming `what`) for an accessor out of range.
Eigen::MatrixXf accessorFloats(const tinygltf::Model& model, int accessor, const std::string& what = "an accessor");
// An accessor of unsigned integers (indices, joints) as 32-bit values, one column per element.
Eigen::Matrix<std::uint32_t, Eigen::Dynamic, Eigen::Dynamic> accessorIndices(const tinygltf::Model& model, int accessor,
                                                                             const std::string& what = "an accessor");

// Appends zeros up to a multiple of `alignment` (glTF's buffers align accessors to 4).
void padBytes(std::vector<unsigned char>& bytes, std::size_t alignment);

}  // namespace th::formats
