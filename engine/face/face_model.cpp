#include "face/face_model.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>

#include "core/error.h"
#include "face/fap.h"
#include "face/rig.h"
#include "face/rig_ears.h"
#include "face/rig_jaw.h"
#include "face/rig_lattice.h"
#include "face/rig_lids_and_eyes.h"
#include "face/rig_neck.h"
#include "face/rig_points.h"
#include "face/rig_tongue.h"

namespace th::face {

Eigen::Matrix3d headRotation(double pitch, double yaw, double roll) {
  // As the head model's angles: R = Ry(yaw)·Rx(pitch)·Rz(roll); FAP 48 positive pitches down about +x, 49 yaws
  // to the face's left about +y, 50 rolls to its right about +z (face/fap.cpp).
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitX()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()))
      .toRotationMatrix();
}

FaceModel FaceModel::buildDefault() {
  return build(loadIctFace(ictFaceDirectory()));
}

// The rig's parts (rig_*.h), each built from the neutral face and from what the parts before it found: the jaw's
// shares tell the lips and the tongue apart, and the feature points a part places are there for those after it.
FaceModel FaceModel::build(const FaceAssets& assets, const FaceModelOptions& options) {
  FaceModel model;
  model.mesh_ = assets.neutral;
  model.points_ = assets.points;
  model.landmarks_ = assets.landmarks;
  model.units_ = measureFapUnits(model.points_, model.mesh_.positions);
  const rig::NeutralFace neutral = rig::neutralFace(model.mesh_, model.units_);
  rig::placeDerivedPoints(neutral, model.points_);

  rig::JawRig jaw = rig::rigJaw(neutral, model.points_, assets.jawOpen);
  model.jaw_ = jaw.hinge;
  model.jawFollow_ = std::move(jaw.follow);
  model.jawVertices_ = std::move(jaw.vertices);
  model.chinFollow_ = jaw.chinFollow;

  rig::SkinLattice skin = rig::embedSkin(neutral, options.lattice);
  rig::LinearFields fields;
  rig::addLatticeFields(neutral, model.points_, skin, model.jawFollow_, options.lattice, fields);
  rig::addEarFields(neutral, model.points_, fields);
  rig::TongueRoll tongueRoll = rig::rigTongue(neutral, model.points_, model.jawFollow_, fields);
  model.lattice_ = std::move(skin.lattice);
  model.embedding_ = std::move(skin.embedding);
  model.linear_ = std::move(fields.entries);
  model.reach_ = fields.reach;
  model.tongueRoll_ = std::move(tongueRoll.shares);
  model.tongueAxisY_ = tongueRoll.axisY;

  std::array<rig::EyeRig, 2> eyes = rig::rigEyes(neutral, model.points_);
  for (std::size_t e = 0; e < eyes.size(); ++e)
    model.eyes_[e] = {eyes[e].centre, eyes[e].radius, std::move(eyes[e].ball), std::move(eyes[e].upperLid),
                      std::move(eyes[e].lowerLid)};
  model.pupilRadius_ = rig::pupilRadius(neutral);

  rig::NeckRig neck = rig::rigNeck(neutral, model.points_, model.jaw_);
  model.neckPivot_ = neck.pivot;
  model.headShare_ = std::move(neck.headShare);
  return model;
}

std::vector<int> FaceModel::innerLipVertices() const {
  std::vector<int> vertices;
  for (const char* id : {"2.2", "2.3", "2.4", "2.5", "2.6", "2.7", "2.8", "2.9"})
    for (int v : points_.vertices(id)) vertices.push_back(v);
  return vertices;
}

std::vector<int> FaceModel::eyeLidVertices(int side) const {
  std::vector<int> vertices;
  const auto ids = side == 0 ? std::array{"3.1", "3.3", "3.7", "3.11"} : std::array{"3.2", "3.4", "3.8", "3.12"};
  for (const char* id : ids)
    for (int v : points_.vertices(id)) vertices.push_back(v);
  return vertices;
}

