#include "core/json_reading.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/text_files.h"

namespace th {

Json parseJson(std::string_view text, const std::string& fileName, const JsonParseOptions& options) {
  const std::string prefix = options.subject.empty() ? "" : options.subject + " ";
  if (text.find_first_not_of(" \t\r\n") == std::string_view::npos) throw fileError(fileName, prefix + "is empty");
  const Json::parser_callback_t limitDepth = [&](int depth, Json::parse_event_t event, Json&) {
    if ((event == Json::parse_event_t::object_start || event == Json::parse_event_t::array_start) &&
        depth >= options.maxDepth) {
      throw fileError(fileName, prefix + "nests arrays and objects more than " + std::to_string(options.maxDepth) +
                                    " deep" + (options.depthNote.empty() ? "" : " (" + options.depthNote + ")"));
    }
    return true;
  };
  try {
    return Json::parse(text.begin(), text.end(), limitDepth);
  } catch (const Json::out_of_range& e) {
    // nlohmann refuses a number beyond the range of double (1e999) with "number overflow parsing '1e999'"
    // and no position; the token is found in the text to say where it is.
    const std::string what = e.what();
    const auto open = what.find('\'');
    const auto close = what.rfind('\'');
    if (open == std::string::npos || close <= open) throw fileError(fileName, prefix + jsonReason(what));
    const std::string token = what.substr(open + 1, close - open - 1);
    std::string where;
    if (const auto at = text.find(token); at != std::string_view::npos) {
      const auto lineStart = text.rfind('\n', at);
      const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n');
      const auto column = lineStart == std::string_view::npos ? at + 1 : at - lineStart;
      where = " at line " + std::to_string(line) + ", column " + std::to_string(column);
    }
    throw fileError(fileName, (options.subject.empty() ? "" : options.subject + ": ") + "the number " +
                                  printable(token) + where + " is out of the range of a double");
  } catch (const Json::exception& e) {
    throw fileError(fileName, prefix + "is not valid JSON (" + jsonReason(e.what()) + ")");
  }
}

Json readJsonFile(const std::filesystem::path& path, std::string_view kind, const JsonParseOptions& options) {
  return parseJson(readTextFile(path, kind), path.string(), options);
}

void JsonFields::fail(const std::string& field, const std::string& what) const {
  throw fileError(fileName_, field + " " + what);
}

const Json* JsonFields::find(const Json& object, std::string_view key) const {
  const auto it = object.find(std::string(key));
  return it == object.end() ? nullptr : &*it;
}

const Json& JsonFields::member(const Json& object, std::string_view key, const std::string& objectField) const {
  const Json* value = find(object, key);
  if (value == nullptr) fail(dotted(objectField, key), "is missing");
  return *value;
}

void JsonFields::onlyKnownFields(const Json& object, std::initializer_list<std::string_view> known,
                                 const std::string& objectField, std::string_view description) const {
  for (auto it = object.begin(); it != object.end(); ++it) {
    if (std::find(known.begin(), known.end(), it.key()) != known.end()) continue;
    std::string list;
    for (std::string_view key : known) list += (list.empty() ? "" : ", ") + std::string(key);
    const std::string field = dotted(objectField, printable(it.key()));
    if (description.empty()) fail(field, "is not a known field (there are " + list + ")");
    fail(field, "is not a field of " + std::string(description) + " (it has " + list + ")");
  }
}

const Json& JsonFields::object(const Json& value, const std::string& field) const {
  if (!value.is_object()) fail(field, "is " + kindOf(value) + ", not an object");
  return value;
}

const Json& JsonFields::array(const Json& value, const std::string& field) const {
  if (!value.is_array()) fail(field, "is " + kindOf(value) + ", not an array");
  return value;
}

const std::string& JsonFields::string(const Json& value, const std::string& field) const {
  if (!value.is_string()) fail(field, "is " + kindOf(value) + ", not a string");
  return value.get_ref<const std::string&>();
}

bool JsonFields::boolean(const Json& value, const std::string& field) const {
  if (!value.is_boolean()) fail(field, "is " + describe(value) + ", not true or false");
  return value.get<bool>();
}

double JsonFields::number(const Json& value, const std::string& field) const {
  if (!value.is_number()) fail(field, "is " + describe(value) + ", not a number");
  const double number = value.get<double>();
  if (!std::isfinite(number)) fail(field, "is not a finite number");
  return number;
}

std::int64_t JsonFields::integer(const Json& value, const std::string& field) const {
  // nlohmann reads a non-negative integer as unsigned and a negative one as signed.
  if (value.is_number_unsigned()) {
    const auto unsignedValue = value.get<std::uint64_t>();
    if (unsignedValue > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
      fail(field, "is " + std::to_string(unsignedValue) + ", out of range");
    return static_cast<std::int64_t>(unsignedValue);
  }
  if (!value.is_number_integer()) fail(field, "is " + describe(value) + ", not an integer");
  return value.get<std::int64_t>();
}

std::string JsonFields::kindOf(const Json& value) {
  switch (value.type()) {
    case Json::value_t::null:
      return "null";
    case Json::value_t::object:
      return "an object";
    case Json::value_t::array:
      return "an array";
    case Json::value_t::string:
      return "a string";
    case Json::value_t::boolean:
      return "a boolean";
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned:
      return "an integer";
    case Json::value_t::number_float:
      return "a number";
    default:
      return "not a JSON value";
  }
}

std::string JsonFields::describe(const Json& value) {
  if (value.is_string()) return "\"" + printable(value.get_ref<const std::string&>()) + "\"";
  if (value.is_number()) return value.dump();  // "1.0" for a float, so "is 1.0, not an integer" reads right
  return kindOf(value);
}

std::string JsonFields::indexed(const std::string& field, std::size_t index) {
  return field + "[" + std::to_string(index) + "]";
}

std::string JsonFields::dotted(const std::string& field, std::string_view key) {
  return field.empty() ? std::string(key) : field + "." + std::string(key);
}

}  // namespace th
