#include "viewer/script.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "logrid/error.hpp"

namespace logrid::viewer {
namespace {

// Limits that keep a hostile script from asking for absurd work.
constexpr std::size_t kMaxFrame = 10000000;
constexpr double kMaxCoordinate = 1e6;
constexpr int kMaxWindowSide = 16384;
constexpr std::size_t kMaxScriptBytes = std::size_t{16} << 20;

class LineParser {
 public:
  LineParser(const std::string& name, std::size_t line, const std::string& text)
      : name_(name), line_(line), in_(text) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw Error(ErrorCode::BadInput,
                "script " + name_ + " line " + std::to_string(line_) + ": " + what);
  }
  std::string word(const char* what) {
    std::string w;
    if (!(in_ >> w)) fail(std::string("expected ") + what);
    return w;
  }
  double number(const char* what, double lo, double hi) {
    const std::string w = word(what);
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(w, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != w.size() || !std::isfinite(v) || v < lo || v > hi) {
      std::ostringstream out;
      out << what << " '" << w << "' is invalid; use a number from " << lo << " to " << hi;
      fail(out.str());
    }
    return v;
  }
  std::size_t count(const char* what, std::size_t hi) {
    const double v = number(what, 0, double(hi));
    if (v != std::floor(v)) fail(std::string(what) + " must be a whole number");
    return std::size_t(v);
  }
  int key() {
    const std::string w = word("a key name");
    const auto k = keyFromName(w);
    if (!k) fail("unknown key '" + w + "'; use " + keyNameList());
    return *k;
  }
  int button() {
    const std::string w = word("a mouse button");
    const auto b = mouseButtonFromName(w);
    if (!b) fail("unknown mouse button '" + w + "'; use left, right or middle");
    return *b;
  }
  std::string quoted() {
    in_ >> std::ws;
    std::string rest;
    std::getline(in_, rest);
    if (rest.size() < 2 || rest.front() != '"' || rest.back() != '"') {
      fail("text must be one string in double quotes, e.g. text \"32\"");
    }
    return rest.substr(1, rest.size() - 2);
  }
  void end() {
    std::string extra;
    if (in_ >> extra) fail("unexpected '" + extra + "' at the end of the line");
  }

 private:
  const std::string& name_;
  std::size_t line_;
  std::istringstream in_;
};

InputEvent make(EventType type, int code = 0, double x = 0, double y = 0) {
  InputEvent e;
  e.type = type;
  e.code = code;
  e.x = x;
  e.y = y;
  return e;
}

// Appends the code points of UTF-8 text (invalid bytes are taken as Latin-1).
void appendUtf8(const std::string& s, std::vector<std::uint32_t>& out) {
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    int n = c < 0x80 ? 0 : (c >> 5) == 6 ? 1 : (c >> 4) == 14 ? 2 : (c >> 3) == 30 ? 3 : -1;
    std::uint32_t cp = n == 0 ? c : n == 1 ? (c & 0x1Fu) : n == 2 ? (c & 0x0Fu) : (c & 0x07u);
    bool ok = n >= 0 && i + std::size_t(n) < s.size() + (n == 0 ? 1 : 0);
    for (int k = 1; ok && k <= n; ++k) {
      const auto d = static_cast<unsigned char>(s[i + std::size_t(k)]);
      ok = (d >> 6) == 2;
      cp = (cp << 6) | (d & 0x3Fu);
    }
    if (!ok) n = 0, cp = c;
    out.push_back(cp);
    i += std::size_t(n) + 1;
  }
}

}  // namespace

Script Script::fromFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw Error(ErrorCode::Environment,
                "script " + path + ": cannot be read (check that the file exists)");
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (text.str().size() > kMaxScriptBytes) {
    throw Error(ErrorCode::BadInput, "script " + path +
                                         ": larger than 16 MiB; a script is a "
                                         "few lines per second of flight");
  }
  return fromText(text.str(), path);
}

