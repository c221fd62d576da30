#include "core/options.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>

#include "core/number_parsing.h"
#include "core/text_files.h"

namespace th {
namespace {

std::string formatValue(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

bool inRange(double value, const OptionSpec& spec) {
  return value >= spec.min && value <= spec.max;
}

bool isChoice(const std::string& value, const OptionSpec& spec) {
  return spec.choices.empty() || std::find(spec.choices.begin(), spec.choices.end(), value) != spec.choices.end();
}

// "NAME: 7 is outside 0..5" and the like.
[[noreturn]] void outOfRange(const OptionSpec& spec, const std::string& value) {
  throw Error(std::string(spec.name) + ": " + value + " is not " + describeRange(spec));
}

class Checker final : public OptionVisitor {
 public:
  void option(bool&, const OptionSpec&) override {}
  void option(int& value, const OptionSpec& spec) override { number(value, spec); }
  void option(unsigned& value, const OptionSpec& spec) override { number(value, spec); }
  void option(double& value, const OptionSpec& spec) override {
    if (!std::isfinite(value)) outOfRange(spec, formatValue(value));
    number(value, spec);
  }
  void option(std::string& value, const OptionSpec& spec) override {
    if (!isChoice(value, spec)) outOfRange(spec, "\"" + printable(value) + "\"");
  }

 private:
  template <typename T>
  void number(T value, const OptionSpec& spec) {
    if (!inRange(static_cast<double>(value), spec)) outOfRange(spec, formatValue(static_cast<double>(value)));
  }
};

// Parses text into the field of that name.
class Setter final : public OptionVisitor {
 public:
  Setter(std::string_view name, std::string_view text) : name_(name), text_(text) {}
  bool found() const { return found_; }

  void option(bool& value, const OptionSpec& spec) override {
    if (!mine(spec)) return;
    if (text_ == "true" || text_ == "1" || text_ == "on") {
      value = true;
    } else if (text_ == "false" || text_ == "0" || text_ == "off") {
      value = false;
    } else {
      throw Error(std::string(spec.name) + ": \"" + printable(text_) + "\" is not true or false");
    }
  }
  void option(int& value, const OptionSpec& spec) override { whole(value, spec); }
  void option(unsigned& value, const OptionSpec& spec) override { whole(value, spec); }
  void option(double& value, const OptionSpec& spec) override {
    if (!mine(spec)) return;
    const std::optional<double> parsed = parseWholeNumber<double>(text_);
    if (!parsed || !std::isfinite(*parsed))
      throw Error(std::string(spec.name) + ": \"" + printable(text_) + "\" is not a number");
    if (!inRange(*parsed, spec)) outOfRange(spec, std::string(text_));
    value = *parsed;
  }
  void option(std::string& value, const OptionSpec& spec) override {
    if (!mine(spec)) return;
    const std::string text(text_);
    if (!isChoice(text, spec)) outOfRange(spec, "\"" + printable(text) + "\"");
    value = text;
  }

 private:
  bool mine(const OptionSpec& spec) {
    if (spec.name != name_ && (spec.formerName.empty() || spec.formerName != name_)) return false;
    found_ = true;
    return true;
  }
  template <typename T>
  void whole(T& value, const OptionSpec& spec) {
    if (!mine(spec)) return;
    long long parsed = 0;
    const auto [end, error] = std::from_chars(text_.data(), text_.data() + text_.size(), parsed);
    if (error != std::errc() || end != text_.data() + text_.size())
      throw Error(std::string(spec.name) + ": \"" + printable(text_) + "\" is not a whole number");
    if (!inRange(static_cast<double>(parsed), spec)) outOfRange(spec, std::string(text_));
    value = static_cast<T>(parsed);
  }

  std::string_view name_;
  std::string_view text_;
  bool found_ = false;
};

class JsonWriter final : public OptionVisitor {
 public:
  Json document = Json::object();
  void option(bool& value, const OptionSpec& spec) override { document[settingsKey(spec.name)] = value; }
  void option(int& value, const OptionSpec& spec) override { document[settingsKey(spec.name)] = value; }
  void option(unsigned& value, const OptionSpec& spec) override { document[settingsKey(spec.name)] = value; }
  void option(double& value, const OptionSpec& spec) override { document[settingsKey(spec.name)] = value; }
  void option(std::string& value, const OptionSpec& spec) override { document[settingsKey(spec.name)] = value; }
};

class JsonReader final : public OptionVisitor {
 public:
  JsonReader(const Json& document, const std::filesystem::path& path) : document_(document), fields_(path.string()) {}

  void option(bool& value, const OptionSpec& spec) override {
    if (const Json* item = find(spec)) value = fields_.boolean(*item, key(spec));
  }
  void option(int& value, const OptionSpec& spec) override { whole(value, spec); }
  void option(unsigned& value, const OptionSpec& spec) override { whole(value, spec); }
  void option(double& value, const OptionSpec& spec) override {
    const Json* item = find(spec);
    if (item == nullptr) return;
    const double read = fields_.number(*item, key(spec));
    if (!inRange(read, spec))
      fields_.fail(key(spec), "is " + formatValue(read) + "; it must be " + describeRange(spec));
    value = read;
  }
  void option(std::string& value, const OptionSpec& spec) override {
    const Json* item = find(spec);
    if (item == nullptr) return;
    const std::string& read = fields_.string(*item, key(spec));
    if (!isChoice(read, spec))
      fields_.fail(key(spec), "is \"" + printable(read) + "\"; it must be " + describeRange(spec));
    value = read;
  }

 private:
  // The option's key, or its former name's in a file written before the option was renamed.
  std::string key(const OptionSpec& spec) const {
    const std::string current = settingsKey(spec.name);
    if (spec.formerName.empty() || fields_.find(document_, current) != nullptr) return current;
    const std::string former = settingsKey(spec.formerName);
    return fields_.find(document_, former) != nullptr ? former : current;
  }
  const Json* find(const OptionSpec& spec) const { return fields_.find(document_, key(spec)); }
  template <typename T>
  void whole(T& value, const OptionSpec& spec) {
    const Json* item = find(spec);
    if (item == nullptr) return;
    const std::int64_t read = fields_.integer(*item, key(spec));
    if (!inRange(static_cast<double>(read), spec))
      fields_.fail(key(spec), "is " + std::to_string(read) + "; it must be " + describeRange(spec));
    value = static_cast<T>(read);
  }

  const Json& document_;
  JsonFields fields_;
};

}  // namespace

std::string settingsKey(std::string_view name) {
  std::string key(name);
  std::replace(key.begin(), key.end(), '-', '_');
  return key;
}

std::string describeRange(const OptionSpec& spec) {
  std::string text;
  if (!spec.choices.empty()) {
    text = "one of ";
    for (std::size_t i = 0; i < spec.choices.size(); ++i) text += (i > 0 ? ", " : "") + std::string(spec.choices[i]);
    return text;
  }
  const bool low = std::isfinite(spec.min);
  const bool high = std::isfinite(spec.max);
  if (low && high)
    text = formatValue(spec.min) + ".." + formatValue(spec.max);
  else if (low)
    text = "at least " + formatValue(spec.min);
  else if (high)
    text = "at most " + formatValue(spec.max);
  if (!spec.unit.empty() && !text.empty()) text += " " + std::string(spec.unit);
  return text;
}

void checkOptionValues(const std::function<void(OptionVisitor&)>& visit) {
  Checker checker;
  visit(checker);
}

bool setOptionByName(const std::function<void(OptionVisitor&)>& visit, std::string_view name, std::string_view text) {
  Setter setter(name, text);
  visit(setter);
  return setter.found();
}

Json optionValuesToJson(const std::function<void(OptionVisitor&)>& visit) {
  JsonWriter writer;
  visit(writer);
  return writer.document;
}

void optionValuesFromJson(const std::function<void(OptionVisitor&)>& visit, const Json& document,
                          const std::filesystem::path& path) {
  if (!document.is_object()) throw fileError(path, "is not a JSON object of settings");
  JsonReader reader(document, path);
  visit(reader);
}

}  // namespace th
