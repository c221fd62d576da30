// Reading and writing numeric tables as CSV: a header of column names, then one row of numbers per line.
//
//   th::NumericTable table = th::readNumericCsv("features.csv");
//   int f0 = table.column("f0_hz");            // throws th::Error naming the file if there is no such column
//   double value = table.rows[t][f0];
//
// Bad input (missing file, empty, ragged rows, text where a number should be, NaN/inf) is a th::Error of one
// line: "PATH: line 17 has 3 values, the header has 4". Thread contract: no shared state.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace th {

struct NumericTable {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  std::filesystem::path source;

  int column(const std::string& name) const;      // throws if absent
  int findColumn(const std::string& name) const;  // -1 if absent
};

NumericTable readNumericCsv(const std::filesystem::path& path);

// Writes atomically (temporary file + rename): the file is complete or absent.
void writeNumericCsv(const std::filesystem::path& path, const std::vector<std::string>& columns,
                     const std::vector<std::vector<double>>& rows);

}  // namespace th
