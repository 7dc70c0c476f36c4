// The core's JSON reader (json_reader.hpp).
#include "json_reader.hpp"

#include <cctype>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "logrid/error.hpp"

namespace logrid::detail {
namespace {

class JsonReader {
 public:
  JsonReader(const std::string& text, const std::string& origin, const JsonFileKind& kind)
      : s_(text), origin_(origin), kind_(kind) {}

  std::unique_ptr<Json> document() {
    auto v = value(0);
    space();
    if (i_ != s_.size()) fail("text after the end of the JSON value");
    return v;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    std::size_t line = 1;
    for (std::size_t k = 0; k < i_ && k < s_.size(); ++k) line += s_[k] == '\n';
    throw Error(ErrorCode::BadInput, origin_ + ": not a " + kind_.what + " (line " +
                                         std::to_string(line) + ": " + what + "); " + kind_.remedy);
  }
  void space() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  bool eat(char c) {
    space();
    if (i_ < s_.size() && s_[i_] == c) {
      ++i_;
      return true;
    }
    return false;
  }
  void expect(char c) {
    if (!eat(c)) fail(std::string("expected '") + c + "'");
  }
  std::string string() {
    expect('"');
    std::string out;
    while (i_ < s_.size() && s_[i_] != '"') {
      char c = s_[i_++];
      if (c == '\\') {
        if (i_ >= s_.size()) break;
        const char e = s_[i_++];
        switch (e) {
          case 'n': c = '\n'; break;
          case 't': c = '\t'; break;
          case 'u':
            if (i_ + 4 > s_.size()) fail("a short \\u escape");
            i_ += 4;
            c = '?';  // names and notes only: no file's value depends on one
            break;
          default: c = e;
        }
      }
      out += c;
    }
    if (i_ >= s_.size()) fail("a string without its closing quote");
    ++i_;
    return out;
  }
  std::unique_ptr<Json> value(int depth) {
    if (depth > 16) fail("nested too deeply");
    space();
    if (i_ >= s_.size()) fail("the text ends where a value was expected");
    auto v = std::make_unique<Json>();
    const char c = s_[i_];
    if (c == '{') {
      ++i_;
      v->kind = Json::Kind::Object;
      if (eat('}')) return v;
      do {
        space();
        std::string key = string();
        expect(':');
        v->members.emplace_back(std::move(key), value(depth + 1));
      } while (eat(','));
      expect('}');
    } else if (c == '[') {
      ++i_;
      v->kind = Json::Kind::Array;
      if (eat(']')) return v;
      do {
        value(depth + 1);
      } while (eat(','));
      expect(']');
    } else if (c == '"') {
      v->kind = Json::Kind::String;
      v->text = string();
    } else if (s_.compare(i_, 4, "true") == 0 || s_.compare(i_, 5, "false") == 0) {
      v->kind = Json::Kind::Bool;
      v->boolean = s_[i_] == 't';
      i_ += v->boolean ? 4 : 5;
    } else if (s_.compare(i_, 4, "null") == 0) {
      i_ += 4;
    } else {
      const char* begin = s_.c_str() + i_;
      char* end = nullptr;
      v->number = std::strtod(begin, &end);
      if (end == begin) fail("expected a value");
      v->kind = Json::Kind::Number;
      i_ += std::size_t(end - begin);
    }
    return v;
  }

  const std::string& s_;
  const std::string& origin_;
  const JsonFileKind& kind_;
  std::size_t i_ = 0;
};

}  // namespace

const Json* Json::find(const std::string& key) const {
  for (const auto& m : members) {
    if (m.first == key) return m.second.get();
  }
  return nullptr;
}

std::unique_ptr<Json> parseJson(const std::string& text, const std::string& origin,
                                const JsonFileKind& kind) {
  return JsonReader(text, origin, kind).document();
}

std::string readTextFile(const std::string& path, const JsonFileKind& kind) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw Error(ErrorCode::Environment, std::string(kind.what) + " " + path +
                                            " cannot be read; check the path, or " + kind.remedy);
  }
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string jsonEscape(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += static_cast<unsigned char>(c) < 0x20 ? ' ' : c;
  }
  return out;
}

}  // namespace logrid::detail
