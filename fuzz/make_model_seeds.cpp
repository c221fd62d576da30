// Writes the model-file fuzzer's seed corpus: small valid models of every shape the format has (full and
// diagonal covariance, one and several components, with and without names, blocks and training metadata).
//
//   make_model_seeds OUT_DIR
//
// Small on purpose: libFuzzer mutates faster on short inputs, and every field is already there to mutate.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>

#include "hmm/model_file.h"
#include "hmm_test_models.h"

namespace {

void write(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error(path.string() + ": cannot be written");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: make_model_seeds OUT_DIR\n";
    return 2;
  }
  try {
    using th::hmm::CovarianceType;
    const std::filesystem::path out = argv[1];
    std::filesystem::create_directories(out);

    write(out / "sticky_1d.json", th::hmm::formatModel(th::test::stickyModel1d(3, 0.9),
                                                       R"({"iterations": 12, "logLikelihoods": [-310.5, -290.25]})"));

    th::hmm::HmmModel named = th::test::randomModel(2, 2, 3, CovarianceType::kFull, 1);
    named.columnNames = {"f0_hz", "energy_db", "jaw"};
    named.blocks = {{"audio", 0, 2}, {"visual", 2, 1}};
    write(out / "full_named.json", th::hmm::formatModel(named, R"({"options": {"entropic": 0.5, "seed": 1}})"));

    th::hmm::HmmModel diagonal = th::test::randomModel(3, 2, 2, CovarianceType::kDiagonal, 2);
    diagonal.columnNames = {"mfcc1", "lip_width"};
    diagonal.blocks = {{"audio", 0, 1}, {"visual", 1, 1}};
    write(out / "diagonal_named.json", th::hmm::formatModel(diagonal));

    write(out / "single.json", th::hmm::formatModel(th::test::randomModel(1, 1, 1, CovarianceType::kFull, 3)));
    write(out / "full_d4.json", th::hmm::formatModel(th::test::randomModel(2, 1, 4, CovarianceType::kFull, 4)));
  } catch (const std::exception& e) {
    std::cerr << e.what() << '\n';
    return 1;
  }
  return 0;
}
