// The animated face: the reference head's mesh deformed by MPEG-4 FAP values and turned by the head FAPs.
//
//   th::face::FaceModel face = th::face::FaceModel::buildDefault();   // ICT FaceKit's head, from assets/
//   th::face::FapFrame faps{};                 // index = FAP number (1..68), values in FAPU counts
//   faps[3] = 400;                              // open the jaw: the chin drops 400 MNS
//   faps[49] = 20 * std::numbers::pi / 180 / 1e-5;   // turn the head 20° to its left
//   Eigen::Matrix3Xd positions = face.deform(faps);  // 3 x V, the mesh's vertex order
//
// How each FAP moves the mesh (fields built once, from the neutral mesh, its feature points and its jawOpen
// shape; every field is normalised so that the feature point the standard names moves by exactly
// value × FAPU in the standard's direction):
// - Linear FAPs through the lattice (lips 4–13, 16, 17, 51–60; chin 18; brows 31–38; cheeks 39–42; nose
//   61–64): piecewise Bézier volume deformation (bezier_volume.h). FAP k displaces the lattice's control points by D_k, a Gaussian
//   fall-off around its feature point times its direction, so the skin moves by B·D_k: smooth, and zero far
//   away. The brow raisers (31–36) differ: the three of a side share its brow line (each is 1 at its own point
//   and 0 at its neighbours', so raising all six lifts every brow point by exactly the value), fade linearly
//   up the forehead to the lattice's top, and turn into the skin's tangent plane above the brow, so a large
//   raise slides the forehead over the skull instead of bulging it out. A per-vertex mask confines each field to the skin of its own side and lip (the upper and lower lip
//   touch at rest, so no smooth field alone could move one without the other): the lips are told apart by how
//   far the jaw carries each vertex (jaw.h).
// - The jaw (FAP 3) is a hinge (jaw.h): every vertex turns about it by its share of the angle (lower teeth
//   and tongue fully, chin and lower lip mostly, the upper lip hardly); the angle is the one that drops the
//   chin point by value × MNS. FAPs 14 and 15 move the same vertices by the same shares, straight forward or
//   sideways. A rotation, because a jaw turns: a linear field would stretch the teeth.
// - Eyelids (19–22) turn about the eyeball's centre (a sphere fitted to the sclera), so the lid slides over the
//   eye instead of cutting into it; a value of 1024 (one IRISD) brings the upper lid's middle down onto the
//   lower lid's. Eyeballs (23–26) turn rigidly about the same centres; 27/28 push them forward; 29/30 (pupil
//   size) are passed to the renderer (pupilScale).
// - The head (48–50) turns rigidly about a neck pivot, blended into the neck so the base of the neck stays.
// - Ears (65–68; points 10.1/10.2 the top of each auricle, its highest fully moving vertex; 10.3/10.4 its
//   outermost point, the back of the helix's rim): a direct per-vertex field, not through the lattice (the
//   auricles are M_Face skin inside it, but in its outermost cells, too coarse to move an ear without the side
//   of the head). The side of the head around the ear is fitted as a quadratic height field (trimmed least
//   squares, so the ear itself is left out); a vertex's weight grows with how far it stands out of it, 1 on the
//   auricle and 0 on the head, so raising or pulling moves the whole auricle, fading into the crease where it
//   joins the head; the face and the other ear do not move.
// - Tongue (43–46 linear, 47 roll; 6.1 the tip, the front-most mid-line vertex; 6.2 the top of its body; 6.3/6.4
//   its left and right borders): ICT draws gums and tongue as one connected surface (M_GumsTongue, 2977
//   vertices), so the tongue is told apart geometrically: the jaw-carried part grown from the top of the tongue
//   down to the lowest level at which it does not yet reach the lower gums' front (the fold where its underside
//   meets the floor of the mouth; 322 vertices). Direct per-vertex fields move the tip region (43–45; fading out
//   over the tongue's middle) or the body (46; fading out towards the root) and fade to 0 at the fold; the roll
//   turns each side about the mid-line's axis by a share growing from 0 on the mid-line to 1 at the borders.
//   They act before the jaw, so the tongue rides on it.
// Order: linear fields (ears and tongue included), tongue roll, then jaw, then eyelids and eyeballs, then the
// head, so lip and tongue FAPs ride on the jaw. The high-level FAPs 1–2 (visemes, expressions) are not the face
// model's and are ignored; `supports` says which FAPs are shown (all of 3–68).
// Thread contract: a FaceModel is immutable after build(); deform() is const and safe from any thread.
#pragma once

#include <Eigen/Core>
#include <array>
#include <memory>
#include <vector>

#include "face/bezier_volume.h"
#include "face/fap.h"
#include "face/feature_points.h"
#include "face/jaw.h"
#include "face/mesh.h"

