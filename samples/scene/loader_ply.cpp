// PLY files checked before assimp reads them (loader_detail.hpp).
//
// Assimp 5.2's PLY importer trusts its input. What it does with a file that bends or
// breaks the format was found by experiment, file by file (the cases live in
// tests/unit/loader_test.cpp; tests/fuzz/loader_fuzz_test.cpp keeps mutating valid
// files). This check splits lines and words as assimp does, and
//
// refuses what assimp would hang or crash on, or read into wrong geometry without a word:
//  * no "end_header" line (in the first 1 MiB): its header reader loops for ever;
//  * an element declared twice: a heap overflow (assimp issue 5729);
//  * an element count above 2^32 - 1, or counts (of instances or of list values) larger
//    than the data holds: it loops or allocates that often, or reads on into the next
//    line or the next element;
//  * a line among an element's properties that is not a property of a type assimp
//    knows (a comment, free text, a line of blanks, a property of an unknown type) when
//    more properties follow: assimp ends the element's property list at that line and
//    drops the properties after it;
//  * a property declared twice (the second one's values win) or without a name;
//  * NUL, lone CR or form feed anywhere in the header, other control bytes outside
//    comments: assimp ends lines at some of them, and whether that drops properties or
//    loops depends on the line after it;
//  * ASCII data: a line with fewer values than its element declares (assimp takes 0 or
//    reads on into the next line), a value it would read only in part ("4.0" as a list
//    count, "1.2.3", "1e5.5"), a line of blanks (read as an instance), control bytes;
//  * binary data: CR LF line ends in the header, or 0x0A as the first data byte (both
//    read one byte off), a property of an unknown type (its size is unknown), negative
//    list counts;
// and, with a clearer message than assimp's, what assimp refuses anyway: a first line
// other than "ply", no format (or an unknown one) on line 2, a malformed element line;
//
// warns about what assimp reads correctly although the file bends the format:
//  * a header line that is no PLY keyword, where no property follows it in its element
//    (exporters of Blender 2.4x wrote "Created by Blender3D 245 - www.blender.org, ..."
//    without "comment"), and a property before the first element (ignored);
//  * extra words after an element count, a property name or end_header; digits followed
//    by junk as an element count ("5x": 5); a second format line (ignored);
//  * in ASCII files, a last property of an unknown type (ignored, with its values), more
//    values on a data line than its element declares (the rest of the line is ignored),
//    empty data lines (skipped), decimal commas ("1,5": 1.5), anything after the last
//    element (ignored); in binary files, bytes after the last element;
//
// and passes without a word what the format allows: non-ASCII text in comments, CR LF
// line ends in ASCII files, tabs, numbers such as "1.", ".5" and "1E3", NaN and infinite
// values (which checkRawScene then refuses, naming the vertex).
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "scene/loader_detail.hpp"

namespace logrid::samples::load {
namespace {

namespace fs = std::filesystem;

struct PlyProperty {
  std::string name;
  bool list = false;
  char count_kind = 'u';  // of the list count: 'i', 'u' or 'f' (floating point)
  int count_size = 0;     // bytes
  char kind = 'f';        // of the values: 'i', 'u' or 'f'
  int size = 0;           // bytes
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
  // A last property of a type assimp does not know (ASCII only): assimp ignores it, so
  // the values after the known properties are extra.
  bool ignores_last = false;
};

enum class PlyFormat { Ascii, BinaryLittleEndian, BinaryBigEndian };

struct PlyHeader {
  PlyFormat format = PlyFormat::Ascii;
  std::vector<PlyElement> elements;
  std::uint64_t data_offset = 0;  // first byte after the end_header line
};

// The warnings of one file, one per kind: its message, the first place and how many.
class PlyNotes {
 public:
  void add(const std::string& message, const std::string& where) {
    for (Note& note : notes_) {
      if (note.message == message) {
        ++note.count;
        return;
      }
    }
    notes_.push_back({message, where, 1});
  }
  void emit(const Warn& warn) const {
    for (const Note& note : notes_) {
      warn(note.message + (note.count == 1 ? " (" + note.first + ")"
                                           : " (" + std::to_string(note.count) + " times, first " +
                                                 note.first + ")"));
    }
  }