Script Script::fromText(const std::string& text, const std::string& name) {
  Script script;
  std::istringstream lines(text);
  std::size_t line_number = 0, previous = 0;
  for (std::string line; std::getline(lines, line);) {
    ++line_number;
    if (const auto hash = line.find('#'); hash != std::string::npos) {
      // A '#' inside a quoted text argument is text, not a comment.
      const auto quote = line.find('"');
      if (quote == std::string::npos || hash < quote) line.erase(hash);
    }
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    LineParser p(name, line_number, line);
    const std::size_t f = p.count("frame number", kMaxFrame);
    if (f < previous) {
      p.fail("frame " + std::to_string(f) + " comes after frame " + std::to_string(previous) +
             "; frames must not decrease");
    }
    previous = f;
    const std::string type = p.word(
        "an event (key, key-down, key-up, mouse-move, mouse-down, "
        "mouse-up, click, drag, scroll, text, resize)");
    auto add = [&](std::size_t frame, const InputEvent& e) {
      script.events_.push_back({frame, e});
      script.last_frame_ = std::max(script.last_frame_, frame);
    };
    if (type == "key") {
      const int k = p.key();
      add(f, make(EventType::KeyDown, k));
      add(f + 1, make(EventType::KeyUp, k));
    } else if (type == "key-down") {
      add(f, make(EventType::KeyDown, p.key()));
    } else if (type == "key-up") {
      add(f, make(EventType::KeyUp, p.key()));
    } else if (type == "mouse-move") {
      const double x = p.number("x", -kMaxCoordinate, kMaxCoordinate);
      add(f, make(EventType::MouseMove, 0, x, p.number("y", -kMaxCoordinate, kMaxCoordinate)));
    } else if (type == "mouse-down") {
      add(f, make(EventType::MouseDown, p.button()));
    } else if (type == "mouse-up") {
      add(f, make(EventType::MouseUp, p.button()));
    } else if (type == "click") {
      const int b = p.button();
      const double x = p.number("x", -kMaxCoordinate, kMaxCoordinate);
      add(f, make(EventType::MouseMove, 0, x, p.number("y", -kMaxCoordinate, kMaxCoordinate)));
      add(f, make(EventType::MouseDown, b));
      add(f + 1, make(EventType::MouseUp, b));
    } else if (type == "drag") {
      const int b = p.button();
      const double dx = p.number("dx", -kMaxCoordinate, kMaxCoordinate);
      const double dy = p.number("dy", -kMaxCoordinate, kMaxCoordinate);
      const std::size_t n = p.count("frames", 100000);
      if (n < 1) p.fail("a drag lasts at least 1 frame");
      add(f, make(EventType::MouseDown, b));
      for (std::size_t i = 1; i <= n; ++i) {
        add(f + i, make(EventType::MouseMoveBy, 0, dx / double(n), dy / double(n)));
      }
      add(f + n + 1, make(EventType::MouseUp, b));
    } else if (type == "scroll") {
      add(f, make(EventType::Scroll, 0, 0, p.number("steps", -1000, 1000)));
    } else if (type == "text") {
      std::vector<std::uint32_t> cps;
      appendUtf8(p.quoted(), cps);
      for (std::uint32_t cp : cps) {
        InputEvent e = make(EventType::Char);
        e.codepoint = cp;
        add(f, e);
      }
      continue;  // quoted() consumed the rest of the line
    } else if (type == "resize") {
      const double w = p.number("width", 1, kMaxWindowSide);
      const double h = p.number("height", 1, kMaxWindowSide);
      if (w != std::floor(w) || h != std::floor(h)) p.fail("window sides are whole pixels");
      add(f, make(EventType::Resize, 0, w, h));
    } else {
      p.fail("unknown event '" + type +
             "'; use key, key-down, key-up, mouse-move, mouse-down, mouse-up, click, drag, "
             "scroll, text or resize");
    }
    p.end();
  }
  if (script.events_.empty()) {
    throw Error(ErrorCode::BadInput,
                "script " + name + ": no events; write one per line, e.g. '10 key Escape'");
  }
  std::stable_sort(script.events_.begin(), script.events_.end(),
                   [](const ScriptEvent& a, const ScriptEvent& b) { return a.frame < b.frame; });
  return script;
}

std::vector<InputEvent> Script::eventsAt(std::size_t frame) const {
  std::vector<InputEvent> out;
  const auto first =
      std::lower_bound(events_.begin(), events_.end(), frame,
                       [](const ScriptEvent& e, std::size_t f) { return e.frame < f; });
  for (auto it = first; it != events_.end() && it->frame == frame; ++it) out.push_back(it->event);
  return out;
}

}  // namespace logrid::viewer
