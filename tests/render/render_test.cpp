// The rendering stage: off-screen images of the ICT FaceKit head (coverage, colours, eyes), determinism,
// motion, normals of a deformed mesh, PNG files, and the window context's error without a display. With
// TALKINGHEAD_RENDER_SNAPSHOTS=DIR the views rendered here are also written to DIR as PNG, to look at.
#include <glad/gl.h>
#include <gtest/gtest.h>

extern "C" {
#include <libswscale/swscale.h>
}

#include <Eigen/Geometry>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <numbers>
#include <string>
#include <tuple>

#include "core/error.h"
#include "core/temporary_file.h"
#include "face/face_model.h"
#include "face/feature_points.h"
#include "face/mesh.h"
#include "render/backdrop.h"
#include "render/camera.h"
#include "render/face_renderer.h"
#include "render/fxaa.h"
#include "render/gl_context.h"
#include "render/image.h"
#include "render/normals.h"
#include "render/occlusion.h"
#include "render/simplify.h"
#include "render/surfaces.h"
#include "render/yuv.h"

namespace {

namespace fs = std::filesystem;
using th::render::FaceRenderer;
using th::render::Image;
using th::render::OrbitCamera;

const th::face::Mesh& neutral() {
  static const th::face::Mesh mesh = th::face::loadObjMesh(th::face::ictFaceDirectory() / "generic_neutral_mesh.obj");
  return mesh;
}

// One context and renderer for the tests that draw the neutral head at 640x480 (the set-up costs a second).
struct Scene {
  th::render::OffscreenContext context;
  FaceRenderer renderer{context, neutral()};
  OrbitCamera camera = th::render::frameHead(neutral().positions, 640.0 / 480.0);
};

Scene& scene() {
  static Scene s;
  return s;
}

void snapshot(const Image& image, const std::string& name) {
  const char* dir = std::getenv("TALKINGHEAD_RENDER_SNAPSHOTS");
  if (dir == nullptr || *dir == '\0') return;
  th::render::writePng(fs::path(dir) / (name + ".png"), image);
}

// Where the head is: pixels that differ clearly from the backdrop's colour at the same row (the backdrop is a
// smooth vertical gradient with a soft pool of light, so its left and right edges are a good reference).
struct Coverage {
  double fraction = 0.0;
  double centreX = 0.0;
  double centreY = 0.0;
};

Coverage coverage(const Image& image) {
  Coverage c;
  long count = 0;
  for (int y = 0; y < image.height; ++y) {
    const std::uint8_t* edge = image.pixel(2, y);
    for (int x = 0; x < image.width; ++x) {
      const std::uint8_t* p = image.pixel(x, y);
      const int d = std::abs(p[0] - edge[0]) + std::abs(p[1] - edge[1]) + std::abs(p[2] - edge[2]);
      // The backdrop's pool of light brightens its middle by up to ~25 levels per channel and keeps it grey.
      const bool grey =
          std::abs((p[0] - edge[0]) - (p[2] - edge[2])) < 6 && std::abs((p[1] - edge[1]) - (p[2] - edge[2])) < 6;
      if (d > 45 && !(grey && d < 80)) {
        ++count;
        c.centreX += x;
        c.centreY += y;
      }
    }
  }
  if (count > 0) {
    c.centreX /= static_cast<double>(count);
    c.centreY /= static_cast<double>(count);
  }
  c.fraction = static_cast<double>(count) / (static_cast<double>(image.width) * image.height);
  return c;
}

bool skinLike(const std::uint8_t* p) {
  const int r = p[0];
  const int g = p[1];
  const int b = p[2];
  return r > 90 && r > g + 10 && g >= b - 5 && r - b > 25;
}

// The pixel where a world point lands.
std::pair<int, int> project(const OrbitCamera& camera, const Eigen::Vector3d& point, int width, int height) {
  const Eigen::Vector4f clip = camera.projection(static_cast<float>(width) / static_cast<float>(height)) *
                               camera.view() *
                               Eigen::Vector4f(static_cast<float>(point.x()), static_cast<float>(point.y()),
                                               static_cast<float>(point.z()), 1.0f);
  const float x = (clip.x() / clip.w() * 0.5f + 0.5f) * static_cast<float>(width);
  const float y = (0.5f - clip.y() / clip.w() * 0.5f) * static_cast<float>(height);
  return {static_cast<int>(std::lround(x)), static_cast<int>(std::lround(y))};
}

// The middle of the iris disc: the mean of the iris mesh's frontmost vertices (the eyes look ahead, +z).
Eigen::Vector3d pupilOf(const th::face::Mesh& mesh, const char* material) {
  const std::vector<int> vertices = mesh.verticesOf(material);
  double front = -1e9;
  for (int v : vertices) front = std::max(front, mesh.positions(2, v));
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int count = 0;
  for (int v : vertices)
    if (mesh.positions(2, v) > front - 0.15) {
      sum += mesh.positions.col(v);
      ++count;
    }
  return sum / count;
}

TEST(FaceRenderer, NeutralHeadFillsTheFrameWithSkinAndLivelyEyes) {
  Scene& s = scene();
  s.renderer.setPositions(neutral().positions);
  const Image image = s.renderer.renderImage(s.camera);
  snapshot(image, "front");
  ASSERT_EQ(image.width, 640);
  ASSERT_EQ(image.height, 480);
  EXPECT_GE(s.renderer.samples(), 4);

  const Coverage c = coverage(image);
  EXPECT_GT(c.fraction, 0.20);  // a portrait: the head is the subject
  EXPECT_LT(c.fraction, 0.60);  // and there is room round it
  EXPECT_NEAR(c.centreX, 320.0, 20.0);

  // The middle of the face (cheeks, nose, mouth): mostly skin.
  int skin = 0;
  int total = 0;
  const auto [noseX, noseY] = project(s.camera, Eigen::Vector3d(0.0, -1.0, 11.0), 640, 480);
  for (int y = noseY - 40; y <= noseY + 40; ++y)
    for (int x = noseX - 50; x <= noseX + 50; ++x) {
      skin += skinLike(image.pixel(x, y)) ? 1 : 0;
      ++total;
    }
  EXPECT_GT(static_cast<double>(skin) / total, 0.8);

  // Each eye: a white of the eye and a dark pupil within a box round the iris.
  for (const char* iris : {"M_IrisLeft", "M_IrisRight"}) {
    const auto [ex, ey] = project(s.camera, pupilOf(neutral(), iris), 640, 480);
    int light = 0;
    int dark = 0;
    for (int y = ey - 8; y <= ey + 8; ++y)
      for (int x = ex - 16; x <= ex + 16; ++x) {
        const std::uint8_t* p = image.pixel(x, y);
        const int luma = (2 * p[0] + 5 * p[1] + p[2]) / 8;
        if (luma > 170 && std::abs(p[0] - p[2]) < 40) ++light;
        if (luma < 40) ++dark;
      }
    EXPECT_GE(light, 8) << iris;
    EXPECT_GE(dark, 4) << iris;
    // The pupil is at the iris's centre (the darkest pixel near the projected centre of the iris disc).
    int darkest = 255;
    for (int y = ey - 1; y <= ey + 1; ++y)
      for (int x = ex - 1; x <= ex + 1; ++x) {
        const std::uint8_t* p = image.pixel(x, y);
        darkest = std::min(darkest, (2 * p[0] + 5 * p[1] + p[2]) / 8);
      }
    EXPECT_LT(darkest, 50) << iris;
  }
}

// The face's skin vertex whose texture coordinates lie nearest `uv` (ICT FaceKit's face tile: u 0..1, the
// face's left at u > 0.5, up is +v; the eyes' thin layers share the tile, hence the material).
int vertexNearUv(const th::face::Mesh& mesh, const Eigen::Vector2f& uv) {
  int nearest = -1;
  for (int v : mesh.verticesOf("M_Face"))
    if (nearest < 0 || (mesh.uv.col(v) - uv).squaredNorm() < (mesh.uv.col(nearest) - uv).squaredNorm()) nearest = v;
  return nearest;
}

// The mean colour of the 3x3 pixels round where a vertex lands.
Eigen::Vector3d colourAt(const Image& image, const OrbitCamera& camera, const Eigen::Vector3d& point) {
  const auto [cx, cy] = project(camera, point, image.width, image.height);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int y = cy - 1; y <= cy + 1; ++y)
    for (int x = cx - 1; x <= cx + 1; ++x)
      for (int k = 0; k < 3; ++k) sum[k] += image.pixel(x, y)[k];
  return sum / 9.0;
}

