#include "render/occlusion.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <numbers>

#include "core/atomic_file.h"
#include "core/error.h"
#include "gl_program.h"
#include "render/camera.h"
#include "shader_sources.h"

namespace th::render {
namespace {

// GL objects of one computation, released on every exit.
struct DepthViews {
  GLuint program = 0;
  GLuint vao = 0;
  GLuint vertexBuffer = 0;
  GLuint indexBuffer = 0;
  GLuint framebuffer = 0;
  GLuint depth = 0;

  ~DepthViews() {
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glBindVertexArray(0);
    glDeleteFramebuffers(1, &framebuffer);
    glDeleteRenderbuffers(1, &depth);
    glDeleteBuffers(1, &vertexBuffer);
    glDeleteBuffers(1, &indexBuffer);
    glDeleteVertexArrays(1, &vao);
    glDeleteProgram(program);
  }
};

Eigen::Matrix4f orthographic(float halfSize, float nearPlane, float farPlane) {
  Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
  m(0, 0) = 1.0f / halfSize;
  m(1, 1) = 1.0f / halfSize;
  m(2, 2) = -2.0f / (farPlane - nearPlane);
  m(2, 3) = -(farPlane + nearPlane) / (farPlane - nearPlane);
  return m;
}

// `count` directions over the sphere: a Fibonacci sphere, even and deterministic.
std::vector<Eigen::Vector3f> fibonacciSphere(int count) {
  std::vector<Eigen::Vector3f> directions;
  const float golden = std::numbers::pi_v<float> * (3.0f - std::sqrt(5.0f));
  for (int k = 0; k < count; ++k) {
    const float z = 1.0f - 2.0f * (static_cast<float>(k) + 0.5f) / static_cast<float>(count);
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const float phi = static_cast<float>(k) * golden;
    directions.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
  }
  return directions;
}

// Each vertex's value averaged with its neighbours' over the triangles, `passes` times (a vertex only with those
// of its own set of occluders: vertices that were not measured are left out).
void smoothOverTriangles(Eigen::VectorXf& open, const std::vector<std::array<int, 3>>& triangles,
                         const std::vector<std::uint32_t>& occludedBy, int passes) {
  Eigen::VectorXf sum(open.size());
  Eigen::VectorXf count(open.size());
  for (int pass = 0; pass < passes; ++pass) {
    sum = open;
    count.setOnes();
    for (const auto& t : triangles)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          const int a = t[static_cast<std::size_t>(i)];
          const int b = t[static_cast<std::size_t>(j)];
          if (i == j || occludedBy[static_cast<std::size_t>(a)] != occludedBy[static_cast<std::size_t>(b)]) continue;
          sum[a] += open[b];
          count[a] += 1.0f;
        }
    open = sum.cwiseQuotient(count);
  }
}

// The depth program, the mesh's vertices p (its triangles are given per pass, in the index buffer) and a size x size
// depth target, bound and set for the passes: depth tested and written, no culling, no blending.
void openDepthViews(DepthViews& gl, const Eigen::Matrix3Xf& p, int size) {
  gl.program = linkProgram(shaders::kDepth_vert, shaders::kDepth_frag, "depth");
  glGenVertexArrays(1, &gl.vao);
  glBindVertexArray(gl.vao);
  glGenBuffers(1, &gl.vertexBuffer);
  glBindBuffer(GL_ARRAY_BUFFER, gl.vertexBuffer);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(p.size() * static_cast<Eigen::Index>(sizeof(float))), p.data(),
               GL_STATIC_DRAW);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
  glEnableVertexAttribArray(0);
  glGenBuffers(1, &gl.indexBuffer);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, gl.indexBuffer);
  glGenFramebuffers(1, &gl.framebuffer);
  glBindFramebuffer(GL_FRAMEBUFFER, gl.framebuffer);
  glGenRenderbuffers(1, &gl.depth);
  glBindRenderbuffer(GL_RENDERBUFFER, gl.depth);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, size, size);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, gl.depth);
  glDrawBuffer(GL_NONE);
  glReadBuffer(GL_NONE);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw Error("computeOpenness: the depth framebuffer is incomplete");
  glUseProgram(gl.program);
  glViewport(0, 0, size, size);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDisable(GL_CULL_FACE);  // a surface blocks light from both its sides
  glDisable(GL_BLEND);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
}

}  // namespace