bool FaceModel::supports(int fap) const {
  if (fap < 1 || fap > kNumFaps) return false;
  if (!linear_[static_cast<std::size_t>(fap)].empty()) return true;
  return fap == 3 || fap == 14 || fap == 15 || (fap >= 19 && fap <= 30) || (fap == 47 && !tongueRoll_.empty()) ||
         (fap >= 48 && fap <= 50);
}

double FaceModel::jawAngleFor(double openJaw) const {
  if (openJaw <= 0.0) return 0.0;  // unidirectional: the jaw does not close past rest
  const double target = std::max(0.0, openJaw) * units_.mns;
  const Eigen::Vector3d chin = points_.position(mesh_.positions, "2.1");
  const auto drop = [&](double angle) { return chinFollow_ * (chin.y() - jaw_.rotate(chin, angle).y()); };
  // The drop grows with the angle up to where the chin passes below the hinge; bisect within that.
  double low = 0.0, high = std::numbers::pi / 3;
  if (target >= drop(high)) return high;
  for (int i = 0; i < 60; ++i) {
    const double middle = 0.5 * (low + high);
    (drop(middle) < target ? low : high) = middle;
  }
  return 0.5 * (low + high);
}

std::array<double, 2> FaceModel::pupilScale(const FapFrame& faps) const {
  return {std::max(0.1, 1.0 + faps[29] * units_.irisd / pupilRadius_),
          std::max(0.1, 1.0 + faps[30] * units_.irisd / pupilRadius_)};
}

Eigen::Matrix3Xd FaceModel::deform(const FapFrame& faps) const {
  return deformSelected(faps, nullptr);
}

Eigen::Matrix3Xd FaceModel::deform(const FapFrame& faps, const VertexSelection& selection) const {
  if (selection.columnOf.size() != static_cast<std::size_t>(mesh_.numVertices()) ||
      selection.fields.size() != linear_.size())
    throw Error("FaceModel::deform: the selection was made for another mesh");
  return deformSelected(faps, &selection);
}

namespace {

// The vertex of an entry of a rig list: a vertex, or a vertex and its share.
int vertexOfEntry(int vertex) {
  return vertex;
}
int vertexOfEntry(const std::pair<int, float>& entry) {
  return entry.first;
}

// Calls turn(column, entry) for each entry of a rig list whose vertex is deformed: all of them (a vertex is its own
// column) without a selection, the selection's `chosen` ones with it.
template <class List, class Turn>
void forEachDeformed(const List& list, const std::vector<VertexSelection::RigEntry>* chosen, Turn turn) {
  if (chosen) {
    for (const VertexSelection::RigEntry& entry : *chosen)
      turn(entry.column, list[static_cast<std::size_t>(entry.index)]);
  } else {
    for (const auto& entry : list) turn(vertexOfEntry(entry), entry);
  }
}

}  // namespace

VertexSelection FaceModel::select(const std::vector<int>& vertices) const {
  VertexSelection selection;
  selection.vertices = vertices;
  selection.columnOf.assign(static_cast<std::size_t>(mesh_.numVertices()), -1);
  for (std::size_t c = 0; c < vertices.size(); ++c) {
    if (vertices[c] < 0 || vertices[c] >= mesh_.numVertices())
      throw Error("FaceModel::select: vertex " + std::to_string(vertices[c]) + " is not in the mesh");
    int& column = selection.columnOf[static_cast<std::size_t>(vertices[c])];
    if (column < 0) column = static_cast<int>(c);  // a vertex chosen twice is deformed once (the first column)
  }
  selection.fields.resize(linear_.size());
  for (std::size_t fap = 0; fap < linear_.size(); ++fap)
    for (const FieldEntry& entry : linear_[fap])
      if (const int c = selection.columnOf[static_cast<std::size_t>(entry.vertex)]; c >= 0)
        selection.fields[fap].push_back({c, entry.displacement});
  const auto chosen = [&](const auto& list) {
    std::vector<VertexSelection::RigEntry> entries;
    for (std::size_t i = 0; i < list.size(); ++i)
      if (const int c = selection.columnOf[static_cast<std::size_t>(vertexOfEntry(list[i]))]; c >= 0)
        entries.push_back({c, static_cast<int>(i)});
    return entries;
  };
  selection.tongue = chosen(tongueRoll_);
  selection.jaw = chosen(jawVertices_);
  for (std::size_t e = 0; e < eyes_.size(); ++e) {
    selection.upperLid[e] = chosen(eyes_[e].upperLid);
    selection.lowerLid[e] = chosen(eyes_[e].lowerLid);
    selection.ball[e] = chosen(eyes_[e].ball);
  }
  return selection;
}

