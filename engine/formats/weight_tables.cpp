#include "formats/weight_tables.h"

#include <cstdio>

namespace th::formats {

void writeWeightsCsv(std::ostream& out, std::span<const std::string_view> names, const Eigen::MatrixXd& weights,
                     double framesPerSecond) {
  out << "time_s";
  for (std::string_view name : names) out << ',' << name;
  out << '\n';
  char buffer[32];
  for (Eigen::Index t = 0; t < weights.cols(); ++t) {
    std::snprintf(buffer, sizeof buffer, "%.6f", static_cast<double>(t) / framesPerSecond);
    out << buffer;
    for (Eigen::Index k = 0; k < weights.rows(); ++k) {
      std::snprintf(buffer, sizeof buffer, ",%.4f", weights(k, t));
      out << buffer;
    }
    out << '\n';
  }
}

void writeWeightsJson(std::ostream& out, std::span<const std::string_view> names, const Eigen::MatrixXd& weights,
                      double framesPerSecond) {
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "%.17g", framesPerSecond);
  out << "{\n  \"fps\": " << buffer << ",\n  \"names\": [";
  for (std::size_t k = 0; k < names.size(); ++k) out << (k == 0 ? "\"" : ", \"") << names[k] << '"';
  out << "],\n  \"frames\": [";
  for (Eigen::Index t = 0; t < weights.cols(); ++t) {
    std::snprintf(buffer, sizeof buffer, "%.6f", static_cast<double>(t) / framesPerSecond);
    out << (t == 0 ? "\n" : ",\n") << "    {\"time\": " << buffer << ", \"weights\": [";
    for (Eigen::Index k = 0; k < weights.rows(); ++k) {
      std::snprintf(buffer, sizeof buffer, "%s%.4f", k == 0 ? "" : ", ", weights(k, t));
      out << buffer;
    }
    out << "]}";
  }
  out << "\n  ]\n}\n";
}

}  // namespace th::formats