Eigen::VectorXf computeOpenness(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xf& normals,
                                const std::vector<std::array<int, 3>>& triangles, const std::vector<int>& triangleGroup,
                                const std::vector<std::uint32_t>& occludedBy, const OcclusionOptions& options) {
  const Eigen::Index n = positions.cols();
  if (normals.cols() != n || static_cast<Eigen::Index>(occludedBy.size()) != n ||
      triangleGroup.size() != triangles.size())
    throw Error("computeOpenness: positions, normals, groups and masks disagree in size");
  Eigen::VectorXf open = Eigen::VectorXf::Ones(n);
  if (n == 0 || triangles.empty() || options.directions <= 0 || options.resolution <= 0) return open;

  const Eigen::Vector3f low = positions.rowwise().minCoeff().cast<float>();
  const Eigen::Vector3f high = positions.rowwise().maxCoeff().cast<float>();
  const Eigen::Vector3f centre = 0.5f * (low + high);
  const float radius = 0.5f * (high - low).norm() * 1.02f + 1e-3f;
  const int size = options.resolution;
  const float texel = 2.0f * radius / static_cast<float>(size);
  const float depthRange = 2.0f * radius;  // near = radius, far = 3 * radius from the eye

  const Eigen::Matrix3Xf p = positions.cast<float>();
  DepthViews gl;
  openDepthViews(gl, p, size);
  const GLint viewProjectionAt = glGetUniformLocation(gl.program, "uViewProjection");

  const std::vector<Eigen::Vector3f> directions = fibonacciSphere(options.directions);

  // One pass per distinct set of occluders.
  std::map<std::uint32_t, std::vector<int>> receiversOf;
  for (Eigen::Index v = 0; v < n; ++v)
    if (occludedBy[static_cast<std::size_t>(v)] != 0)
      receiversOf[occludedBy[static_cast<std::size_t>(v)]].push_back(static_cast<int>(v));
  std::vector<float> depth(static_cast<std::size_t>(size) * static_cast<std::size_t>(size));
  std::vector<std::uint32_t> indices;
  for (const auto& [mask, receivers] : receiversOf) {
    indices.clear();
    for (std::size_t t = 0; t < triangles.size(); ++t)
      if ((mask >> triangleGroup[t] & 1U) != 0)
        for (int v : triangles[t]) indices.push_back(static_cast<std::uint32_t>(v));
    if (indices.empty()) continue;  // nothing can block these vertices: they stay open
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(indices.size() * sizeof(std::uint32_t)),
                 indices.data(), GL_STATIC_DRAW);
    std::vector<float> seen(receivers.size(), 0.0f);
    std::vector<float> weight(receivers.size(), 0.0f);
    for (const Eigen::Vector3f& d : directions) {
      const Eigen::Vector3f up = std::abs(d.y()) < 0.9f ? Eigen::Vector3f::UnitY() : Eigen::Vector3f::UnitX();
      const Eigen::Matrix4f viewProjection =
          orthographic(radius, radius, 3.0f * radius) * lookAt(centre + 2.0f * radius * d, centre, up);
      glUniformMatrix4fv(viewProjectionAt, 1, GL_FALSE, viewProjection.data());
      glClearDepth(1.0);
      glClear(GL_DEPTH_BUFFER_BIT);
      glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(indices.size()), GL_UNSIGNED_INT, nullptr);
      glReadPixels(0, 0, size, size, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
      for (std::size_t i = 0; i < receivers.size(); ++i) {
        const int v = receivers[i];
        const Eigen::Vector3f normal = normals.col(v);
        const float cosine = normal.dot(d);
        if (cosine <= 0.0f) continue;
        const Eigen::Vector4f clip = viewProjection * p.col(v).homogeneous();
        const int x = std::clamp(static_cast<int>((clip.x() * 0.5f + 0.5f) * static_cast<float>(size)), 0, size - 1);
        const int y = std::clamp(static_cast<int>((clip.y() * 0.5f + 0.5f) * static_cast<float>(size)), 0, size - 1);
        const float own = clip.z() * 0.5f + 0.5f;
        // Slope-scaled: a surface seen at a grazing angle changes depth by up to texel * tan across a texel.
        const float tangent = std::min(std::sqrt(std::max(0.0f, 1.0f - cosine * cosine)) / cosine, 4.0f);
        const float bias = (static_cast<float>(options.bias) + texel * tangent) / depthRange;
        const float nearest =
            depth[static_cast<std::size_t>(y) * static_cast<std::size_t>(size) + static_cast<std::size_t>(x)];
        weight[i] += cosine;
        if (own <= nearest + bias) seen[i] += cosine;
      }
    }
    for (std::size_t i = 0; i < receivers.size(); ++i)
      open[receivers[i]] = weight[i] > 0.0f ? seen[i] / weight[i] : 1.0f;
  }

  smoothOverTriangles(open, triangles, occludedBy, options.smoothingPasses);
  return open;
}

