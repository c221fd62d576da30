// An independent cross-check of the visual basis on the real BEAT2 jaw + FLAME expression data (101 x 1906):
// scikit-learn's PCA(whiten=True) and FastICA(logcosh, parallel), run by tools/visual_basis_reference.py on
// the same standardised data, must find the same two components (|correlation| > 0.999, up to order and sign)
// and the same explained variance.
//
//   ctest --test-dir build -L crosscheck --output-on-failure
//
// Needs /usr/bin/python3 with python3-numpy and python3-sklearn (scripts/packages.txt); without them the
// tests fail.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "animation/visual_basis.h"
#include "core/data_path.h"
#include "core/error.h"
#include "core/numeric_csv.h"
#include "core/subprocess.h"
#include "core/temporary_file.h"

namespace th::animation {
namespace {

constexpr const char* kPython = "/usr/bin/python3";

std::string referenceScript() {
  return std::string(TALKINGHEAD_SOURCE_DIR) + "/tools/visual_basis_reference.py";
}

// One BLAS thread, so a loaded machine gives the same numbers as an idle one. stderr is discarded by
// runProgram; on failure, run the command from the error message by hand to see Python's traceback.
std::string runReference(const std::vector<std::string>& arguments) {
  std::vector<std::string> argv{"env", "OPENBLAS_NUM_THREADS=1", "OMP_NUM_THREADS=1", kPython};
  argv.insert(argv.end(), arguments.begin(), arguments.end());
  return runProgram(argv);
}

// The last non-empty line the reference printed, as a number.
double lastNumber(const std::string& output) {
  std::istringstream lines(output);
  std::string line;
  std::string last;
  while (std::getline(lines, line)) {
    if (!line.empty()) last = line;
  }
  size_t used = 0;
  const double value = std::stod(last, &used);
  if (used != last.size()) throw std::runtime_error("not a number: " + last);
  return value;
}

// Jaw opening (degrees) and the 100 FLAME expression coefficients of the BEAT2 take, one frame per column,
// with the column names the CSV for the reference gets.
struct VisualData {
  std::vector<std::string> columns;
  Eigen::MatrixXd x;  // 101 x T
};

VisualData beat2Visual() {
  const NumericTable expression = readNumericCsv(sharedDataPath("beat2/2_scott_0_1_1_flame_expr_30fps.csv"));
  const NumericTable pose = readNumericCsv(sharedDataPath("beat2/2_scott_0_1_1_headpose_30fps.csv"));
  EXPECT_EQ(expression.rows.size(), pose.rows.size()) << "the two CSVs are the same take, frame for frame";
  const size_t jaw = static_cast<size_t>(pose.column("jaw_aa_x_deg"));
  const Eigen::Index numFrames = static_cast<Eigen::Index>(std::min(expression.rows.size(), pose.rows.size()));
  VisualData data;
  data.columns.push_back("jaw_aa_x_deg");
  data.columns.insert(data.columns.end(), expression.columns.begin(), expression.columns.end());
  data.x.resize(static_cast<Eigen::Index>(data.columns.size()), numFrames);
  for (Eigen::Index t = 0; t < numFrames; ++t) {
    const auto& row = expression.rows[static_cast<size_t>(t)];
    data.x(0, t) = pose.rows[static_cast<size_t>(t)][jaw];
    for (size_t e = 0; e < row.size(); ++e) data.x(static_cast<Eigen::Index>(e) + 1, t) = row[e];
  }
  return data;
}

double correlation(const Eigen::Ref<const Eigen::RowVectorXd>& a, const Eigen::Ref<const Eigen::RowVectorXd>& b) {
  const Eigen::RowVectorXd ca = a.array() - a.mean();
  const Eigen::RowVectorXd cb = b.array() - b.mean();
  return ca.dot(cb) / std::sqrt(ca.squaredNorm() * cb.squaredNorm());
}

TEST(VisualBasisCrosscheck, PythonNumpyAndSklearnAreInstalled) {
  std::string versions;
  try {
    versions = runReference({"-c", "import numpy, sklearn; print(numpy.__version__, sklearn.__version__)"});
  } catch (const Error& e) {
    FAIL() << kPython << " with numpy and sklearn is needed for the cross-check "
           << "(apt-get install python3-numpy python3-sklearn; scripts/packages.txt): " << e.what();
  }
  ASSERT_TRUE(std::filesystem::exists(referenceScript())) << referenceScript();
  std::printf("[ INFO     ] numpy, sklearn: %s", versions.c_str());
}

TEST(VisualBasisCrosscheck, ComponentsAgreeWithScikitLearnOnBeat2) {
  const VisualData data = beat2Visual();
  ASSERT_EQ(data.x.rows(), 101);
  ASSERT_EQ(data.x.cols(), 1906);
  const Eigen::Index numFrames = data.x.cols();

  const TemporaryFolder folder;
  const std::filesystem::path input = folder.path() / "visual.csv";
  const std::filesystem::path output = folder.path() / "components.csv";
  std::vector<std::vector<double>> rows(static_cast<size_t>(numFrames));
  for (Eigen::Index t = 0; t < numFrames; ++t) {
    const Eigen::VectorXd frame = data.x.col(t);
    rows[static_cast<size_t>(t)].assign(frame.data(), frame.data() + frame.size());
  }
  writeNumericCsv(input, data.columns, rows);

  const std::string printed = runReference({referenceScript(), input.string(), output.string(), "--components", "2"});
  const double sklearnExplained = lastNumber(printed);
  const NumericTable reference = readNumericCsv(output);
  ASSERT_EQ(reference.columns.size(), 2u);
  ASSERT_EQ(reference.rows.size(), static_cast<size_t>(numFrames));
  Eigen::MatrixXd theirs(2, numFrames);
  for (Eigen::Index t = 0; t < numFrames; ++t) {
    for (Eigen::Index k = 0; k < 2; ++k) theirs(k, t) = reference.rows[static_cast<size_t>(t)][static_cast<size_t>(k)];
  }

  const VisualBasis basis = VisualBasis::fit(data.x, {.components = 2});
  const Eigen::MatrixXd ours = basis.transform(data.x);
  EXPECT_NEAR(basis.explainedVariance(), sklearnExplained, 1e-9) << "PCA: eigen-decomposition vs sklearn's SVD";

  // Match up to order and sign: the pairing with the larger total |correlation|.
  Eigen::Matrix2d c;
  for (Eigen::Index i = 0; i < 2; ++i) {
    for (Eigen::Index j = 0; j < 2; ++j) c(i, j) = correlation(ours.row(i), theirs.row(j));
  }
  const bool straight = std::abs(c(0, 0)) + std::abs(c(1, 1)) >= std::abs(c(0, 1)) + std::abs(c(1, 0));
  const double first = straight ? c(0, 0) : c(0, 1);
  const double second = straight ? c(1, 1) : c(1, 0);
  std::printf("[ INFO     ] explained variance: ours %.12f, sklearn %.12f (%s)\n", basis.explainedVariance(),
              sklearnExplained, printed.substr(0, printed.find('\n')).c_str());
  std::printf("[ INFO     ] ours 0 ~ sklearn %d: correlation %+.8f; ours 1 ~ sklearn %d: correlation %+.8f\n",
              straight ? 0 : 1, first, straight ? 1 : 0, second);
  EXPECT_GT(std::abs(first), 0.999) << "all correlations (ours x sklearn):\n" << c;
  EXPECT_GT(std::abs(second), 0.999) << "all correlations (ours x sklearn):\n" << c;
}

}  // namespace
}  // namespace th::animation