double luma(const Eigen::Vector3d& c) {
  return 0.25 * c[0] + 0.625 * c[1] + 0.125 * c[2];
}

TEST(FaceRenderer, TheFaceHasDarkBrowsAndRedLips) {
  Scene& s = scene();
  const th::face::Mesh& mesh = neutral();
  ASSERT_EQ(mesh.uv.cols(), mesh.numVertices());
  s.renderer.setPositions(mesh.positions);
  const Image image = s.renderer.renderImage(s.camera);
  const auto at = [&](int vertex) { return colourAt(image, s.camera, mesh.positions.col(vertex)); };
  for (const float side : {-1.0f, 1.0f}) {
    // The middle of each brow (its line in UV space runs through the brow landmarks' UVs), and the forehead
    // 2 cm above it.
    const int brow = vertexNearUv(mesh, {0.5f + side * 0.147f, 0.808f});
    const int forehead = vertexNearUv(mesh, {0.5f + side * 0.147f, 0.87f});
    EXPECT_GT(mesh.positions(1, forehead), mesh.positions(1, brow) + 1.5);
    EXPECT_LT(luma(at(brow)), luma(at(forehead)) - 40.0) << "side " << side;
    // The lips' red against a cheek's: clearly redder (R/G; the cheek is flushed, the lips about twice as red).
    const int cheek = vertexNearUv(mesh, {0.5f + side * 0.155f, 0.6f});
    Eigen::Index lip = 0;
    s.renderer.lipWeight().maxCoeff(&lip);
    const Eigen::Vector3d lipColour = at(static_cast<int>(lip));
    const Eigen::Vector3d cheekColour = at(cheek);
    EXPECT_GT(lipColour[0] / lipColour[1], cheekColour[0] / cheekColour[1] + 0.8) << "side " << side;
  }
}

TEST(FaceRenderer, OtherViewsShowTheHeadToo) {
  Scene& s = scene();
  s.renderer.setPositions(neutral().positions);
  for (const auto& [name, yaw, pitch] : {std::tuple{"three_quarter", 35.0f, 8.0f}, std::tuple{"profile", 90.0f, 0.0f},
                                         std::tuple{"back", 180.0f, 10.0f}, std::tuple{"below", 20.0f, -25.0f}}) {
    OrbitCamera camera = s.camera;
    camera.yawDegrees = yaw;
    camera.pitchDegrees = pitch;
    const Image image = s.renderer.renderImage(camera);
    snapshot(image, name);
    const Coverage c = coverage(image);
    EXPECT_GT(c.fraction, 0.15) << name;
    EXPECT_LT(c.fraction, 0.6) << name;
  }
}

TEST(FaceRenderer, RenderingTwiceGivesTheSamePixels) {
  Scene& s = scene();
  s.renderer.setPositions(neutral().positions);
  Image first;
  s.renderer.render(s.camera);
  s.renderer.readPixels(first);
  Image second;
  s.renderer.render(s.camera);
  s.renderer.readPixels(second);
  EXPECT_TRUE(first == second);
}

TEST(FaceRenderer, MovingTheMeshMovesTheFace) {
  Scene& s = scene();
  s.renderer.setPositions(neutral().positions);
  const Coverage before = coverage(s.renderer.renderImage(s.camera));
  Eigen::Matrix3Xd moved = neutral().positions;
  moved.row(0).array() += 2.0;  // 2 cm towards the face's left, which is the image's right seen from the front
  s.renderer.setPositions(moved);
  const Image image = s.renderer.renderImage(s.camera);
  const Coverage after = coverage(image);
  // 2 cm at the head's distance, in pixels: the projection of the shift at the target's depth.
  const auto [x0, y0] = project(s.camera, s.camera.target.cast<double>(), 640, 480);
  const auto [x1, y1] = project(s.camera, s.camera.target.cast<double>() + Eigen::Vector3d(2.0, 0.0, 0.0), 640, 480);
  EXPECT_NEAR(after.centreX - before.centreX, x1 - x0, 3.0);
  EXPECT_NEAR(after.centreY, before.centreY, 2.0);
  EXPECT_GT(x1 - x0, 10);
  EXPECT_EQ(y1, y0);
  // Normals are recomputed from the new positions: a translation leaves them as they were...
  const Eigen::Matrix3Xf movedNormals = s.renderer.normals();
  s.renderer.setPositions(neutral().positions);
  EXPECT_TRUE(movedNormals.isApprox(s.renderer.normals(), 1e-5f));
  // ...and a deformation (the head flattened front to back) turns them as the normals of the deformed mesh.
  Eigen::Matrix3Xd flat = neutral().positions;
  flat.row(2) *= 0.5;
  s.renderer.setPositions(flat);
  Eigen::Matrix3Xf expected;
  th::render::VertexNormals(neutral()).compute(flat, expected);
  EXPECT_TRUE(s.renderer.normals().isApprox(expected, 1e-6f));
  EXPECT_FALSE(s.renderer.normals().isApprox(movedNormals, 1e-2f));
  s.renderer.setPositions(neutral().positions);
}

TEST(FaceRenderer, PerVertexDetailDarkensCavitiesAndReddensTheLips) {
  const FaceRenderer& r = scene().renderer;
  const th::face::Mesh& mesh = neutral();
  Eigen::Index tip = 0;
  mesh.positions.row(2).maxCoeff(&tip);  // the nose's tip sees most of the sky
  EXPECT_GT(r.openness()[tip], 0.6f);
  const auto meanOver = [&](const Eigen::VectorXf& values, const char* material) {
    double sum = 0.0;
    const std::vector<int> vertices = mesh.verticesOf(material);
    for (int v : vertices) sum += values[v];
    return sum / static_cast<double>(vertices.size());
  };
  EXPECT_LT(meanOver(r.openness(), "M_GumsTongue"), 0.5);  // inside the mouth
  EXPECT_LT(meanOver(r.openness(), "M_Teeth"), 0.6);
  // Lips: the skin between the mouth's corners just above and below the slit; nothing on the forehead or
  // neck.
  EXPECT_GT(r.lipWeight().maxCoeff(), 0.9f);
  Eigen::Index forehead = 0;
  mesh.positions.row(1).maxCoeff(&forehead);
  EXPECT_EQ(r.lipWeight()[forehead], 0.0f);
  for (Eigen::Index v = 0; v < mesh.numVertices(); ++v)
    if (r.lipWeight()[v] > 0.5f) {
      EXPECT_LT(mesh.positions(1, v), -0.5) << v;  // below the nose (the slit is near y = -3)
      EXPECT_GT(mesh.positions(1, v), -6.0) << v;
      EXPECT_LT(std::abs(mesh.positions(0, v)), 3.5) << v;
    }
}

