// A small JSON reader for the core's own files (the costs file, costs.hpp; the culler
// configuration, config.hpp), so that the core needs no JSON library; and the helpers
// their writers share. Internal to logrid::core.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "logrid/error.hpp"

namespace logrid::detail {

// A JSON value. Arrays are parsed (so that a file may hold them) but not kept: none of
// the core's files reads one.
struct Json {
  enum class Kind { Null, Bool, Number, String, Array, Object } kind = Kind::Null;
  bool boolean = false;
  double number = 0;
  std::string text;  // a string's contents, or a number's text as the file has it
  std::vector<std::pair<std::string, std::unique_ptr<Json>>> members;

  // The member named `key` of an object; nullptr if there is none.
  const Json* find(const std::string& key) const;
};

// What a file is, for messages: its name ("costs file", as in "not a costs file" and
// "costs file PATH cannot be read") and how to make a good one ("write one with
// `logrid calibrate --costs FILE`").
struct JsonFileKind {
  const char* what;
  const char* remedy;
};

// Parses one JSON value; ErrorCode::BadInput for text that is not JSON, naming `origin`,
// the line, what was wrong, and the kind's remedy. Nesting deeper than 16 is refused, and
// so is a key given twice in one object.
Result<std::unique_ptr<Json>> parseJson(const std::string& text, const std::string& origin,
                                        const JsonFileKind& kind);

// A file's whole text; ErrorCode::Environment naming the path and the kind's remedy if it
// cannot be read.
Result<std::string> readTextFile(const std::string& path, const JsonFileKind& kind);

// `text` as a JSON string's contents: quotes, backslashes and control characters
// escaped, so that parseJson reads back exactly `text`.
std::string jsonEscape(const std::string& text);

// The shortest text of a JSON number that reads back as exactly `v` (finite values
// only; independent of the locale). A float is read back exactly by parsing the text
// as a float (std::from_chars on Json::text), not by rounding Json::number.
std::string jsonNumber(double v);
std::string jsonNumber(float v);

}  // namespace logrid::detail
