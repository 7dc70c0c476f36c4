#include "cli/option_checks.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstdlib>
#include <functional>
#include <sstream>

#include "cli/values.hpp"
#include "logrid/error.hpp"

namespace logrid::samples {
namespace {

enum class Parsed { Number, NotANumber, NotWhole, Overflow };

// A real number as strtod reads it, the whole text (no blanks around it).
Parsed parseReal(const std::string& text, double& out) {
  if (text.empty() || std::isspace(static_cast<unsigned char>(text[0]))) return Parsed::NotANumber;
  errno = 0;
  char* end = nullptr;
  out = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size()) return Parsed::NotANumber;
  // ERANGE with a tiny result is an underflow to (nearly) zero: a number like any other.
  if (errno == ERANGE && std::isinf(out)) return Parsed::Overflow;
  return Parsed::Number;
}

// Decimal digits with an optional sign; a sign on an unsigned type allows only "-0".
template <typename T>
Parsed parseWhole(const std::string& text, T& out) {
  std::size_t first = !text.empty() && (text[0] == '+' || text[0] == '-') ? 1 : 0;
  const bool digits =
      text.size() > first && std::all_of(text.begin() + std::ptrdiff_t(first), text.end(),
                                         [](char c) { return c >= '0' && c <= '9'; });
  if (!digits) {
    double real = 0;
    return parseReal(text, real) == Parsed::NotANumber ? Parsed::NotANumber : Parsed::NotWhole;
  }
  const bool negative = text[0] == '-';
  if (std::is_signed_v<T> && negative) first = 0;  // from_chars reads the minus itself
  if (!std::is_signed_v<T> && negative) {
    const bool zero = text.find_first_not_of('0', 1) == std::string::npos;
    if (!zero) return Parsed::Overflow;  // below every unsigned range
  }
  const char* begin = text.data() + first;
  const auto [end, error] = std::from_chars(begin, text.data() + text.size(), out);
  if (error == std::errc::result_out_of_range) return Parsed::Overflow;
  return error == std::errc() && end == text.data() + text.size() ? Parsed::Number
                                                                  : Parsed::NotANumber;
}

Parsed parse(const std::string& text, std::uint32_t& out) { return parseWhole(text, out); }
Parsed parse(const std::string& text, unsigned long& out) { return parseWhole(text, out); }
Parsed parse(const std::string& text, unsigned long long& out) { return parseWhole(text, out); }
Parsed parse(const std::string& text, int& out) { return parseWhole(text, out); }
Parsed parse(const std::string& text, double& out) { return parseReal(text, out); }
Parsed parse(const std::string& text, float& out) {
  double real = 0;
  const Parsed p = parseReal(text, real);
  if (p != Parsed::Number) return p;
  if (std::isfinite(real) && std::abs(real) > double(std::numeric_limits<float>::max())) {
    return Parsed::Overflow;
  }
  out = float(real);
  return Parsed::Number;
}

template <typename T>
std::string numberText(T v) {
  if constexpr (std::is_integral_v<T>) {
    return std::to_string(v);
  } else {
    const double d = double(v);
    if (std::isinf(d)) return d > 0 ? "inf" : "-inf";
    std::ostringstream out;
    out.precision(std::numeric_limits<T>::max_digits10);
    if (d == std::floor(d) && std::abs(d) < 1e15) {
      out << static_cast<long long>(d);
    } else {
      out << double(v);
    }
    return out.str();
  }
}

// `check` on the whole text, or on each item of a comma-separated list.
CLI::Validator textCheck(const std::string& name, bool list,
                         std::function<std::string(const std::string&)> check) {
  return CLI::Validator(
      [list, check](std::string& text) {
        if (!list) return check(text);
        for (const std::string& item : splitList(text)) {
          const std::string problem = check(item);
          if (!problem.empty()) return "in '" + text + "', " + problem;
        }
        return std::string();
      },
      "", name);
}

// The message of the logrid::Error that `parse` throws, if it does.
std::function<std::string(const std::string&)> parsed(void (*parse)(const std::string&)) {
  return [parse](const std::string& text) {
    try {
      parse(text);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
}

}  // namespace

bool parseNumber(const std::string& text, std::uint32_t& out) {
  return parse(text, out) == Parsed::Number;
}
bool parseNumber(const std::string& text, unsigned long& out) {
  return parse(text, out) == Parsed::Number;
}
bool parseNumber(const std::string& text, unsigned long long& out) {
  return parse(text, out) == Parsed::Number;
}
bool parseNumber(const std::string& text, int& out) { return parse(text, out) == Parsed::Number; }
bool parseNumber(const std::string& text, double& out) {
  return parse(text, out) == Parsed::Number;
}
bool parseNumber(const std::string& text, float& out) { return parse(text, out) == Parsed::Number; }

template <typename T>
bool NumberRange<T>::contains(T v) const {
  if constexpr (std::is_floating_point_v<T>) {
    if (std::isnan(v)) return false;
  }
  if (!only.empty()) return std::find(only.begin(), only.end(), v) != only.end();
  const bool above_min = min_open ? v > min : v >= min;
  const bool below_max = max_open ? v < max : v <= max;
  return above_min && below_max;
}

template <typename T>
std::string NumberRange<T>::text() const {
  if (!only.empty()) {
    std::string out = "{";
    for (std::size_t i = 0; i < only.size(); ++i) out += (i ? ", " : "") + numberText(only[i]);
    return out + "}";
  }
  return (min_open ? "(" : "[") + numberText(min) + ", " + numberText(max) + (max_open ? ")" : "]");
}

template <typename T>
std::string numberProblem(const std::string& text, const NumberRange<T>& range) {
  T value{};
  switch (parse(text, value)) {
    case Parsed::NotANumber: return "'" + text + "' is not a number in range " + range.text();
    case Parsed::NotWhole: return "'" + text + "' is not a whole number in range " + range.text();
    case Parsed::Overflow: return "'" + text + "' is out of range " + range.text();
    case Parsed::Number: break;
  }
  return range.contains(value) ? std::string() : "'" + text + "' is out of range " + range.text();
}

template <typename T>
CLI::Validator numberListCheck(const NumberRange<T>& range) {
  return textCheck(std::is_integral_v<T> ? kNumberListCheck : kRealListCheck, true,
                   [range](const std::string& item) { return numberProblem(item, range); });
}

CLI::Validator sizeCheck() {
  return textCheck(kSizeCheck, false, parsed([](const std::string& t) { parseSize(t); }));
}
CLI::Validator sizeListCheck() {
  return textCheck(kSizeListCheck, true, parsed([](const std::string& t) { parseSize(t); }));
}
CLI::Validator lookaheadCheck() {
  return textCheck(kLookaheadCheck, false, parsed([](const std::string& t) { parseLookahead(t); }));
}
CLI::Validator lookaheadListCheck() {
  return textCheck(kLookaheadListCheck, true,
                   parsed([](const std::string& t) { parseLookahead(t); }));
}

template struct NumberRange<std::uint32_t>;
template struct NumberRange<unsigned long>;
template struct NumberRange<unsigned long long>;
template struct NumberRange<int>;
template struct NumberRange<double>;
template struct NumberRange<float>;
template std::string numberProblem(const std::string&, const NumberRange<std::uint32_t>&);
template std::string numberProblem(const std::string&, const NumberRange<unsigned long>&);
template std::string numberProblem(const std::string&, const NumberRange<unsigned long long>&);
template std::string numberProblem(const std::string&, const NumberRange<int>&);
template std::string numberProblem(const std::string&, const NumberRange<double>&);
template std::string numberProblem(const std::string&, const NumberRange<float>&);
template CLI::Validator numberListCheck(const NumberRange<std::uint32_t>&);
template CLI::Validator numberListCheck(const NumberRange<double>&);

}  // namespace logrid::samples