// Each eye's lids closed about its centre by FAPs 19–22, its ball turned by 23–26 and thrust by 27–28.
void FaceModel::closeLidsAndTurnEyes(const FapFrame& faps, const VertexSelection* selection,
                                     Eigen::Matrix3Xd& v) const {
  const Eigen::Matrix3Xd& rest = mesh_.positions;
  for (int e = 0; e < 2; ++e) {
    const Eye& eye = eyes_[static_cast<std::size_t>(e)];
    const bool left = e == 0;
    const double closeUpper = faps[left ? 19 : 20], closeLower = faps[left ? 21 : 22];
    const auto lidAngle = [&](std::string_view point, double drop) {
      // The angle about the eye's x axis that moves the lid's middle vertically by `drop` (down positive).
      const Eigen::Vector3d p = points_.position(rest, point) - eye.centre;
      const double radius = std::hypot(p.y(), p.z());
      const double elevation = std::atan2(p.y(), p.z());
      const double target = std::clamp((p.y() - drop) / radius, -1.0, 1.0);
      return elevation - std::asin(target);  // positive turns the front downwards (about +x)
    };
    if (closeUpper != 0.0) {
      const double turn = lidAngle(left ? "3.1" : "3.2", closeUpper * units_.irisd);
      forEachDeformed(
          eye.upperLid, selection ? &selection->upperLid[e] : nullptr, [&](int c, const std::pair<int, float>& entry) {
            v.col(c) =
                eye.centre + Eigen::AngleAxisd(entry.second * turn, Eigen::Vector3d::UnitX()) * (v.col(c) - eye.centre);
          });
    }
    if (closeLower != 0.0) {
      const double turn = lidAngle(left ? "3.3" : "3.4", -closeLower * units_.irisd);
      forEachDeformed(
          eye.lowerLid, selection ? &selection->lowerLid[e] : nullptr, [&](int c, const std::pair<int, float>& entry) {
            v.col(c) =
                eye.centre + Eigen::AngleAxisd(entry.second * turn, Eigen::Vector3d::UnitX()) * (v.col(c) - eye.centre);
          });
    }
    const double yaw = faps[left ? 23 : 24] * kAngleUnit, pitch = faps[left ? 25 : 26] * kAngleUnit;
    const double thrust = faps[left ? 27 : 28] * units_.es;
    if (yaw != 0.0 || pitch != 0.0 || thrust != 0.0) {
      const Eigen::Matrix3d turn =
          (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitX()))
              .toRotationMatrix();
      forEachDeformed(eye.ball, selection ? &selection->ball[e] : nullptr, [&](int c, int) {
        v.col(c) = eye.centre + turn * (v.col(c) - eye.centre) + thrust * Eigen::Vector3d::UnitZ();
      });
    }
  }
}