TEST(SkinMarkings, HairOnTheScalpNotTheFaceAndFlushedCheeks) {
  const th::face::Mesh& mesh = neutral();
  const th::render::SurfaceMap map = th::render::classifySurfaces(mesh);
  const th::render::SkinMarkings m = th::render::skinMarkings(mesh, map);
  Eigen::Index crown = 0;
  mesh.positions.row(1).maxCoeff(&crown);
  EXPECT_GT(m.hair[crown], 0.9f);
  const int cheek = vertexNearUv(mesh, {0.655f, 0.6f});
  const int forehead = vertexNearUv(mesh, {0.5f, 0.87f});
  EXPECT_EQ(m.hair[cheek], 0.0f);
  EXPECT_EQ(m.hair[forehead], 0.0f);
  EXPECT_GT(m.redness[cheek], m.redness[forehead] + 0.2f);
  // The back of the neck and the chin are bare.
  Eigen::Index chin = 0;
  (mesh.positions.row(2).array() - 1e3 * (mesh.positions.row(1).array() + 7.5).abs()).maxCoeff(&chin);
  EXPECT_LT(m.hair[chin], 0.01f);
}

TEST(EyeRig, FollowsARotatedHead) {
  const th::face::Mesh& mesh = neutral();
  const th::render::SurfaceMap map = th::render::classifySurfaces(mesh);
  std::vector<th::render::EyeRig> eyes = th::render::findEyes(mesh, map);
  ASSERT_EQ(eyes.size(), 2u);
  for (const auto& eye : eyes) {
    EXPECT_GT(eye.axis.z(), 0.95f);                   // looking ahead
    EXPECT_NEAR(std::abs(eye.centre.x()), 3.2, 0.3);  // eyes about 6.3 cm apart
    EXPECT_NEAR(eye.centre.y(), 3.6, 0.3);
  }
  // Turn the head 30 degrees about +y (and move it): the eyes' centres and axes turn with it.
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(30.0 * std::numbers::pi / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Vector3d shift(1.0, -2.0, 0.5);
  const Eigen::Matrix3Xd turned = (turn * mesh.positions).colwise() + shift;
  for (auto& eye : eyes) {
    const Eigen::Vector3f centre = eye.centre;
    const Eigen::Vector3f axis = eye.axis;
    eye.track(turned);
    EXPECT_TRUE(eye.centre.isApprox((turn.cast<float>() * centre + shift.cast<float>()), 1e-4f));
    EXPECT_TRUE(eye.axis.isApprox(turn.cast<float>() * axis, 1e-4f));
  }
}

TEST(FaceRenderer, ResizeAndWrongPositionCount) {
  th::render::OffscreenContext context;
  FaceRenderer renderer(context, neutral(), {.width = 320, .height = 200, .samples = 1});
  EXPECT_EQ(renderer.samples(), 1);
  Image image = renderer.renderImage(th::render::frameHead(neutral().positions, 1.6));
  EXPECT_EQ(image.width, 320);
  EXPECT_EQ(image.height, 200);
  EXPECT_GT(coverage(image).fraction, 0.15);
  renderer.resize(160, 120);
  renderer.render(th::render::frameHead(neutral().positions, 160.0 / 120.0));
  renderer.readPixels(image);
  EXPECT_EQ(image.width, 160);
  EXPECT_EQ(image.pixels.size(), 160u * 120u * 3u);
  EXPECT_THROW(renderer.setPositions(Eigen::Matrix3Xd::Zero(3, 10)), th::Error);
}

TEST(FaceRenderer, CullingOnTheCpuDrawsWhatGlWouldDraw) {
  th::render::OffscreenContext context;
  FaceRenderer cpu(context, neutral(), {.width = 320, .height = 240, .samples = 1});
  FaceRenderer gl(context, neutral(), {.width = 320, .height = 240, .samples = 1, .cullOnCpu = false});
  // The head turned and bent (as a head FAP would), seen from the front, a side, behind and above.
  const Eigen::Matrix3d turn =
      (Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  const Eigen::Matrix3Xd turned = turn * neutral().positions;
  cpu.setPositions(turned);
  gl.setPositions(turned);
  OrbitCamera camera = th::render::frameHead(neutral().positions, 320.0 / 240.0);
  for (const auto& [yaw, pitch] : {std::pair{0.0f, 0.0f}, {80.0f, 0.0f}, {180.0f, 10.0f}, {30.0f, 60.0f}}) {
    camera.yawDegrees = yaw;
    camera.pitchDegrees = pitch;
    const Image a = cpu.renderImage(camera);
    const Image b = gl.renderImage(camera);
    long differing = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) differing += a.pixels[i] != b.pixels[i] ? 1 : 0;
    EXPECT_EQ(differing, 0) << "yaw " << yaw << ", pitch " << pitch;
  }
}

TEST(FaceRenderer, CroppingToTheHeadChangesNoPixel) {
  th::render::OffscreenContext context;
  const th::render::RenderOptions whole{.width = 480, .height = 360, .samples = 1, .fxaa = true, .cropToHead = false};
  th::render::RenderOptions cropping = whole;
  cropping.cropToHead = true;
  FaceRenderer cropped(context, neutral(), cropping);
  FaceRenderer full(context, neutral(), whole);
  const OrbitCamera framed = th::render::frameHead(neutral().positions, 480.0 / 360.0);
  // One renderer through a sequence: the head turning and moving, seen from the side, close up (the head fills
  // the frame), moved out of view, and with the camera inside the head (vertices behind it: the whole frame).
  // Both read-backs compared.
  struct Step {
    double yaw;
    Eigen::Vector3d shift;
    float cameraYaw, distance;
  };
  const float d = framed.distance;
  int croppedFrames = 0;
  th::render::RawFrame rawCropped, rawFull;
  for (const Step& step :
       {Step{0.0, {0, 0, 0}, 0, d}, Step{0.35, {6, 2, 0}, 0, d}, Step{-0.3, {-8, 0, 0}, 0, d},
        Step{0.0, {0, 0, 0}, 80, d}, Step{0.1, {0, 0, 0}, 0, 0.35f * d}, Step{0.0, {500, 0, 0}, 0, d},
        Step{0.0, {0, 0, 0}, 0, 2.0f}, Step{-0.2, {3, -3, 0}, 20, d}}) {
    const Eigen::Matrix3Xd positions =
        (Eigen::AngleAxisd(step.yaw, Eigen::Vector3d::UnitY()).toRotationMatrix() * neutral().positions).colwise() +
        step.shift;
    OrbitCamera camera = framed;
    camera.yawDegrees = step.cameraYaw;
    camera.distance = step.distance;
    const std::string what = "yaw " + std::to_string(step.yaw) + ", camera " + std::to_string(step.cameraYaw) + " at " +
                             std::to_string(step.distance);
    // The GL targets themselves (what present() shows in a window) hold the same: cropping changes only what
    // is read back. render() leaves its target bound.
    std::array<std::vector<std::uint8_t>, 2> targets;
    for (int i = 0; i < 2; ++i) {
      FaceRenderer& r = i == 0 ? cropped : full;
      r.setPositions(positions);
      r.render(camera);
      GLint target = 0;
      glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &target);
      glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(target));
      glPixelStorei(GL_PACK_ALIGNMENT, 1);
      targets[static_cast<std::size_t>(i)].resize(480 * 360 * 4);
      glReadPixels(0, 0, 480, 360, GL_RGBA, GL_UNSIGNED_BYTE, targets[static_cast<std::size_t>(i)].data());
    }
    EXPECT_TRUE(targets[0] == targets[1]) << what;
    const th::render::PixelRegion region = cropped.drawnRegion();
    if (region.width * region.height < 480 * 360) ++croppedFrames;
    EXPECT_EQ(full.drawnRegion(), (th::render::PixelRegion{0, 0, 480, 360})) << what;
    cropped.readRaw(rawCropped);
    full.readRaw(rawFull);
    th::render::Yuv420Image yuvCropped, yuvFull;
    th::render::RawFrame again = rawCropped;
    cropped.finish(again, yuvCropped, true);
    full.finish(rawFull, yuvFull, true);
    EXPECT_TRUE(yuvCropped.y == yuvFull.y && yuvCropped.cb == yuvFull.cb && yuvCropped.cr == yuvFull.cr) << what;
    const Image a = cropped.renderImage(camera);
    const Image b = full.renderImage(camera);
    long differing = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) differing += a.pixels[i] != b.pixels[i] ? 1 : 0;
    EXPECT_EQ(differing, 0) << what;
  }
  // The sequence did crop: the framed, turned and out-of-view steps (the last with nothing to draw).
  EXPECT_GE(croppedFrames, 5);
}

