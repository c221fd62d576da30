#include "core/numeric_csv.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/number_parsing.h"

namespace th {
namespace {

std::vector<std::string> splitFields(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream stream(line);
  while (std::getline(stream, field, ',')) {
    const auto first = field.find_first_not_of(" \t\r");
    const auto last = field.find_last_not_of(" \t\r");
    fields.push_back(first == std::string::npos ? "" : field.substr(first, last - first + 1));
  }
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

}  // namespace

int NumericTable::findColumn(const std::string& name) const {
  for (size_t i = 0; i < columns.size(); ++i) {
    if (columns[i] == name) return static_cast<int>(i);
  }
  return -1;
}

int NumericTable::column(const std::string& name) const {
  const int index = findColumn(name);
  if (index < 0) throw fileError(source, "has no column named '" + name + "'");
  return index;
}

NumericTable readNumericCsv(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!std::filesystem::exists(path)) throw fileError(path, "no such file");
  if (!in) throw fileError(path, "cannot be opened for reading");
  NumericTable table;
  table.source = path;
  std::string line;
  if (!std::getline(in, line) || line.find_first_not_of(" \t\r") == std::string::npos) {
    throw fileError(path, "empty (expected a header line of column names)");
  }
  table.columns = splitFields(line);
  for (const auto& name : table.columns) {
    if (name.empty()) throw fileError(path, "the header has an empty column name");
  }
  int lineNumber = 1;
  while (std::getline(in, line)) {
    ++lineNumber;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const auto fields = splitFields(line);
    if (fields.size() != table.columns.size()) {
      throw fileError(path, "line " + std::to_string(lineNumber) + " has " + std::to_string(fields.size()) +
                                " values, the header has " + std::to_string(table.columns.size()));
    }
    std::vector<double> row(fields.size());
    for (size_t i = 0; i < fields.size(); ++i) {
      const std::string& text = fields[i];
      const std::optional<double> value = parseWholeNumber<double>(text);
      if (!value || !std::isfinite(*value)) {
        throw fileError(path, "line " + std::to_string(lineNumber) + ", column '" + table.columns[i] + "': '" + text +
                                  "' is not a finite number");
      }
      row[i] = *value;
    }
    table.rows.push_back(std::move(row));
  }
  if (table.rows.empty()) throw fileError(path, "has a header but no rows");
  return table;
}

void writeNumericCsv(const std::filesystem::path& path, const std::vector<std::string>& columns,
                     const std::vector<std::vector<double>>& rows) {
  AtomicFile file(path);
  std::ostream& out = file.stream();
  for (size_t i = 0; i < columns.size(); ++i) out << (i ? "," : "") << columns[i];
  out << '\n' << std::setprecision(std::numeric_limits<double>::max_digits10);
  for (const auto& row : rows) {
    for (size_t i = 0; i < row.size(); ++i) out << (i ? "," : "") << row[i];
    out << '\n';
  }
  file.commit();
}

}  // namespace th
