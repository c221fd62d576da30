// The linear FAPs' fields through the skin's Bézier lattice (lips 4–13, 16, 17, 51–60; chin 18; brows 31–38;
// cheeks 39–42; nose 61–64): piecewise Bézier volume deformation (bezier_volume.h). FAP k displaces the lattice's
// control points by D_k, a Gaussian fall-off around its feature point times its direction, so the skin moves by
// B·D_k: smooth, and zero far away. All skin inside the lattice is embedded; the fields vanish on the lattice's
// surface, so skin outside it (the back of the head) meets the moving skin inside without a crack. A per-vertex
// mask confines each field to the skin of its own side and lip: the upper and lower lip touch at rest, so no
// smooth field alone could move one without the other, and the lips are told apart by how far the jaw carries
// each vertex (rig_jaw.h). The brows' fields differ (rig_brows.h).
// Thread contract: values and pure functions.
#pragma once

#include <Eigen/Core>

#include "face/bezier_volume.h"
#include "face/feature_points.h"
#include "face/rig.h"

namespace th::face::rig {

struct SkinLattice {
  BezierLattice lattice;  // around the face (M_Face), 0.1 MW wider on every side
  Embedding embedding;    // the skin inside it; `points` are mesh vertex numbers
};

SkinLattice embedSkin(const NeutralFace& neutral, const BezierLatticeOptions& options);

// Adds the field of each FAP above to `fields`. `jawFollow`: per vertex, its share of the jaw's motion (the
// lips' masks). Throws th::Error if a FAP's feature point lies outside the lattice or its field does not reach it.
void addLatticeFields(const NeutralFace& neutral, const FeaturePointMap& points, const SkinLattice& skin,
                      const Eigen::VectorXd& jawFollow, const BezierLatticeOptions& options, LinearFields& fields);

}  // namespace th::face::rig
