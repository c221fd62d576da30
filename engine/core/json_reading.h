// Checked JSON reading for every file the program parses (model files, animation files, settings, corpora's
// indices): parsing with a nesting limit, and typed access whose errors are one line naming the file and the
// field at fault ("model.json: states[3].weights is a string, not an array").
//
//   const th::Json document = th::readJsonFile(path, "settings file");
//   const th::JsonFields fields(path.string());
//   const double fps = fields.number(fields.member(document, "fps", ""), "fps");
//   fields.onlyKnownFields(document, {"fps", "name"}, "");   // a misspelt key is an error, not ignored
//
// Documents are ordered (nlohmann::ordered_json): keys keep the order they were written in, so a file that is
// read and written back reads top to bottom as before. Field paths are built only when something fails.
// Thread contract: pure functions; a JsonFields is immutable.
#pragma once

#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace th {

using Json = nlohmann::ordered_json;

struct JsonParseOptions {
  // Deeper nesting is refused while parsing, before a forged file can build a deep tree (nlohmann's dump()
  // and destructor recurse).
  int maxDepth = 64;
  std::string depthNote;  // said after the limit, e.g. "a model needs 7"
  std::string subject;    // what the text is when it is not the whole file: "the training metadata"
};

// Errors read "FILE: [SUBJECT] what": empty text, invalid JSON (with nlohmann's line and column), a number beyond
// a double (with its line and column), nesting beyond the limit.
Json parseJson(std::string_view text, const std::string& fileName, const JsonParseOptions& options = {});
// The file read with readTextFile (core/text_files.h; `kind` names it in messages) and parsed.
Json readJsonFile(const std::filesystem::path& path, std::string_view kind, const JsonParseOptions& options = {});

// Typed access to a parsed document; each failure throws th::Error "FILE: FIELD what".
class JsonFields {
 public:
  explicit JsonFields(std::string fileName) : fileName_(std::move(fileName)) {}

  [[noreturn]] void fail(const std::string& field, const std::string& what) const;

  // The member `key` of `object` (whose own field path is objectField, "" at the top); missing is an error.
  const Json& member(const Json& object, std::string_view key, const std::string& objectField) const;
  const Json* find(const Json& object, std::string_view key) const;  // nullptr if absent
  // Any other key is an error: "X is not a known field (there are a, b)", or with a description
  // "X is not a field of DESCRIPTION (it has a, b)".
  void onlyKnownFields(const Json& object, std::initializer_list<std::string_view> known,
                       const std::string& objectField, std::string_view description = {}) const;

  const Json& object(const Json& value, const std::string& field) const;
  const Json& array(const Json& value, const std::string& field) const;
  const std::string& string(const Json& value, const std::string& field) const;
  bool boolean(const Json& value, const std::string& field) const;
  // JSON has no NaN or infinity and the parser refuses numbers beyond a double, but an integer may still be
  // too large for one: non-finite values are refused.
  double number(const Json& value, const std::string& field) const;
  std::int64_t integer(const Json& value, const std::string& field) const;

  // "an object", "a string", "an integer", ...; and a short rendering for messages (strings quoted, numbers
  // as numbers, anything else by its kind).
  static std::string kindOf(const Json& value);
  static std::string describe(const Json& value);
  static std::string indexed(const std::string& field, std::size_t index);    // "field[3]"
  static std::string dotted(const std::string& field, std::string_view key);  // "field.key" ("key" at the top)

 private:
  std::string fileName_;
};

}  // namespace th