TEST(Simplify, FewerTrianglesOverTheSameVerticesOnTheSameSurfaceWithItsBorderKept) {
  // A dense hemisphere of radius 1 (an open surface: its rim is a border), 48 x 24 quads.
  constexpr int kAround = 48;
  constexpr int kDown = 24;
  Eigen::Matrix3Xd positions(3, kAround * (kDown + 1) + 1);
  positions.col(0) = Eigen::Vector3d::UnitZ();  // the pole
  for (int j = 1; j <= kDown + 1; ++j)
    for (int i = 0; i < kAround; ++i) {
      const double polar = std::numbers::pi / 2 * j / (kDown + 1);
      const double azimuth = 2 * std::numbers::pi * i / kAround;
      positions.col(1 + (j - 1) * kAround + i) << std::sin(polar) * std::cos(azimuth),
          std::sin(polar) * std::sin(azimuth), std::cos(polar);
    }
  const auto at = [](int ring, int i) { return static_cast<std::uint32_t>(1 + (ring - 1) * kAround + (i % kAround)); };
  std::vector<std::uint32_t> triangles;
  for (int i = 0; i < kAround; ++i) triangles.insert(triangles.end(), {0U, at(1, i), at(1, i + 1)});
  for (int j = 1; j <= kDown; ++j)
    for (int i = 0; i < kAround; ++i)
      triangles.insert(triangles.end(),
                       {at(j, i), at(j + 1, i), at(j + 1, i + 1), at(j, i), at(j + 1, i + 1), at(j, i + 1)});
  const auto area = [&](const std::vector<std::uint32_t>& t) {
    double sum = 0.0;
    for (std::size_t k = 0; k < t.size(); k += 3)
      sum +=
          0.5 *
          (positions.col(t[k + 1]) - positions.col(t[k])).cross(positions.col(t[k + 2]) - positions.col(t[k])).norm();
    return sum;
  };
  const std::vector<std::uint32_t> fewer =
      th::render::simplifyTriangles(triangles, positions, {.keep = 0.25f, .error = 0.01f});
  ASSERT_EQ(fewer.size() % 3, 0U);
  EXPECT_LT(fewer.size(), triangles.size() * 35 / 100);
  EXPECT_GT(fewer.size(), triangles.size() / 10);
  // No hole, nothing folded over: the same area within 2 %, every triangle still facing outwards, and its
  // centre within the 1 % error of the sphere (chords lie a little inside it).
  EXPECT_NEAR(area(fewer), area(triangles), 0.02 * area(triangles));
  for (std::size_t k = 0; k < fewer.size(); k += 3) {
    const Eigen::Vector3d a = positions.col(fewer[k]), b = positions.col(fewer[k + 1]), c = positions.col(fewer[k + 2]);
    const Eigen::Vector3d centre = (a + b + c) / 3.0;
    EXPECT_GT((b - a).cross(c - a).dot(centre), 0.0) << "triangle " << k / 3;
    EXPECT_GT(centre.norm(), 0.97) << "triangle " << k / 3;
  }
  // The rim stays: every one of its vertices is still used.
  for (int i = 0; i < kAround; ++i)
    EXPECT_NE(std::find(fewer.begin(), fewer.end(), at(kDown + 1, i)), fewer.end()) << "rim vertex " << i;
  EXPECT_THROW(th::render::simplifyTriangles({0, 1}, positions), th::Error);
  EXPECT_THROW(th::render::simplifyTriangles({0, 1, 100000}, positions), th::Error);
}

TEST(FaceRenderer, SimplifiedEyeballsLookTheSame) {
  const th::face::FaceModel face = th::face::FaceModel::buildDefault();
  th::render::OffscreenContext context;
  const th::render::RenderOptions options{.width = 1280, .height = 720, .samples = 1, .fxaa = true};
  th::render::RenderOptions full = options;
  full.simplifyEyeballs = false;
  FaceRenderer simplified(context, face.mesh(), options);
  FaceRenderer original(context, face.mesh(), full);
  const OrbitCamera camera = th::render::frameHead(face.mesh().positions, 1280.0 / 720.0);
  // Looking ahead, aside and up, the head turned; the pupils wide.
  for (const double gaze : {0.0, 40000.0, -40000.0}) {
    th::face::FapFrame faps{};
    faps[23] = faps[24] = gaze;
    faps[25] = faps[26] = gaze / 2;
    faps[49] = gaze / 2;
    faps[29] = faps[30] = gaze == 0.0 ? 0.0 : 300.0;
    const Eigen::Matrix3Xd positions = face.deform(faps);
    simplified.setPositions(positions);
    original.setPositions(positions);
    simplified.setPupilScale(face.pupilScale(faps));
    original.setPupilScale(face.pupilScale(faps));
    const Image a = simplified.renderImage(camera);
    const Image b = original.renderImage(camera);
    EXPECT_LT(simplified.trianglesDrawn(), original.trianglesDrawn() - 2000);
    long changed = 0;
    double sum = 0.0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
      const int d = std::abs(a.pixels[i] - b.pixels[i]);
      changed += d > 16 ? 1 : 0;
      sum += d;
    }
    // Some hundreds of values along the eyes' edges (a frame holds 2.8 million).
    EXPECT_LT(changed, 2500) << "gaze " << gaze;
    EXPECT_LT(sum / static_cast<double>(a.pixels.size()), 0.05) << "gaze " << gaze;
    // The pupils keep their size and shape: a coarser iris disc opens its pupil hole into a keyhole, where
    // the dark inside of the eye shows.
    const auto darkPixels = [](const Image& image) {
      long dark = 0;
      for (std::size_t i = 0; i < image.pixels.size(); i += 3)
        dark += image.pixels[i] < 30 && image.pixels[i + 1] < 30 && image.pixels[i + 2] < 30 ? 1 : 0;
      return dark;
    };
    EXPECT_NEAR(static_cast<double>(darkPixels(a)), static_cast<double>(darkPixels(b)),
                0.05 * static_cast<double>(darkPixels(b)))
        << "gaze " << gaze;
  }
}

