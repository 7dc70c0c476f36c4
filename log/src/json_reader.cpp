// The core's JSON reader (json_reader.hpp).
#include "json_reader.hpp"

#include <cctype>
#include <charconv>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "logrid/error.hpp"

namespace logrid::detail {
namespace {

class JsonReader {
 public:
  JsonReader(const std::string& text, const std::string& origin, const JsonFileKind& kind)
      : s_(text), origin_(origin), kind_(kind) {}

  Result<std::unique_ptr<Json>> document() {
    auto v = value(0);
    space();
    if (i_ != s_.size()) fail("text after the end of the JSON value");
    if (error_.failed()) return error_.take();
    return v;
  }

 private:
  // Keeps the first error and moves to the end of the text, where every step stops (each
  // caller returns after it).
  void fail(const std::string& what) {
    std::size_t line = 1;
    for (std::size_t k = 0; k < i_ && k < s_.size(); ++k) line += s_[k] == '\n';
    error_.note(Status(ErrorCode::BadInput, origin_ + ": not a " + kind_.what + " (line " +
                                                std::to_string(line) + ": " + what + "); " +
                                                kind_.remedy));
    i_ = s_.size();
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
  // JSON's escapes (RFC 8259 §7): \uXXXX as UTF-8, a surrogate pair as one code point,
  // a lone surrogate as its own three bytes. Control characters are taken as they are
  // (jsonEscape writes them escaped), so that every string reads back as written.
  std::string string() {
    expect('"');
    std::string out;
    for (;;) {
      if (i_ >= s_.size()) {
        fail("a string without its closing quote");
        return out;
      }
      const char c = s_[i_++];
      if (c == '"') return out;
      if (c != '\\') {
        out += c;
        continue;
      }
      if (i_ >= s_.size()) {
        fail("a string without its closing quote");
        return out;
      }
      const char e = s_[i_++];
      switch (e) {
        case '"':
        case '\\':
        case '/': out += e; break;
        case 'b': out += '\b'; break;
        case 'f': out += '\f'; break;
        case 'n': out += '\n'; break;
        case 'r': out += '\r'; break;
        case 't': out += '\t'; break;
        case 'u': appendUtf8(out, codePoint()); break;
        default: fail(std::string("an unknown escape \\") + e + " in a string"); return out;
      }
    }
  }
  unsigned hex4() {
    if (i_ + 4 > s_.size()) {
      fail("a short \\u escape");
      return 0;
    }
    unsigned v = 0;
    for (int k = 0; k < 4; ++k) {
      const char h = s_[i_++];
      v <<= 4;
      if (h >= '0' && h <= '9') {
        v |= unsigned(h - '0');
      } else if (h >= 'a' && h <= 'f') {
        v |= unsigned(h - 'a' + 10);
      } else if (h >= 'A' && h <= 'F') {
        v |= unsigned(h - 'A' + 10);
      } else {
        fail("a \\u escape that is not four hexadecimal digits");
        return 0;
      }
    }
    return v;
  }
  // After "\u": one code point (a high surrogate and the low one escaped after it: one).
  unsigned codePoint() {
    const unsigned u = hex4();
    if (u >= 0xD800 && u < 0xDC00 && s_.compare(i_, 2, "\\u") == 0) {
      const std::size_t at = i_;
      i_ += 2;
      const unsigned low = hex4();
      if (low >= 0xDC00 && low < 0xE000) return 0x10000 + ((u - 0xD800) << 10) + (low - 0xDC00);
      i_ = at;  // not a pair: the second escape is read on its own
    }
    return u;
  }
  static void appendUtf8(std::string& out, unsigned u) {
    if (u < 0x80) {
      out += char(u);
    } else if (u < 0x800) {
      out += char(0xC0 | (u >> 6));
      out += char(0x80 | (u & 0x3F));
    } else if (u < 0x10000) {
      out += char(0xE0 | (u >> 12));
      out += char(0x80 | ((u >> 6) & 0x3F));
      out += char(0x80 | (u & 0x3F));
    } else {
      out += char(0xF0 | (u >> 18));
      out += char(0x80 | ((u >> 12) & 0x3F));
      out += char(0x80 | ((u >> 6) & 0x3F));
      out += char(0x80 | (u & 0x3F));
    }
  }
  // A JSON number (RFC 8259 §6: no "+", no leading zeros, no "nan", "inf" or hexadecimal),
  // converted without the C locale (std::from_chars: a decimal point is '.' whatever the
  // application's locale). Its text is kept for a reader that wants a float (one rounding).
  void number(Json& v) {
    const std::size_t begin = i_;
    const auto digits = [this] {
      const std::size_t from = i_;
      while (i_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[i_]))) ++i_;
      return i_ > from;
    };
    if (i_ < s_.size() && s_[i_] == '-') ++i_;
    if (i_ < s_.size() && s_[i_] == '0') {
      ++i_;
    } else if (!digits()) {
      i_ = begin;
      fail("expected a value");
      return;
    }
    if (i_ < s_.size() && s_[i_] == '.') {
      ++i_;
      if (!digits()) {
        fail("a number without digits after its '.'");
        return;
      }
    }
    if (i_ < s_.size() && (s_[i_] == 'e' || s_[i_] == 'E')) {
      ++i_;
      if (i_ < s_.size() && (s_[i_] == '+' || s_[i_] == '-')) ++i_;
      if (!digits()) {
        fail("a number without digits in its exponent");
        return;
      }
    }
    v.kind = Json::Kind::Number;
    v.text = s_.substr(begin, i_ - begin);
    const std::from_chars_result r =
        std::from_chars(v.text.data(), v.text.data() + v.text.size(), v.number);
    if (r.ec != std::errc() || r.ptr != v.text.data() + v.text.size()) {
      fail("the number " + v.text + " is beyond a double's range");
    }
  }
  // After a failure: a null value, and the text is at its end.
  std::unique_ptr<Json> value(int depth) {
    auto v = std::make_unique<Json>();
    if (depth > 16) {
      fail("nested too deeply");
      return v;
    }
    space();
    if (i_ >= s_.size()) {
      fail("the text ends where a value was expected");
      return v;
    }
    const char c = s_[i_];
    if (c == '{') {
      ++i_;
      v->kind = Json::Kind::Object;
      if (eat('}')) return v;
      do {
        space();
        std::string key = string();
        // One meaning per key: readers would otherwise take the first or the last.
        if (v->find(key)) {
          fail("the key \"" + key + "\" twice in one object");
          return v;
        }
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
      number(*v);
    }
    return v;
  }

  const std::string& s_;
  const std::string& origin_;
  const JsonFileKind& kind_;
  std::size_t i_ = 0;
  FirstError error_;
};

}  // namespace

const Json* Json::find(const std::string& key) const {
  for (const auto& m : members) {
    if (m.first == key) return m.second.get();
  }
  return nullptr;
}

Result<std::unique_ptr<Json>> parseJson(const std::string& text, const std::string& origin,
                                        const JsonFileKind& kind) {
  return JsonReader(text, origin, kind).document();
}

Result<std::string> readTextFile(const std::string& path, const JsonFileKind& kind) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    return Status(ErrorCode::Environment, std::string(kind.what) + " " + path +
                                              " cannot be read; check the path, or " + kind.remedy);
  }
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string jsonEscape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\b': out += "\\b"; break;
      case '\f': out += "\\f"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char escape[8];
          std::snprintf(escape, sizeof escape, "\\u%04x", unsigned(static_cast<unsigned char>(c)));
          out += escape;
        } else {
          out += c;
        }
    }
  }
  return out;
}

namespace {

template <typename T>
std::string shortest(T v) {
  char text[64];
  const std::to_chars_result r = std::to_chars(text, text + sizeof text, v);
  return std::string(text, r.ptr);
}

}  // namespace

std::string jsonNumber(double v) { return shortest(v); }
std::string jsonNumber(float v) { return shortest(v); }

}  // namespace logrid::detail