 private:
  struct Note {
    std::string message;
    std::string first;
    std::uint64_t count;
  };
  std::vector<Note> notes_;
};

// The type names assimp knows.
bool plyType(const std::string& name, char& kind, int& size) {
  static const struct {
    const char* name;
    char kind;
    int size;
  } kTypes[] = {{"char", 'i', 1},  {"int8", 'i', 1},    {"uchar", 'u', 1},  {"uint8", 'u', 1},
                {"short", 'i', 2}, {"int16", 'i', 2},   {"ushort", 'u', 2}, {"uint16", 'u', 2},
                {"int", 'i', 4},   {"int32", 'i', 4},   {"uint", 'u', 4},   {"uint32", 'u', 4},
                {"float", 'f', 4}, {"float32", 'f', 4}, {"double", 'f', 8}, {"float64", 'f', 8}};
  for (const auto& type : kTypes) {
    if (name == type.name) {
      kind = type.kind;
      size = type.size;
      return true;
    }
  }
  return false;
}

// Words separated by spaces and tabs, the only blanks assimp skips.
std::vector<std::string> plyWords(const std::string& line) {
  std::vector<std::string> words;
  const char* const blanks = " \t";
  for (std::size_t w = line.find_first_not_of(blanks); w != std::string::npos;) {
    const std::size_t end = std::min(line.find_first_of(blanks, w), line.size());
    words.push_back(line.substr(w, end - w));
    w = line.find_first_not_of(blanks, end);
  }
  return words;
}

bool isDigit(char c) { return c >= '0' && c <= '9'; }

bool isDigits(const std::string& s, std::size_t from = 0) {
  return s.size() > from && s.find_first_not_of("0123456789", from) == std::string::npos;
}

// The decimal value of the digits of s from `from` up to the first non-digit, saturated
// at 2^64 - 1 (what assimp's strtoul10 reads, without its wrap-around).
std::uint64_t digitsValue(const std::string& s, std::size_t from = 0) {
  constexpr std::uint64_t kMax = std::numeric_limits<std::uint64_t>::max();
  std::uint64_t value = 0;
  for (std::size_t i = from; i < s.size() && isDigit(s[i]); ++i) {
    value = value > (kMax - 9) / 10 ? kMax : value * 10 + std::uint64_t(s[i] - '0');
  }
  return value;
}

bool isControl(char c) { return (c >= 0 && c < 0x20 && c != '\t') || c == 0x7F; }

std::string byteName(char c) {
  static const char* const kHex = "0123456789ABCDEF";
  const auto b = static_cast<unsigned char>(c);
  return std::string("0x") + kHex[b >> 4] + kHex[b & 15];
}

// How a value word reads: entirely as a number of the kind, as one with a decimal comma
// (floating point only, which assimp reads as a decimal point), or not as a whole.
enum class PlyValue { Number, DecimalComma, Bad };

// Integers as assimp's strtoul10/strtol10 read them: digits, with a sign when signed,
// within 32 bits. Floating point as fast_atoreal_move reads it: sign, digits with at
// most one '.' (or ','), at least one digit, an optional exponent; or nan/inf/infinity
// in any case (read, then refused as not finite after parsing).
PlyValue plyValue(const std::string& word, char kind) {
  if (word.empty()) return PlyValue::Bad;
  if (kind == 'u') {
    return isDigits(word) && digitsValue(word) <= 0xFFFFFFFFu ? PlyValue::Number : PlyValue::Bad;
  }
  const std::size_t sign = (word[0] == '-' || word[0] == '+') ? 1 : 0;
  if (kind == 'i') {
    return isDigits(word, sign) && digitsValue(word, sign) <= 0x80000000u ? PlyValue::Number
                                                                          : PlyValue::Bad;
  }
  const std::string rest = lowerCase(word.substr(sign));
  if (rest == "nan" || rest == "inf" || rest == "infinity") return PlyValue::Number;
  std::size_t i = sign;
  bool digits = false, comma = false;
  while (i < word.size() && isDigit(word[i])) ++i, digits = true;
  if (i < word.size() && (word[i] == '.' || word[i] == ',')) {
    comma = word[i] == ',';
    ++i;
    while (i < word.size() && isDigit(word[i])) ++i, digits = true;
  }
  if (!digits) return PlyValue::Bad;
  if (i < word.size() && (word[i] == 'e' || word[i] == 'E')) {
    ++i;
    if (i < word.size() && (word[i] == '-' || word[i] == '+')) ++i;
    if (i == word.size() || !isDigit(word[i])) return PlyValue::Bad;
    while (i < word.size() && isDigit(word[i])) ++i;
  }
  if (i != word.size()) return PlyValue::Bad;
  return comma ? PlyValue::DecimalComma : PlyValue::Number;
}

[[noreturn]] void plyFail(const std::string& path, const std::string& what) {
  fail(ErrorCode::BadInput, path, "is a PLY file that assimp 5.2 cannot read correctly: " + what);
}

// Reads and checks the header, line by line: see the comment at the top.
class PlyHeaderReader {
 public:
  PlyHeaderReader(const std::string& path, PlyHeader& header, PlyNotes& notes)
      : path_(path), header_(header), notes_(notes) {
    constexpr std::size_t kScanBytes = std::size_t{1} << 20;
    std::ifstream in(path, std::ios::binary);
    head_.assign(kScanBytes, '\0');
    in.read(&head_[0], static_cast<std::streamsize>(head_.size()));
    head_.resize(static_cast<std::size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  }

  void read() {
    for (int number = 1;; ++number) {
      const std::string line = nextLine();
      const std::string where = "header line " + std::to_string(number);
      const std::vector<std::string> w = plyWords(line);
      const bool comment = !w.empty() && (w[0] == "comment" || w[0] == "obj_info");
      checkBytes(line, where, comment);
      if (number == 1) {
        if (w.size() != 1 || lowerCase(w[0]) != "ply") fail("the first line is not 'ply'");
      } else if (number == 2) {
        readFormat(w, where);
      } else if (!readLine(line, w, where, comment)) {
        break;  // end_header
      }
    }
    if (has_cr_ && header_.format != PlyFormat::Ascii) {
      fail(
          "a binary PLY header with CR LF line ends (assimp 5.2 reads the data after it one "
          "byte off)");
    }
  }

 private:
  [[noreturn]] void fail(const std::string& what) const { plyFail(path_, what); }

  // The next line without its line end (CR LF noted).
  std::string nextLine() {
    const std::size_t end = head_.find('\n', begin_);
    if (end == std::string::npos) {
      fail(
          "the header has no end_header line in the first 1 MiB (truncated?); assimp would "
          "look for it for ever");
    }
    std::string line = head_.substr(begin_, end - begin_);
    begin_ = end + 1;
    if (!line.empty() && line.back() == '\r') {
      line.pop_back();
      has_cr_ = true;
    }
    return line;
  }

  void checkBytes(const std::string& line, const std::string& where, bool comment) const {
    for (const char c : line) {
      if (c == '\0' || c == '\r' || c == '\f' || (isControl(c) && !comment)) {
        fail(where + " holds the control byte " + byteName(c) +
             " (assimp ends lines at some of them: it may drop properties, or loop looking for "
             "end_header)");
      }
    }
  }

  void readFormat(const std::vector<std::string>& w, const std::string& where) {
    if (w.size() < 2 || w[0] != "format") {
      fail(
          "line 2 is not the format line (assimp requires 'format ascii 1.0' or "
          "'format binary_little_endian 1.0' there)");
    }
    if (w[1] == "ascii") {
      header_.format = PlyFormat::Ascii;
    } else if (w[1] == "binary_little_endian") {
      header_.format = PlyFormat::BinaryLittleEndian;
    } else if (w[1] == "binary_big_endian") {
      header_.format = PlyFormat::BinaryBigEndian;
    } else {
      fail(where + ": unknown format '" + w[1] + "'");
    }
    if (w.size() > 3) notes_.add("extra words after the format (assimp ignores them)", where);
  }

  // A line after the format line; false at end_header.
  bool readLine(const std::string& line, const std::vector<std::string>& w,
                const std::string& where, bool comment) {
    if (w.empty()) {
      // assimp skips an empty line, but a line of blanks ends a property list.
      if (!line.empty()) {
        if (!header_.elements.empty()) interruption_ = where + " (a line of blanks)";
        notes_.add("a header line of blanks (assimp ignores it)", where);
      }
    } else if (comment) {
      if (!header_.elements.empty()) interruption_ = where + " (a comment)";
    } else if (w[0] == "end_header") {
      if (w.size() > 1) notes_.add("extra words after end_header (assimp ignores them)", where);
      header_.data_offset = begin_;
      return false;
    } else if (w[0] == "element") {
      readElement(line, w, where);
    } else if (w[0] == "property") {
      readProperty(line, w, where);
    } else {
      // Any other line, including a second format line: assimp ignores it.
      if (!header_.elements.empty()) interruption_ = where + " ('" + line + "')";
      notes_.add("a header line that is no PLY keyword (assimp ignores it)",
                 where + ", '" + line + "'");
    }
    return true;
  }

  void readElement(const std::string& line, const std::vector<std::string>& w,
                   const std::string& where) {
    if (w.size() < 3 || !isDigit(w[2][0])) {
      fail(where + ": '" + line + "' is not 'element NAME COUNT'");
    }
    const std::uint64_t count = digitsValue(w[2]);
    if (count > 0xFFFFFFFFu) fail(where + ": element count '" + w[2] + "' is not a 32-bit count");
    if (!isDigits(w[2])) {
      notes_.add("an element count followed by other characters (assimp reads the digits)",
                 where + ", '" + w[2] + "'");
    }
    if (w.size() > 3) notes_.add("extra words after an element count (assimp ignores them)", where);
    for (const PlyElement& other : header_.elements) {
      if (other.name == w[1]) {
        fail(where + ": element '" + w[1] +
             "' declared twice (assimp 5.2 overflows a heap buffer)");
      }
    }
    header_.elements.push_back({w[1], count, {}, false});
    interruption_.clear();
  }

  void readProperty(const std::string& line, const std::vector<std::string>& w,
                    const std::string& where) {
    if (header_.elements.empty()) {
      notes_.add("a property before the first element (assimp ignores it)", where);
      return;
    }
    PlyElement& element = header_.elements.back();
    PlyProperty property;
    const bool list = w.size() > 1 && w[1] == "list";
    const std::size_t name_at = list ? 4 : 2;
    if (w.size() <= name_at) fail(where + ": '" + line + "' names no property");
    if (!interruption_.empty() || element.ignores_last) {
      fail(where + ": property '" + w[name_at] + "' of element '" + element.name +
           "' comes after " +
           (element.ignores_last ? "one of a type assimp does not know" : interruption_) +
           ", where assimp ends the element's properties: it would drop this one and read the "
           "data wrongly");
    }
    property.list = list;
    property.name = w[name_at];
    const bool known = list ? plyType(w[2], property.count_kind, property.count_size) &&
                                  plyType(w[3], property.kind, property.size)
                            : plyType(w[1], property.kind, property.size);
    if (!known) {
      if (header_.format != PlyFormat::Ascii) {
        fail(where + ": '" + line +
             "' has a type assimp does not know, so the size of its binary values is unknown");
      }
      notes_.add("a property of a type assimp does not know (ignored, with its values)",
                 where + ", '" + line + "'");
      element.ignores_last = true;
      return;
    }
    if (w.size() > name_at + 1) {
      notes_.add("extra words after a property name (assimp ignores them)", where);
    }
    for (const PlyProperty& other : element.properties) {
      if (other.name == property.name) {
        fail(where + ": property '" + property.name + "' of element '" + element.name +
             "' declared twice");
      }
    }
    element.properties.push_back(property);
  }

  const std::string& path_;
  PlyHeader& header_;
  PlyNotes& notes_;
  std::string head_;       // the first 1 MiB of the file
  std::size_t begin_ = 0;  // of the next line in head_
  bool has_cr_ = false;
  // The line that ended the current element's property list for assimp, if any.
  std::string interruption_;
};

// ASCII: one instance per line, each property's values as words of the line, list
// counts within the line. See the comment at the top for what is refused and why.
void checkPlyAscii(const std::string& path, const PlyHeader& header, PlyNotes& notes) {
  std::ifstream in(path, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(header.data_offset));
  std::string line;
  std::uint64_t number = 0;
  // The next line assimp reads as an instance (it skips empty ones), or false at the end.
  auto nextLine = [&]() {
    while (std::getline(in, line)) {
      ++number;
      if (line.empty()) {
        notes.add("empty data lines (assimp skips them)", "data line " + std::to_string(number));
        continue;
      }
      if (line.back() == '\r') line.pop_back();
      const std::string where = "data line " + std::to_string(number);
      for (const char c : line) {
        if (isControl(c)) {
          plyFail(path, where + " holds the control byte " + byteName(c) +
                            " (assimp reads such lines wrongly or not at all)");
        }
      }
      if (line.find_first_not_of(" \t") == std::string::npos) {
        plyFail(path, where + " holds only blanks (assimp would read it as an instance)");
      }
      return true;
    }
    return false;
  };
  for (const PlyElement& element : header.elements) {
    for (std::uint64_t i = 0; i < element.count; ++i) {
      if (!nextLine()) {
        std::ostringstream out;
        out << "the file ends after " << i << " of " << element.count << " '" << element.name
            << "' lines (truncated?)";
        plyFail(path, out.str());
      }
      const std::vector<std::string> w = plyWords(line);
      const std::string where = "data line " + std::to_string(number) + " ('" + element.name + "')";
      std::size_t next = 0;
      for (const PlyProperty& property : element.properties) {
        std::uint64_t values = 1;
        if (property.list) {
          const std::uint64_t max = property.count_kind == 'f' ? 0xFFFFFFFFu
                                    : property.count_kind == 'u'
                                        ? (std::uint64_t{1} << (8 * property.count_size)) - 1
                                        : (std::uint64_t{1} << (8 * property.count_size - 1)) - 1;
          if (next >= w.size()) plyFail(path, where + ": too few values");
          if (!isDigits(w[next]) || digitsValue(w[next]) > max) {
            plyFail(path,
                    where + ": '" + w[next] + "' is not a count for list '" + property.name + "'");
          }
          values = digitsValue(w[next++]);
          if (values > w.size() - next) {
            std::ostringstream out;
            out << where << ": list '" << property.name << "' declares " << values
                << " values but the line has " << w.size() - next
                << " (assimp would read on into the next line)";
            plyFail(path, out.str());
          }
        }
        for (std::uint64_t v = 0; v < values; ++v, ++next) {
          if (next >= w.size()) {
            plyFail(path, where + ": too few values (assimp would take 0 for the missing ones)");
          }
          const PlyValue value = plyValue(w[next], property.kind);
          if (value == PlyValue::Bad) {
            plyFail(path, where + ": '" + w[next] + "' is not a " +
                              (property.kind == 'f' ? "number" : "32-bit integer") +
                              " as a whole (assimp would read it in part, or not at all)");
          }
          if (value == PlyValue::DecimalComma) {
            notes.add("numbers with a decimal comma (assimp reads them as with a point)",
                      where + ", '" + w[next] + "'");
          }
        }
      }
      if (next != w.size() && !element.ignores_last) {
        notes.add(
            "data lines with more values than their element declares (assimp ignores "
            "the rest of the line)",
            where);
      }
    }
  }
  while (std::getline(in, line)) {
    ++number;
    if (!plyWords(line).empty()) {
      notes.add("data after the last element (assimp ignores it)",
                "data line " + std::to_string(number));
      break;
    }
  }
}

// Binary: the declared instances fit in the file, every list count included.
void checkPlyBinary(const std::string& path, const PlyHeader& header, PlyNotes& notes) {
  std::ifstream in(path, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(header.data_offset));
  std::vector<unsigned char> buffer(std::size_t{1} << 16);
  std::size_t have = 0, at = 0;               // bytes in buffer, read position in it
  std::uint64_t offset = header.data_offset;  // file offset of buffer[at]
  auto available = [&](std::size_t bytes) {   // makes `bytes` bytes available at `at`
    if (have - at >= bytes) return true;
    std::copy(buffer.begin() + static_cast<std::ptrdiff_t>(at),
              buffer.begin() + static_cast<std::ptrdiff_t>(have), buffer.begin());
    have -= at;
    at = 0;
    in.read(reinterpret_cast<char*>(buffer.data() + have),
            static_cast<std::streamsize>(buffer.size() - have));
    have += static_cast<std::size_t>(std::max<std::streamsize>(in.gcount(), 0));
    return have >= bytes;
  };
  auto skip = [&](std::uint64_t bytes) {
    const std::uint64_t in_buffer = std::min<std::uint64_t>(bytes, have - at);
    at += static_cast<std::size_t>(in_buffer);
    offset += bytes;
    if (bytes > in_buffer) {
      at = have = 0;
      in.clear();
      in.seekg(static_cast<std::streamoff>(offset));
    }
  };
  std::error_code ec;
  const std::uintmax_t file_bytes = fs::file_size(path, ec);
  if (ec) fail(ErrorCode::Environment, path, "cannot read its size (" + ec.message() + ")");
  if (file_bytes > header.data_offset && available(1) && buffer[at] == '\n') {
    plyFail(path, "binary data starting with byte 0x0A (assimp 5.2 reads it one byte off)");
  }
  auto truncated = [&](const PlyElement& element, std::uint64_t i) {
    std::ostringstream out;
    out << "the file ends in '" << element.name << "' " << i << " of " << element.count
        << " (truncated, or a corrupt list count)";
    plyFail(path, out.str());
  };
  const bool big_endian = header.format == PlyFormat::BinaryBigEndian;
  for (const PlyElement& element : header.elements) {
    // Without lists every instance has the same size: check them all at once.
    std::uint64_t fixed_size = 0;
    for (const PlyProperty& property : element.properties) {
      fixed_size = property.list ? 0 : fixed_size + std::uint64_t(property.size);
      if (property.list) break;
    }
    if (fixed_size > 0) {
      const std::uint64_t left = file_bytes - std::min<std::uint64_t>(offset, file_bytes);
      if (element.count > left / fixed_size) truncated(element, left / fixed_size);
      skip(element.count * fixed_size);
      continue;
    }
    for (std::uint64_t i = 0; i < element.count; ++i) {
      for (const PlyProperty& property : element.properties) {
        std::uint64_t values = 1;
        if (property.list) {
          const std::size_t n = static_cast<std::size_t>(property.count_size);
          if (offset + n > file_bytes || !available(n)) truncated(element, i);
          std::uint64_t bits = 0;
          for (std::size_t b = 0; b < n; ++b) {
            bits |= std::uint64_t{buffer[at + (big_endian ? n - 1 - b : b)]} << (8 * b);
          }
          if (property.count_kind == 'f') {
            // A floating-point count: a whole number from 0 to 2^32 - 1, or refused.
            double count = 0;
            if (n == 4) {
              float f = 0;
              const auto low = static_cast<std::uint32_t>(bits);
              std::memcpy(&f, &low, 4);
              count = f;
            } else {
              std::memcpy(&count, &bits, 8);
            }
            if (!(count >= 0 && count <= 4294967295.0) ||
                count != static_cast<double>(static_cast<std::uint64_t>(count))) {
              plyFail(path, "a floating-point list count for '" + property.name +
                                "' that is no whole number from 0 to 2^32 - 1");
            }
            bits = static_cast<std::uint64_t>(count);
          } else if (property.count_kind == 'i' && (bits >> (8 * n - 1)) != 0) {
            plyFail(path, "a negative list count for '" + property.name + "'");
          }
          skip(n);
          values = bits;
        }
        const std::uint64_t bytes = values * std::uint64_t(property.size);
        if (bytes > file_bytes - std::min<std::uint64_t>(offset, file_bytes)) {
          truncated(element, i);
        }
        skip(bytes);
      }
    }
  }
  if (offset < file_bytes) {
    notes.add("bytes after the last element (assimp ignores them)",
              std::to_string(file_bytes - offset) + " bytes");
  }
}

}  // namespace

void checkPly(const std::string& path, const Warn& warn) {
  // Only files named .ply reach assimp's PLY importer (loader.cpp, restrictImporters).
  if (lowerCase(fs::path(path).extension().string()) != ".ply") return;
  PlyHeader header;
  PlyNotes notes;
  PlyHeaderReader(path, header, notes).read();
  // Every instance takes at least a line or a byte: refuse absurd counts before walking.
  std::error_code ec;
  const std::uintmax_t bytes = fs::file_size(path, ec);
  const std::uint64_t data = ec || bytes <= header.data_offset ? 0 : bytes - header.data_offset;
  std::uint64_t instances = 0;
  // No overflow: counts are 32-bit, and a 1 MiB header has fewer than 2^17 elements.
  for (const PlyElement& element : header.elements) instances += element.count;
  if (instances > data) {
    std::ostringstream out;
    out << "the header declares " << instances << " element instances but only " << data
        << " bytes follow it (truncated?)";
    plyFail(path, out.str());
  }
  if (header.format == PlyFormat::Ascii) {
    checkPlyAscii(path, header, notes);
  } else {
    checkPlyBinary(path, header, notes);
  }
  notes.emit(warn);
}

}  // namespace logrid::samples::load