TEST(FaceRenderer, TheMouthsInsideAndTheEyeballsAreDroppedOnlyWhereTheyCannotShow) {
  const th::face::FaceModel face = th::face::FaceModel::buildDefault();
  th::render::OffscreenContext context;
  FaceRenderer cpu(context, face.mesh(), {.width = 480, .height = 360, .samples = 1});
  FaceRenderer gl(context, face.mesh(), {.width = 480, .height = 360, .samples = 1, .cullOnCpu = false});
  cpu.setMouthOpening(face.innerLipVertices());
  cpu.setEyeOpenings(face.eyeLidVertices(0), face.eyeLidVertices(1));
  EXPECT_THROW(gl.setMouthOpening({face.mesh().numVertices()}), th::Error);
  OrbitCamera camera = th::render::frameHead(face.mesh().positions, 480.0 / 360.0);
  // Lips closed, parted, open and wide open; a smile; a turned, tilted head; eyes looking aside and up, half
  // shut, shut; seen from the front, a side, below and above, and close up.
  struct Pose {
    double jaw, smile, yaw, gaze, lids;
  };
  int cases = 0;
  for (const Pose& pose : {Pose{0, 0, 0, 0, 0}, Pose{40, 0, 0, 0, 0}, Pose{250, 0, 0, 0, 0}, Pose{700, 0, 0, 0, 0},
                           Pose{120, 250, 0, 40000, 0}, Pose{300, 0, 20000, -40000, 500}, Pose{0, 0, 0, 0, 1024}}) {
    th::face::FapFrame faps{};
    faps[3] = pose.jaw;
    faps[53] = faps[54] = faps[12] = faps[13] = pose.smile;
    faps[49] = pose.yaw;
    faps[48] = pose.yaw / 2;
    faps[23] = faps[24] = pose.gaze;       // eyeballs turn sideways
    faps[25] = faps[26] = -pose.gaze / 2;  // and up or down
    faps[19] = faps[20] = pose.lids;
    const Eigen::Matrix3Xd positions = face.deform(faps);
    cpu.setPositions(positions);
    gl.setPositions(positions);
    for (const auto& [yaw, pitch, distance] : {std::tuple{0.0f, 0.0f, 1.0f},
                                               {60.0f, 0.0f, 1.0f},
                                               {0.0f, -35.0f, 1.0f},
                                               {-20.0f, 40.0f, 1.0f},
                                               {0.0f, 0.0f, 0.35f}}) {
      OrbitCamera view = camera;
      view.yawDegrees = yaw;
      view.pitchDegrees = pitch;
      view.distance *= distance;
      const Image a = cpu.renderImage(view);
      const Image b = gl.renderImage(view);
      long differing = 0;
      for (std::size_t i = 0; i < a.pixels.size(); ++i) differing += a.pixels[i] != b.pixels[i] ? 1 : 0;
      EXPECT_EQ(differing, 0) << "jaw " << pose.jaw << ", smile " << pose.smile << ", head yaw " << pose.yaw
                              << ", gaze " << pose.gaze << ", lids " << pose.lids << "; view yaw " << yaw << ", pitch "
                              << pitch << ", distance x" << distance;
      ++cases;
    }
  }
  EXPECT_EQ(cases, 35);
  // It does drop something (else the comparison above would pass with nothing dropped): with the lips
  // together, most of the teeth and gums, and the eyeballs behind the lids.
  FaceRenderer backFacesOnly(context, face.mesh(), {.width = 480, .height = 360, .samples = 1});
  th::face::FapFrame closed{};
  cpu.setPositions(face.deform(closed));
  backFacesOnly.setPositions(face.deform(closed));
  cpu.render(camera);
  backFacesOnly.render(camera);
  EXPECT_LT(cpu.trianglesDrawn(), backFacesOnly.trianglesDrawn() - 4000)
      << cpu.trianglesDrawn() << " against " << backFacesOnly.trianglesDrawn();
}

// Nearly black pixels in the left and the right half of an image (the pupils are the darkest thing in view).
std::pair<long, long> darkPixels(const Image& image) {
  std::pair<long, long> count{0, 0};
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const std::uint8_t* p = image.pixel(x, y);
      if (p[0] + p[1] + p[2] < 30) (x < image.width / 2 ? count.first : count.second) += 1;
    }
  return count;
}

TEST(FaceRenderer, PupilsDilateOneEyeAtATime) {
  th::render::OffscreenContext context;
  FaceRenderer renderer(context, neutral(), {.width = 480, .height = 240, .samples = 1});
  // A close view of the eyes: the camera aimed between them, nearer than the whole-head framing.
  OrbitCamera camera = th::render::frameHead(neutral().positions, 2.0);
  const std::vector<th::render::EyeRig> eyes = th::render::findEyes(neutral(), th::render::classifySurfaces(neutral()));
  ASSERT_EQ(eyes.size(), 2u);
  camera.target = 0.5f * (eyes[0].centre + eyes[1].centre);
  camera.distance *= 0.3f;
  const auto rest = darkPixels(renderer.renderImage(camera));
  renderer.setPupilScale({1.6, 1.0});  // the face's left eye: the image's right
  const auto left = darkPixels(renderer.renderImage(camera));
  renderer.setPupilScale({1.0, 0.6});
  const Image constricted = renderer.renderImage(camera);
  snapshot(constricted, "pupil_right_0.6");
  const auto right = darkPixels(constricted);
  EXPECT_GT(rest.first, 20);
  EXPECT_GT(rest.second, 20);
  // A pupil is about 8 pixels across here: 1.6 times wider adds some 30 dark pixels, 0.6 times removes some
  // 30 (the rest of the count is the dark lid line, which does not change).
  EXPECT_GT(left.second, rest.second + 15);
  EXPECT_EQ(left.first, rest.first);
  EXPECT_LT(right.first, rest.first - 15);
  EXPECT_EQ(right.second, rest.second);
}

// The 16 x 16 window framebuffer of an OffscreenContext read back and compared with an image of the same size:
// the largest difference in any colour channel.
int largestDifferenceFromTheWindow(const Image& image) {
  std::vector<std::uint8_t> window(16 * 16 * 4);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, 16, 16, GL_RGBA, GL_UNSIGNED_BYTE, window.data());
  int largest = 0;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x)
      for (int k = 0; k < 3; ++k) {
        const int shown = window[static_cast<std::size_t>(((15 - y) * 16 + x) * 4 + k)];  // GL's rows bottom-up
        largest = std::max(largest, std::abs(shown - image.pixel(x, y)[k]));
      }
  return largest;
}

TEST(FaceRenderer, TheWindowAndTheReadBackShowTheSameBackdrop) {
  // OffscreenContext's own framebuffer is 16 x 16: present() into it and read it back.
  th::render::OffscreenContext context;
  FaceRenderer renderer(context, neutral(), {.width = 16, .height = 16, .samples = 1});
  renderer.render(th::render::frameHead(neutral().positions, 1.0));
  Image cpu;
  renderer.readPixels(cpu);  // composited on the CPU (the GL target keeps its transparent background)
  renderer.present({16, 16});
  EXPECT_LE(largestDifferenceFromTheWindow(cpu), 1);  // GL's 8-bit blending rounds once more
  EXPECT_GT(coverage(cpu).fraction, 0.1);             // the head is there, not only the backdrop
  EXPECT_LT(coverage(cpu).fraction, 0.9);
}

// Straight into the window (no target of its own, no copy): the same picture as render() + readPixels().
TEST(FaceRenderer, DrawingStraightIntoTheWindowShowsTheSamePicture) {
  th::render::OffscreenContext context;
  FaceRenderer renderer(context, neutral(), {.width = 16, .height = 16, .samples = 1});
  const th::render::OrbitCamera camera = th::render::frameHead(neutral().positions, 1.0);
  renderer.render(camera);
  Image cpu;
  renderer.readPixels(cpu);
  renderer.renderToWindow(camera);
  EXPECT_LE(largestDifferenceFromTheWindow(cpu), 2);  // 8-bit rounding of the blend, once or twice
  EXPECT_GT(coverage(cpu).fraction, 0.1);
  // The renderer's own target still holds its frame: reading it back gives the same image again.
  Image again;
  renderer.readPixels(again);
  EXPECT_TRUE(again == cpu);
}