Eigen::Matrix3Xd FaceModel::deformSelected(const FapFrame& faps, const VertexSelection* selection) const {
  // The column of a mesh vertex in `v` (-1: not deformed here), and the mesh vertex of a column.
  const auto columnOf = [&](int vertex) {
    return selection ? selection->columnOf[static_cast<std::size_t>(vertex)] : vertex;
  };
  const auto vertexOf = [&](Eigen::Index column) {
    return selection ? selection->vertices[static_cast<std::size_t>(column)] : static_cast<int>(column);
  };
  Eigen::Matrix3Xd v;
  if (selection) {
    v.resize(3, static_cast<Eigen::Index>(selection->vertices.size()));
    for (Eigen::Index c = 0; c < v.cols(); ++c) v.col(c) = mesh_.positions.col(vertexOf(c));
  } else {
    v = mesh_.positions;
  }
  for (int fap = 1; fap <= kNumFaps; ++fap) {
    const double value = faps[static_cast<std::size_t>(fap)];
    if (value == 0.0) continue;
    if (selection) {
      for (const VertexSelection::FieldEntry& entry : selection->fields[static_cast<std::size_t>(fap)])
        v.col(entry.column) += value * entry.displacement.cast<double>();
    } else {
      for (const FieldEntry& entry : linear_[static_cast<std::size_t>(fap)])
        v.col(entry.vertex) += value * entry.displacement.cast<double>();
    }
  }

  // Tongue roll (unidirectional: the sides curl up): each side turns about the mid-line's axis, the face's left
  // (+x) counter-clockwise seen from the front, its right clockwise, so both borders rise.
  const double tongueRoll = std::max(0.0, faps[47]) * kAngleUnit;
  if (tongueRoll != 0.0) {
    forEachDeformed(tongueRoll_, selection ? &selection->tongue : nullptr,
                    [&](int column, const std::pair<int, float>& entry) {
                      const double a = entry.second * tongueRoll, c = std::cos(a), s = std::sin(a);
                      const double x = v(0, column), y = v(1, column) - tongueAxisY_;
                      v(0, column) = c * x - s * y;
                      v(1, column) = tongueAxisY_ + s * x + c * y;
                    });
  }

  // Jaw: each vertex turns by its share of the angle and slides by its share of the thrust and shift. The
  // slide is scaled so that the chin point, whose share is chinFollow_, moves by exactly value × FAPU.
  const double angle = jawAngleFor(faps[3]);
  const Eigen::Vector3d slide = (std::max(0.0, faps[14]) * units_.mns * Eigen::Vector3d::UnitZ() +
                                 faps[15] * units_.mw * -Eigen::Vector3d::UnitX()) /
                                chinFollow_;
  if (angle != 0.0 || slide.squaredNorm() > 0.0) {
    forEachDeformed(jawVertices_, selection ? &selection->jaw : nullptr, [&](int column, int vertex) {
      const double share = jawFollow_[vertex];
      v.col(column) =
          jaw_.pivot + Eigen::AngleAxisd(share * angle, jaw_.axis) * (v.col(column) - jaw_.pivot) + share * slide;
    });
  }

  closeLidsAndTurnEyes(faps, selection, v);

  // Head.
  const double pitch = faps[48] * kAngleUnit, yaw = faps[49] * kAngleUnit, roll = faps[50] * kAngleUnit;
  if (pitch != 0.0 || yaw != 0.0 || roll != 0.0) {
    const Eigen::Matrix3d full = headRotation(pitch, yaw, roll);
    for (Eigen::Index column = 0; column < v.cols(); ++column) {
      const float share = headShare_[static_cast<std::size_t>(vertexOf(column))];
      if (share <= 0.0f) continue;
      const Eigen::Matrix3d turn = share >= 1.0f ? full : headRotation(share * pitch, share * yaw, share * roll);
      v.col(column) = neckPivot_ + turn * (v.col(column) - neckPivot_);
    }
  }
  // A vertex chosen twice was deformed in one column (columnOf holds one); the others take it from there.
  if (selection)
    for (Eigen::Index c = 0; c < v.cols(); ++c)
      if (const int first = columnOf(vertexOf(c)); first != c) v.col(c) = v.col(first);
  return v;
}

}  // namespace th::face
