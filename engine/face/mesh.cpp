#include "face/mesh.h"

#include <tiny_obj_loader.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <system_error>

#include "core/error.h"

namespace th::face {
namespace {

tinyobj::ObjReader parseObj(const std::filesystem::path& path, bool wantMaterials) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) throw fileError(path, "no such file");
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  if (wantMaterials) config.mtl_search_path = path.parent_path().string();
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(path.string(), config)) {
    std::string message = reader.Error();
    std::replace(message.begin(), message.end(), '\n', ' ');
    throw fileError(path, "not a readable OBJ mesh (" + message + ")");
  }
  const auto& vertices = reader.GetAttrib().vertices;
  if (vertices.empty()) throw fileError(path, "no vertices");
  for (float v : vertices)
    if (!std::isfinite(v)) throw fileError(path, "a vertex position is not finite");
  return reader;
}

Eigen::Matrix3Xd positionsOf(const tinyobj::ObjReader& reader) {
  const auto& v = reader.GetAttrib().vertices;
  Eigen::Matrix3Xd positions(3, static_cast<Eigen::Index>(v.size() / 3));
  for (Eigen::Index i = 0; i < positions.cols(); ++i)
    for (int k = 0; k < 3; ++k) positions(k, i) = v[static_cast<std::size_t>(3 * i + k)];
  return positions;
}

}  // namespace

int Mesh::materialIndex(std::string_view name) const {
  for (std::size_t i = 0; i < materials.size(); ++i)
    if (materials[i].name == name) return static_cast<int>(i);
  return -1;
}

std::vector<int> Mesh::verticesOf(std::string_view materialName) const {
  const int material = materialIndex(materialName);
  std::vector<int> vertices;
  if (material < 0) return vertices;
  for (std::size_t t = 0; t < triangles.size(); ++t)
    if (triangleMaterial[t] == material) vertices.insert(vertices.end(), triangles[t].begin(), triangles[t].end());
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  return vertices;
}

Mesh loadObjMesh(const std::filesystem::path& path) {
  const tinyobj::ObjReader reader = parseObj(path, true);
  Mesh mesh;
  mesh.positions = positionsOf(reader);
  for (const tinyobj::material_t& m : reader.GetMaterials()) {
    Material material;
    material.name = m.name;
    material.diffuse = {m.diffuse[0], m.diffuse[1], m.diffuse[2]};
    material.specular = {m.specular[0], m.specular[1], m.specular[2]};
    material.shininess = m.shininess;
    mesh.materials.push_back(std::move(material));
  }
  const int numVertices = mesh.numVertices();
  const int numMaterials = static_cast<int>(mesh.materials.size());
  const std::vector<float>& texcoords = reader.GetAttrib().texcoords;
  mesh.uv = Eigen::Matrix2Xf::Zero(2, numVertices);
  std::vector<bool> hasUv(static_cast<std::size_t>(numVertices), false);
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    const auto& indices = shape.mesh.indices;
    for (std::size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
      if (shape.mesh.num_face_vertices[f] != 3) throw fileError(path, "a face could not be triangulated");
      std::array<int, 3> triangle{};
      for (int k = 0; k < 3; ++k) {
        const int vertex = indices[3 * f + static_cast<std::size_t>(k)].vertex_index;
        if (vertex < 0 || vertex >= numVertices) throw fileError(path, "a face refers to a vertex that does not exist");
        triangle[static_cast<std::size_t>(k)] = vertex;
        const int texcoord = indices[3 * f + static_cast<std::size_t>(k)].texcoord_index;
        if (texcoord >= 0 && 2 * static_cast<std::size_t>(texcoord) + 1 < texcoords.size() &&
            !hasUv[static_cast<std::size_t>(vertex)]) {
          mesh.uv(0, vertex) = texcoords[2 * static_cast<std::size_t>(texcoord)];
          mesh.uv(1, vertex) = texcoords[2 * static_cast<std::size_t>(texcoord) + 1];
          hasUv[static_cast<std::size_t>(vertex)] = true;
        }
      }
      const int material = shape.mesh.material_ids[f];
      mesh.triangles.push_back(triangle);
      mesh.triangleMaterial.push_back(material >= 0 && material < numMaterials ? material : -1);
    }
  }
  if (mesh.triangles.empty()) throw fileError(path, "no faces");
  return mesh;
}

Eigen::Matrix3Xd loadObjPositions(const std::filesystem::path& path, int expectedVertices) {
  Eigen::Matrix3Xd positions = positionsOf(parseObj(path, false));
  if (positions.cols() != expectedVertices)
    throw fileError(path, "has " + std::to_string(positions.cols()) + " vertices, the neutral mesh " +
                              std::to_string(expectedVertices));
  return positions;
}

Eigen::Matrix3Xd vertexNormals(const Mesh& mesh, std::initializer_list<std::string_view> materials) {
  std::vector<int> wanted;
  for (std::string_view name : materials)
    if (const int index = mesh.materialIndex(name); index >= 0) wanted.push_back(index);
  Eigen::Matrix3Xd normals = Eigen::Matrix3Xd::Zero(3, mesh.positions.cols());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (std::find(wanted.begin(), wanted.end(), mesh.triangleMaterial[t]) == wanted.end()) continue;
    const auto& [a, b, c] = mesh.triangles[t];
    const Eigen::Vector3d n =
        (mesh.positions.col(b) - mesh.positions.col(a)).cross(mesh.positions.col(c) - mesh.positions.col(a));
    for (int v : mesh.triangles[t]) normals.col(v) += n;
  }
  for (Eigen::Index v = 0; v < normals.cols(); ++v)
    if (normals.col(v).squaredNorm() > 0.0) normals.col(v).normalize();
  return normals;
}

}  // namespace th::face