namespace {

// FNV-1a, 64 bits: enough to tell meshes and options apart (not a defence against crafted collisions: the
// cache is the user's own folder).
class Fnv1a {
 public:
  void add(const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) hash_ = (hash_ ^ p[i]) * 1099511628211ULL;
  }
  template <typename T>
  void addValue(const T& value) {
    add(&value, sizeof value);
  }
  std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 14695981039346656037ULL;
};

constexpr char kCacheMagic[8] = {'T', 'H', 'O', 'P', 'E', 'N', '0', '1'};  // format version in the last two

}  // namespace

Eigen::VectorXf computeOpennessCached(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xf& normals,
                                      const std::vector<std::array<int, 3>>& triangles,
                                      const std::vector<int>& triangleGroup,
                                      const std::vector<std::uint32_t>& occludedBy, const std::filesystem::path& folder,
                                      const OcclusionOptions& options) {
  if (folder.empty()) return computeOpenness(positions, normals, triangles, triangleGroup, occludedBy, options);
  Fnv1a hash;
  hash.add(kCacheMagic, sizeof kCacheMagic);
  hash.add(positions.data(), static_cast<std::size_t>(positions.size()) * sizeof(double));
  hash.add(normals.data(), static_cast<std::size_t>(normals.size()) * sizeof(float));
  hash.add(triangles.data(), triangles.size() * sizeof(triangles[0]));
  hash.add(triangleGroup.data(), triangleGroup.size() * sizeof(int));
  hash.add(occludedBy.data(), occludedBy.size() * sizeof(std::uint32_t));
  hash.addValue(options.directions);
  hash.addValue(options.resolution);
  hash.addValue(options.bias);
  hash.addValue(options.smoothingPasses);
  char name[48];
  std::snprintf(name, sizeof name, "openness-%016llx.bin", static_cast<unsigned long long>(hash.value()));
  const std::filesystem::path file = folder / name;
  const std::uint64_t count = static_cast<std::uint64_t>(positions.cols());

  {  // A hit: the magic, the count and every value, finite and in 0..1.
    std::ifstream in(file, std::ios::binary);
    char magic[sizeof kCacheMagic] = {};
    std::uint64_t stored = 0;
    Eigen::VectorXf open(positions.cols());
    if (in.read(magic, sizeof magic) && std::equal(magic, magic + sizeof magic, kCacheMagic) &&
        in.read(reinterpret_cast<char*>(&stored), sizeof stored) && stored == count &&
        in.read(reinterpret_cast<char*>(open.data()), static_cast<std::streamsize>(count * sizeof(float))) &&
        in.peek() == std::char_traits<char>::eof() && open.allFinite() && open.minCoeff() >= 0.0f &&
        open.maxCoeff() <= 1.0f)
      return open;
  }
  Eigen::VectorXf open = computeOpenness(positions, normals, triangles, triangleGroup, occludedBy, options);
  try {
    std::filesystem::create_directories(folder);
    AtomicFile out(file);
    out.stream().write(kCacheMagic, sizeof kCacheMagic);
    out.stream().write(reinterpret_cast<const char*>(&count), sizeof count);
    out.stream().write(reinterpret_cast<const char*>(open.data()), static_cast<std::streamsize>(count * sizeof(float)));
    out.commit();
  } catch (const std::exception&) {
    // An unwritable cache only costs time next run; the result is right either way.
  }
  return open;
}

std::filesystem::path detailCacheFolder() {
  if (const char* own = std::getenv("TALKINGHEAD_CACHE")) return own;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && *xdg != '\0')
    return std::filesystem::path(xdg) / "talkinghead";
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0')
    return std::filesystem::path(home) / ".cache" / "talkinghead";
  return {};
}

}  // namespace th::render