// Beside a side panel: the picture starts `left` pixels in, the same picture as at the window's edge, and
// the columns beside it keep what was there.
TEST(FaceRenderer, DrawingIntoTheWindowBesideAPanelLeavesThePanelsColumns) {
  th::render::OffscreenContext context;
  FaceRenderer renderer(context, neutral(), {.width = 10, .height = 16, .samples = 1});
  const th::render::OrbitCamera camera = th::render::frameHead(neutral().positions, 10.0 / 16.0);
  renderer.render(camera);
  Image picture;
  renderer.readPixels(picture);
  ASSERT_GT(coverage(picture).fraction, 0.1);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, 16, 16);
  glClearColor(1.0f, 0.0f, 1.0f, 1.0f);  // magenta: what a panel left there
  glClear(GL_COLOR_BUFFER_BIT);
  renderer.renderToWindow(camera, 6);
  std::vector<std::uint8_t> window(16 * 16 * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, 16, 16, GL_RGBA, GL_UNSIGNED_BYTE, window.data());
  int largest = 0, panelKept = 0;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      const std::uint8_t* shown = &window[static_cast<std::size_t>(((15 - y) * 16 + x) * 4)];  // rows bottom-up
      if (x < 6) {
        panelKept += shown[0] == 255 && shown[1] == 0 && shown[2] == 255 ? 1 : 0;
        continue;
      }
      for (int k = 0; k < 3; ++k) largest = std::max(largest, std::abs(shown[k] - picture.pixel(x - 6, y)[k]));
    }
  EXPECT_EQ(panelKept, 6 * 16);
  EXPECT_LE(largest, 2);  // 8-bit rounding of the blend, as at the edge
}

TEST(Backdrop, CompositesUnderPremultipliedColour) {
  const std::vector<std::uint8_t> backdrop = th::render::backdropPixels(4, 3, {1.0f, 1.0f, 1.0f}, {0.0f, 0.0f, 0.0f});
  ASSERT_EQ(backdrop.size(), 4u * 3u * 3u);
  // Bottom row darker than the top, the middle of a row brighter than its ends (the pool of light).
  EXPECT_LT(backdrop[0], backdrop[2 * 12]);
  EXPECT_GT(backdrop[12 + 3], backdrop[12]);
  // Opaque stays, empty takes the backdrop, half-covered adds half of it.
  std::vector<std::uint8_t> rgba = {10, 20, 30, 255, 0, 0, 0, 0, 50, 60, 70, 128};
  const std::vector<std::uint8_t> under = {200, 200, 200, 90, 100, 110, 200, 100, 0};
  th::render::compositeUnder(rgba.data(), under.data(), 3);
  const std::vector<std::uint8_t> expected = {10, 20, 30, 255, 90, 100, 110, 255, 150, 110, 70, 255};
  EXPECT_EQ(rgba, expected);
}

TEST(Occlusion, TheCacheReturnsWhatWasMeasuredAndRemeasuresADamagedFile) {
  th::render::OffscreenContext context;
  const th::face::Mesh& mesh = neutral();
  Eigen::Matrix3Xf normals;
  th::render::VertexNormals(mesh).compute(mesh.positions, normals);
  const std::vector<int> groups(mesh.triangles.size(), 0);
  const std::vector<std::uint32_t> masks(static_cast<std::size_t>(mesh.numVertices()), 1U);
  const th::render::OcclusionOptions options{.directions = 12, .resolution = 128};
  const th::TemporaryFolder folder;
  const fs::path cache = folder.path() / "cache";
  const Eigen::VectorXf measured =
      th::render::computeOpenness(mesh.positions, normals, mesh.triangles, groups, masks, options);
  const auto cached = [&] {
    return th::render::computeOpennessCached(mesh.positions, normals, mesh.triangles, groups, masks, cache, options);
  };
  EXPECT_TRUE(cached().isApprox(measured, 0.0f));  // measured and written
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(cache)) files.push_back(entry.path());
  ASSERT_EQ(files.size(), 1u);
  const auto size = fs::file_size(files[0]);
  EXPECT_EQ(size, 16u + 4u * static_cast<std::uintmax_t>(mesh.numVertices()));
  {  // Read, not measured: a doctored file's values come back.
    std::fstream file(files[0], std::ios::in | std::ios::out | std::ios::binary);
    const float quarter = 0.25f;
    file.seekp(16);
    file.write(reinterpret_cast<const char*>(&quarter), sizeof quarter);
  }
  EXPECT_EQ(cached()[0], 0.25f);
  // Damaged (cut short): measured again and rewritten whole.
  fs::resize_file(files[0], size / 2);
  EXPECT_TRUE(cached().isApprox(measured, 0.0f));
  EXPECT_EQ(fs::file_size(files[0]), size);
  // Other options, another file.
  th::render::computeOpennessCached(mesh.positions, normals, mesh.triangles, groups, masks, cache,
                                    {.directions = 8, .resolution = 128});
  EXPECT_EQ(std::distance(fs::directory_iterator(cache), fs::directory_iterator{}), 2);
  // A cache folder that cannot exist (under a file) costs only the time.
  std::ofstream(folder.path() / "file") << "x";
  EXPECT_TRUE(th::render::computeOpennessCached(mesh.positions, normals, mesh.triangles, groups, masks,
                                                folder.path() / "file" / "cache", options)
                  .isApprox(measured, 0.0f));
}

// Sum of squared differences between neighbouring pixels: a hard (aliased) step counts more than the same
// step spread over two pixels.
double variation(const Image& image) {
  double sum = 0.0;
  for (int y = 0; y + 1 < image.height; ++y)
    for (int x = 0; x + 1 < image.width; ++x)
      for (int k = 0; k < 3; ++k) {
        const int p = image.pixel(x, y)[k];
        const int dx = p - image.pixel(x + 1, y)[k];
        const int dy = p - image.pixel(x, y + 1)[k];
        sum += dx * dx + dy * dy;
      }
  return sum;
}

TEST(FaceRenderer, FxaaSmoothsTheEdgesOfASingleSampleImage) {
  th::render::OffscreenContext context;
  const OrbitCamera camera = th::render::frameHead(neutral().positions, 320.0 / 240.0);
  FaceRenderer plain(context, neutral(), {.width = 320, .height = 240, .samples = 1});
  FaceRenderer smooth(context, neutral(), {.width = 320, .height = 240, .samples = 1, .fxaa = true});
  FaceRenderer msaa(context, neutral(), {.width = 320, .height = 240, .samples = 4});
  const Image a = plain.renderImage(camera);
  const Image b = smooth.renderImage(camera);
  const Image c = msaa.renderImage(camera);
  snapshot(b, "fxaa_320x240");
  EXPECT_LT(variation(b), 0.9 * variation(a));
  EXPECT_LT(variation(c), 0.9 * variation(a));
  // Only edges change: the picture as a whole stays the same.
  EXPECT_NEAR(coverage(b).fraction, coverage(a).fraction, 0.01);
  long changed = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) changed += a.pixels[i] != b.pixels[i] ? 1 : 0;
  EXPECT_LT(static_cast<double>(changed) / static_cast<double>(a.pixels.size()), 0.2);
}

TEST(Fxaa, BlendsHardEdgesOnlyAndFlipsRows) {
  // GL's orientation: row 0 is the bottom. Left of a slanted edge black, right of it white; a flat grey band
  // along the top.
  const int w = 16;
  const int h = 12;
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(w * h * 4), 255);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = rgba.data() + (y * w + x) * 4;
      const std::uint8_t v = y >= 9 ? 128 : (2 * x < y + 8 ? 0 : 255);
      p[0] = p[1] = p[2] = v;
    }
  Image plain;
  th::render::copyToImage(rgba.data(), w, h, plain);
  EXPECT_EQ(plain.pixel(0, 0)[0], 128);  // the top row of the image is GL's last row
  EXPECT_EQ(plain.pixel(0, h - 1)[0], 0);
  Image smooth;
  th::render::FxaaScratch scratch;
  th::render::fxaaInPlace(rgba.data(), w, h, scratch);
  th::render::copyToImage(rgba.data(), w, h, smooth);
  int between = 0;
  for (int y = 4; y < h - 1; ++y)
    for (int x = 1; x < w - 1; ++x) {
      const int v = smooth.pixel(x, y)[0];
      between += v > 20 && v < 235 ? 1 : 0;
      EXPECT_EQ(smooth.pixel(x, y)[0], smooth.pixel(x, y)[2]);  // grey stays grey
    }
  EXPECT_GE(between, 6);                    // the staircase got intermediate tones
  EXPECT_EQ(smooth.pixel(8, 1)[0], 128);    // the flat band is untouched
  EXPECT_EQ(smooth.pixel(1, h - 2)[0], 0);  // far from the edge: as it was
  EXPECT_EQ(smooth.pixel(w - 2, h - 2)[0], 255);
}

