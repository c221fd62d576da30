// Context stacking: the edges repeat, the stream gives the batch values, and a stream fed faster than it is
// read refuses rather than stacking overwritten frames.
#include "features/context.h"

#include <gtest/gtest.h>

#include <random>

#include "core/error.h"

namespace th::features {
namespace {

TEST(ContextStacking, ReplicatesTheEdges) {
  Eigen::MatrixXd mfcc(2, 4);
  mfcc << 1, 2, 3, 4, 10, 20, 30, 40;
  const Eigen::MatrixXd stacked = stackContext(mfcc, 1);
  ASSERT_EQ(stacked.rows(), 6);
  ASSERT_EQ(stacked.cols(), 4);
  // Frame 0: [frame 0 (edge), frame 0, frame 1]; frame 3: [frame 2, frame 3, frame 3 (edge)].
  EXPECT_EQ(stacked.col(0), (Eigen::VectorXd(6) << 1, 10, 1, 10, 2, 20).finished());
  EXPECT_EQ(stacked.col(3), (Eigen::VectorXd(6) << 3, 30, 4, 40, 4, 40).finished());
  EXPECT_EQ(stackContext(mfcc, 0), mfcc);
  EXPECT_THROW(stackContext(mfcc, -1), Error);
}

TEST(ContextStacking, TheStreamGivesTheBatchValuesFrameByFrame) {
  std::mt19937 random(3);
  std::normal_distribution<double> normal;
  const Eigen::MatrixXd frames = Eigen::MatrixXd::NullaryExpr(11, 40, [&] { return normal(random); });
  for (int context : {0, 1, 3, 5}) {
    const Eigen::MatrixXd batch = stackContext(frames, context);
    ContextStacker stacker(frames.rows(), context);
    Eigen::VectorXd out;
    Eigen::Index next = 0;
    for (Eigen::Index t = 0; t < frames.cols(); ++t) {
      stacker.acceptFrame(frames.col(t));
      while (stacker.next(out)) {
        EXPECT_EQ(next + context, t) << "frame " << next << " waits for exactly its right context";
        EXPECT_EQ(out, batch.col(next++));
      }
    }
    EXPECT_EQ(next, frames.cols() - context);
    stacker.inputFinished();
    while (stacker.next(out)) EXPECT_EQ(out, batch.col(next++));
    EXPECT_EQ(next, frames.cols()) << "context " << context;
  }
}

TEST(ContextStacking, APastOnlyContextWaitsForNoLaterFrame) {
  Eigen::MatrixXd mfcc(2, 4);
  mfcc << 1, 2, 3, 4, 10, 20, 30, 40;
  // Frame 2 with two frames before and none after: [frame 0, frame 1, frame 2].
  const Eigen::MatrixXd past = stackContext(mfcc, 2, 0);
  ASSERT_EQ(past.rows(), 6);
  EXPECT_EQ(past.col(2), (Eigen::VectorXd(6) << 1, 10, 2, 20, 3, 30).finished());
  EXPECT_EQ(past.col(0), (Eigen::VectorXd(6) << 1, 10, 1, 10, 1, 10).finished()) << "the first frame repeats";
  EXPECT_EQ(stackContext(mfcc, 1, 1), stackContext(mfcc, 1));
  EXPECT_THROW(stackContext(mfcc, 1, -1), Error);

  std::mt19937 random(5);
  std::normal_distribution<double> normal;
  const Eigen::MatrixXd frames = Eigen::MatrixXd::NullaryExpr(3, 30, [&] { return normal(random); });
  for (const auto& [before, after] : {std::pair{2, 0}, std::pair{1, 2}, std::pair{0, 3}}) {
    const Eigen::MatrixXd batch = stackContext(frames, before, after);
    ContextStacker stacker(frames.rows(), before, after);
    Eigen::VectorXd out;
    Eigen::Index next = 0;
    for (Eigen::Index t = 0; t < frames.cols(); ++t) {
      stacker.acceptFrame(frames.col(t));
      while (stacker.next(out)) {
        EXPECT_EQ(next + after, t) << "frame " << next << " waits for its " << after << " later frames only";
        EXPECT_EQ(out, batch.col(next++));
      }
    }
    stacker.inputFinished();
    while (stacker.next(out)) EXPECT_EQ(out, batch.col(next++));
    EXPECT_EQ(next, frames.cols()) << before << " before, " << after << " after";
  }
}

TEST(ContextStacking, AFrameInBeforeTheReadyOnesAreTakenIsRefused) {
  ContextStacker stacker(2, 1);
  stacker.acceptFrame(Eigen::Vector2d(1, 2));
  stacker.acceptFrame(Eigen::Vector2d(3, 4));  // frame 0 is ready now
  EXPECT_THROW(stacker.acceptFrame(Eigen::Vector2d(5, 6)), Error);
  Eigen::VectorXd out;
  ASSERT_TRUE(stacker.next(out));
  EXPECT_NO_THROW(stacker.acceptFrame(Eigen::Vector2d(5, 6)));
  EXPECT_THROW(stacker.acceptFrame(Eigen::Vector3d(1, 2, 3)), Error) << "a frame of the wrong size";
}

}  // namespace
}  // namespace th::features