namespace th::face {

struct FaceModelOptions {
  BezierLatticeOptions lattice{.volumes = {12, 15, 4}, .degree = 3, .bend = 0.04};
};

// The head's turn for FAPs 48-50 in radians (pitch, yaw, roll): R = Ry(yaw)·Rx(pitch)·Rz(roll), about the neck
// pivot (FaceModel::neckPivot).
Eigen::Matrix3d headRotation(double pitch, double yaw, double roll);

// Some of a mesh's vertices, for deforming only those (FaceModel::select): fitting the face to tracked
// landmarks moves 68 vertices, not the whole head, dozens of times a frame.
struct VertexSelection {
  struct FieldEntry {
    int column;
    Eigen::Vector3f displacement;
  };
  std::vector<int> vertices;  // the chosen vertices, in the order of the deformed columns (repeats allowed)
  std::vector<int> columnOf;  // per mesh vertex: its (first) column, or -1 when not chosen
  // Per FAP number: the linear fields (FaceModel::linearField) at the chosen vertices only.
  std::vector<std::vector<FieldEntry>> fields;
  // Per part of the rig that turns vertices (the tongue's roll, the jaw, each eye's lids and ball): its entries
  // whose vertex is chosen, as the vertex's column and the entry's place in the model's list, so that deforming a
  // few vertices does not walk every vertex the jaw moves.
  struct RigEntry {
    int column;
    int index;
  };
  std::vector<RigEntry> tongue, jaw;
  std::array<std::vector<RigEntry>, 2> upperLid, lowerLid, ball;
};

class FaceModel {
 public:
  static FaceModel build(const FaceAssets& assets, const FaceModelOptions& options = {});
  // The default face: ICT FaceKit's neutral head from assets/ (feature_points.h's ictFaceDirectory).
  static FaceModel buildDefault();

  Eigen::Matrix3Xd deform(const FapFrame& faps) const;
  // The same deformation of the selected vertices only (3 x selection.vertices.size()).
  Eigen::Matrix3Xd deform(const FapFrame& faps, const VertexSelection& selection) const;
  VertexSelection select(const std::vector<int>& vertices) const;  // throws th::Error for a vertex not in the mesh
  // The 68 iBUG landmarks' vertices (FaceAssets::landmarks; empty if the assets had none).
  const std::vector<int>& landmarkVertices() const { return landmarks_; }

  bool supports(int fap) const;
  const Mesh& mesh() const { return mesh_; }
  const FeaturePointMap& points() const { return points_; }
  // The vertices of the inner lip line (feature points 2.2-2.9): what bounds the mouth's opening.
  std::vector<int> innerLipVertices() const;
  // The vertices of an eye's lid line (feature points 3.1/3.3/3.7/3.11 for the face's left eye, side 0;
  // 3.2/3.4/3.8/3.12 for its right, side 1): what bounds the eye's opening.
  std::vector<int> eyeLidVertices(int side) const;
  const FapUnits& units() const { return units_; }
  const JawHinge& jaw() const { return jaw_; }
  // The pupils' size relative to rest for FAPs 29 (left) and 30 (right): 1 + value / 1024 · IRISD / pupil.
  std::array<double, 2> pupilScale(const FapFrame& faps) const;
  // The jaw angle (radians) that a FAP 3 value asks for.
  double jawAngleFor(double openJaw) const;
  const Eigen::Vector3d& neckPivot() const { return neckPivot_; }
  // How much of the head's turn (FAPs 48-50) a vertex follows: 1 on the head, fading to 0 down the neck.
  double headShare(int vertex) const { return headShare_.at(static_cast<std::size_t>(vertex)); }
  const BezierLattice& lattice() const { return lattice_; }
  const Embedding& embedding() const { return embedding_; }

  // The displacement field of a linear FAP per unit value (lattice fields, and the ears' and tongue's direct
  // ones, 43–46 and 65–68): (vertex, displacement) pairs; empty for others.
  struct FieldEntry {
    int vertex;
    Eigen::Vector3f displacement;
  };
  const std::vector<FieldEntry>& linearField(int fap) const { return linear_[static_cast<std::size_t>(fap)]; }
  // How far a linear FAP's field reaches: beyond this distance from its feature point it is negligible (3.5
  // fall-off radii, widened by the lattice's control-point spacing; for a direct field, the farthest vertex it
  // moves); 0 for other FAPs.
  double reach(int fap) const { return reach_[static_cast<std::size_t>(fap)]; }

 private:
  struct Eye {
    Eigen::Vector3d centre;
    double radius = 0.0;
    std::vector<int> ball;                                  // vertices that turn with the eyeball
    std::vector<std::pair<int, float>> upperLid, lowerLid;  // vertex, share of the lid's angle
  };

  // deform() for the vertices of `selection`, or every vertex when it is null.
  Eigen::Matrix3Xd deformSelected(const FapFrame& faps, const VertexSelection* selection) const;
  void closeLidsAndTurnEyes(const FapFrame& faps, const VertexSelection* selection, Eigen::Matrix3Xd& v) const;

  Mesh mesh_;
  FeaturePointMap points_;
  std::vector<int> landmarks_;
  FapUnits units_;
  JawHinge jaw_;
  Eigen::VectorXd jawFollow_;     // per vertex
  std::vector<int> jawVertices_;  // vertices with a jaw share > 0
  double chinFollow_ = 1.0;
  BezierLattice lattice_;
  Embedding embedding_;
  std::array<std::vector<FieldEntry>, kNumFaps + 1> linear_;
  std::array<double, kNumFaps + 1> reach_{};
  std::array<Eye, 2> eyes_;  // 0 left (+x), 1 right
  Eigen::Vector3d neckPivot_ = Eigen::Vector3d::Zero();
  std::vector<float> headShare_;                   // per vertex, 0..1
  std::vector<std::pair<int, float>> tongueRoll_;  // vertex, signed share of the roll angle (+ on the left)
  double tongueAxisY_ = 0.0;                       // height of the mid-line axis the tongue's sides roll about
  double pupilRadius_ = 0.0;
};

}  // namespace th::face