// ---- Y'CbCr ----

// The frame converted by libswscale as formats::Mp4Writer converts RGB frames (same matrix, same range).
th::render::Yuv420Image swscaleYuv(const std::vector<std::uint8_t>& rgba, int w, int h, bool bt709) {
  SwsContext* context =
      sws_getContext(w, h, AV_PIX_FMT_RGBA, w, h, AV_PIX_FMT_YUV420P, SWS_BILINEAR, nullptr, nullptr, nullptr);
  const int* matrix = sws_getCoefficients(bt709 ? SWS_CS_ITU709 : SWS_CS_SMPTE170M);
  sws_setColorspaceDetails(context, matrix, 1, matrix, 0, 0, 1 << 16, 1 << 16);
  th::render::Yuv420Image out;
  out.width = w;
  out.height = h;
  out.y.resize(static_cast<std::size_t>(w * h));
  out.cb.resize(static_cast<std::size_t>((w / 2) * (h / 2)));
  out.cr.resize(out.cb.size());
  // GL's rows bottom-up: start at the last row with a negative stride.
  const std::uint8_t* source[] = {rgba.data() + static_cast<std::size_t>((h - 1) * w * 4)};
  const int sourceStride[] = {-w * 4};
  std::uint8_t* planes[] = {out.y.data(), out.cb.data(), out.cr.data()};
  const int strides[] = {w, w / 2, w / 2};
  sws_scale(context, source, sourceStride, 0, h, planes, strides);
  sws_freeContext(context);
  return out;
}

TEST(Yuv420, MatchesLibswscaleOnARenderedFrame) {
  // A real frame (skin, eyes, backdrop, edges) and a pattern of saturated colours.
  th::render::OffscreenContext context;
  // The whole frame in the read-back, not only the head's region.
  FaceRenderer renderer(context, neutral(),
                        {.width = 320, .height = 240, .samples = 1, .fxaa = true, .cropToHead = false});
  renderer.render(th::render::frameHead(neutral().positions, 320.0 / 240.0));
  th::render::RawFrame frame;
  renderer.readRaw(frame);
  th::render::Yuv420Image ours;
  renderer.finish(frame, ours, true);  // frame.rgba now holds the finished RGBA
  // Saturated gradients across the whole colour cube (smooth: libswscale's chroma filter reaches into the
  // neighbouring blocks, ours averages each block, and the two agree only where colour varies smoothly).
  std::vector<std::uint8_t> colours(64 * 32 * 4, 255);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x) {
      std::uint8_t* p = colours.data() + (y * 64 + x) * 4;
      p[0] = static_cast<std::uint8_t>(x * 4);
      p[1] = static_cast<std::uint8_t>(y * 8);
      p[2] = static_cast<std::uint8_t>(255 - 2 * (x + y));
    }
  for (const bool bt709 : {true, false}) {
    for (const auto& [rgba, w, h] : {std::tuple{frame.rgba, 320, 240}, std::tuple{colours, 64, 32}}) {
      th::render::Yuv420Image mine;
      th::render::rgbaToYuv420(rgba.data(), w, h, bt709, mine);
      const th::render::Yuv420Image reference = swscaleYuv(rgba, w, h, bt709);
      const auto largest = [](const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
        int m = 0;
        for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(a[i] - b[i]));
        return m;
      };
      const auto mean = [](const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
        double sum = 0.0;
        for (std::size_t i = 0; i < a.size(); ++i) sum += std::abs(a[i] - b[i]);
        return sum / static_cast<double>(a.size());
      };
      const std::string what = std::string(bt709 ? "BT.709 " : "BT.601 ") + std::to_string(w) + "x" + std::to_string(h);
      // The same matrix and range: luma within libswscale's rounding. Chroma: libswscale's filter reaches a
      // little into the neighbouring blocks, so across the head's sharp edges a few levels apart, and on
      // average a fraction of one.
      EXPECT_LE(largest(mine.y, reference.y), 1) << what;
      EXPECT_LE(largest(mine.cb, reference.cb), 3) << what;
      EXPECT_LE(largest(mine.cr, reference.cr), 3) << what;
      EXPECT_LT(mean(mine.cb, reference.cb), 0.5) << what;
      EXPECT_LT(mean(mine.cr, reference.cr), 0.5) << what;
    }
  }
  // Limited range: black and white land on 16 and 235.
  std::vector<std::uint8_t> blackWhite = {0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255, 255, 255, 255, 255, 255};
  th::render::Yuv420Image bw;
  th::render::rgbaToYuv420(blackWhite.data(), 2, 2, true, bw);
  EXPECT_EQ(bw.y, (std::vector<std::uint8_t>{235, 235, 16, 16}));  // GL's bottom row (black) is the image's last
  EXPECT_EQ(bw.cb[0], 128);
  EXPECT_EQ(bw.cr[0], 128);
  // A block converted into its place in a larger image is that image's conversion there; the block must cover
  // whole 2 x 2 chroma blocks.
  th::render::Yuv420Image whole;
  th::render::rgbaToYuv420(colours.data(), 64, 32, true, whole);
  th::render::Yuv420Image pieced = whole;
  std::fill(pieced.y.begin(), pieced.y.end(), 0);
  std::fill(pieced.cb.begin(), pieced.cb.end(), 0);
  std::fill(pieced.cr.begin(), pieced.cr.end(), 0);
  // Rows 0-19 (top-down) are GL's rows 12-31: the upper block; rows 20-31 the lower, columns in two halves.
  const auto block = [&](int left, int top, int w, int h) {
    std::vector<std::uint8_t> part(static_cast<std::size_t>(w * h * 4));
    for (int y = 0; y < h; ++y)  // GL's row y of the block is the image's row top + h - 1 - y
      std::copy_n(colours.data() + ((32 - top - h + y) * 64 + left) * 4, w * 4, part.data() + y * w * 4);
    th::render::rgbaToYuv420(part.data(), w, h, true, pieced, left, top);
  };
  block(0, 0, 64, 20);
  block(0, 20, 32, 12);
  block(32, 20, 32, 12);
  EXPECT_EQ(pieced.y, whole.y);
  EXPECT_EQ(pieced.cb, whole.cb);
  EXPECT_EQ(pieced.cr, whole.cr);
  EXPECT_THROW(block(1, 0, 32, 12), th::Error);    // an odd column
  EXPECT_THROW(block(0, 20, 31, 12), th::Error);   // ends mid-block
  EXPECT_THROW(block(40, 20, 32, 12), th::Error);  // beyond the image
}

// ---- normals ----

// A square pyramid without a base, apex up (+z), 5 vertices.
// `height`: the apex's; `stretch`: scales x; `corner`: the x of the base corner (1, 1) before stretching.
Eigen::Matrix3Xd pyramidPositions(double height, double stretch, double corner) {
  Eigen::Matrix3Xd p(3, 5);
  p.col(0) << 0, 0, height;  // apex
  p.col(1) << corner * stretch, 1, 0;
  p.col(2) << -stretch, 1, 0;
  p.col(3) << -stretch, -1, 0;
  p.col(4) << stretch, -1, 0;
  return p;
}

th::face::Mesh pyramid() {
  th::face::Mesh mesh;
  mesh.positions = pyramidPositions(1.0, 1.0, 1.0);
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1}};
  mesh.triangleMaterial = {0, 0, 0, 0};
  mesh.materials = {th::face::Material{.name = "M"}};
  return mesh;
}

TEST(VertexNormals, AreaWeightedSmoothNormalsFollowTheDeformation) {
  const th::face::Mesh mesh = pyramid();
  const th::render::VertexNormals solver(mesh);
  EXPECT_EQ(solver.numWelded(), 0);
  Eigen::Matrix3Xf n;
  solver.compute(mesh.positions, n);
  EXPECT_TRUE(n.col(0).isApprox(Eigen::Vector3f::UnitZ(), 1e-6f));  // the apex, by symmetry
  // A base corner: mean of its two faces' normals, (1,0,1)/sqrt2 and (0,1,1)/sqrt2 for corner (1,1).
  EXPECT_TRUE(n.col(1).isApprox(Eigen::Vector3f(1, 1, 2).normalized(), 1e-5f));

  // Deform: raise the apex and stretch in x. Normals must be recomputed from the new positions.
  Eigen::Matrix3Xd moved = pyramidPositions(3.0, 2.0, 1.0);
  solver.compute(moved, n);
  // Check against the area-weighted sum of the faces' normals, computed directly.
  for (int v = 0; v < 5; ++v) {
    Eigen::Vector3d expected = Eigen::Vector3d::Zero();
    for (const auto& t : mesh.triangles)
      if (t[0] == v || t[1] == v || t[2] == v)
        expected += (moved.col(t[1]) - moved.col(t[0])).cross(moved.col(t[2]) - moved.col(t[0]));
    EXPECT_TRUE(n.col(v).isApprox(expected.normalized().cast<float>(), 1e-5f)) << v;
  }
  // Area weighting: round the apex, the faces' cross products add up to twice the base's vector area, so with
  // a flat base the apex normal stays perpendicular to it however unevenly the base is stretched. A plain
  // mean of the faces' unit normals would lean.
  moved = pyramidPositions(1.0, 1.0, 6.0);
  solver.compute(moved, n);
  EXPECT_TRUE(n.col(0).isApprox(Eigen::Vector3f::UnitZ(), 1e-5f));
  Eigen::Vector3d unweighted = Eigen::Vector3d::Zero();
  for (const auto& t : mesh.triangles)
    unweighted += (moved.col(t[1]) - moved.col(t[0])).cross(moved.col(t[2]) - moved.col(t[0])).normalized();
  EXPECT_GT(std::abs(unweighted.normalized().x()), 0.05);
  for (int v = 0; v < 5; ++v) EXPECT_NEAR(n.col(v).norm(), 1.0f, 1e-5f);
}

TEST(VertexNormals, CoincidentSeamVerticesOfOneMaterialShareANormal) {
  // Two triangles folded along the y axis, their shared edge split into two copies each (a UV seam).
  th::face::Mesh mesh;
  mesh.positions.resize(3, 6);
  mesh.positions.col(0) << 0, 0, 0;
  mesh.positions.col(1) << 0, 1, 0;
  mesh.positions.col(2) << -1, 0, 1;  // left wing, tilted
  mesh.positions.col(3) << 0, 0, 0;   // copy of 0
  mesh.positions.col(4) << 1, 0, 1;   // right wing
  mesh.positions.col(5) << 0, 1, 0;   // copy of 1
  mesh.triangles = {{0, 1, 2}, {3, 4, 5}};
  mesh.triangleMaterial = {0, 0};
  mesh.materials = {th::face::Material{.name = "M"}};
  const th::render::VertexNormals welded(mesh);
  EXPECT_EQ(welded.numWelded(), 2);
  Eigen::Matrix3Xf n;
  welded.compute(mesh.positions, n);
  EXPECT_TRUE(n.col(0).isApprox(n.col(3)));
  EXPECT_TRUE(n.col(1).isApprox(n.col(5)));
  // Without welding, the copies would keep their own wing's normal: a crease.
  const th::render::VertexNormals plain(6, mesh.triangles);
  Eigen::Matrix3Xf m;
  plain.compute(mesh.positions, m);
  EXPECT_LT(m.col(0).dot(m.col(3)), 0.5f);
  // Different materials are not welded.
  mesh.triangleMaterial = {0, 1};
  mesh.materials.push_back(th::face::Material{.name = "N"});
  EXPECT_EQ(th::render::VertexNormals(mesh).numWelded(), 0);
}

TEST(VertexNormals, IctHeadHasNoCreasesAtItsSeams) {
  const th::render::VertexNormals solver(neutral());
  // ICT FaceKit's positions have no UV seams; only its eyelash cards have coincident copies.
  EXPECT_GT(solver.numWelded(), 0);
  EXPECT_LT(solver.numWelded(), 300);
  Eigen::Matrix3Xf n;
  solver.compute(neutral().positions, n);
  // The tip of the nose (the frontmost face vertex) faces the viewer.
  Eigen::Index tip = 0;
  neutral().positions.row(2).maxCoeff(&tip);
  EXPECT_GT(n(2, tip), 0.8f);
}

// ---- images ----

TEST(Png, RoundTripAndErrors) {
  Image image(5, 3);
  for (std::size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = static_cast<std::uint8_t>(i * 17);
  const fs::path dir = fs::temp_directory_path() / ("th_render_png_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path file = dir / "small.png";
  th::render::writePng(file, image);
  EXPECT_TRUE(image == th::render::readPng(file));

  const fs::path impossible = dir / "no_such_folder" / "x.png";
  try {
    th::render::writePng(impossible, image);
    ADD_FAILURE() << "no error";
  } catch (const th::Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(impossible.string()), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  EXPECT_FALSE(fs::exists(impossible));
  EXPECT_FALSE(fs::exists(impossible.parent_path()));

  // Reading: a missing file, and a file that is not a PNG, each name the file.
  EXPECT_THROW(th::render::readPng(dir / "missing.png"), th::Error);
  { std::ofstream(dir / "text.png") << "not a png"; }
  try {
    th::render::readPng(dir / "text.png");
    ADD_FAILURE() << "no error";
  } catch (const th::Error& e) {
    EXPECT_NE(std::string(e.what()).find("text.png"), std::string::npos);
  }
  EXPECT_THROW(th::render::writePng(dir / "empty.png", Image{}), th::Error);
  fs::remove_all(dir);
  // Nothing but the target is written: no temporary files left next to it (checked by the folder's removal).
}

// ---- window ----

TEST(WindowContext, WithoutADisplayIsAClearError) {
  const char* display = std::getenv("DISPLAY");
  const std::string saved = display != nullptr ? display : "";
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  const std::string savedWayland = wayland != nullptr ? wayland : "";
  ::unsetenv("DISPLAY");
  ::unsetenv("WAYLAND_DISPLAY");
  try {
    th::render::WindowContext window;
    ADD_FAILURE() << "a window without a display";
  } catch (const th::Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("display"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  // A display that does not exist: GLFW's own failure, also a th::Error.
  ::setenv("DISPLAY", ":987", 1);
  EXPECT_THROW(th::render::WindowContext window, th::Error);
  if (!saved.empty())
    ::setenv("DISPLAY", saved.c_str(), 1);
  else
    ::unsetenv("DISPLAY");
  if (!savedWayland.empty()) ::setenv("WAYLAND_DISPLAY", savedWayland.c_str(), 1);
}

}  // namespace
