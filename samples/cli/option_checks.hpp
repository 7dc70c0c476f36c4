// The one place the logrid commands check a number typed on the command line.
//
// Every numeric option is added through addNumber() (a number), or checked by
// numberListCheck() (a comma-separated list of numbers) or by one of the checks of text
// that holds numbers (sizeCheck(), lookaheadCheck() and their lists). Each states its valid
// values in its help text, as "range [1, 10000000]" in interval notation ("(0, 180)"
// excludes both ends, "{32, 64}" is a set), and refuses anything else while the command
// line is parsed:
// not a number, NaN, an infinity, a value below or above the range (negative or zero where
// that means nothing), a fraction for a whole number, and a value that overflows the
// option's type. A refusal is a usage error (exit 2) whose message names the option, the
// value and the range:
//   --frames: '0' is out of range [1, 10000000]
// What depends on other settings (the far plane beyond the near one, a row stride within
// the tile) is left to the library's validators (validateCullerDesc() and the others),
// which runConfig() calls.
#pragma once

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace logrid::samples {

// The values a numeric option takes: from `min` to `max`, either end excluded when open,
// or, when `only` is not empty, exactly the values listed.
template <typename T>
struct NumberRange {
  T min = std::numeric_limits<T>::lowest();
  T max = std::numeric_limits<T>::max();
  bool min_open = false;
  bool max_open = false;
  std::vector<T> only;

  bool contains(T v) const;
  // "[1, 10000000]", "(0, 180)", "[0, inf]", "{32, 64}".
  std::string text() const;
};

// A range from min to max with both ends included, e.g. closed(1u, 64u).
template <typename T>
NumberRange<T> closed(T min, T max) {
  return {min, max, false, false, {}};
}
// Real numbers above `min` (excluded) up to `max` (included; excluded when infinite).
inline NumberRange<double> above(double min, double max = INFINITY) {
  return {min, max, true, std::isinf(max), {}};
}
// Exactly these values, e.g. oneOf<std::uint32_t>({32, 64}).
template <typename T>
NumberRange<T> oneOf(std::vector<T> values) {
  return {T{}, T{}, false, false, std::move(values)};
}

// Parses `text` as a T: decimal digits (with a sign for signed types) for whole numbers;
// for reals what strtod reads, including "nan" and "inf" (which the range then judges).
// False when the text is not such a number as a whole, or overflows T.
bool parseNumber(const std::string& text, std::uint32_t& out);
bool parseNumber(const std::string& text, unsigned long& out);
bool parseNumber(const std::string& text, unsigned long long& out);
bool parseNumber(const std::string& text, int& out);
bool parseNumber(const std::string& text, double& out);
bool parseNumber(const std::string& text, float& out);

// Empty when `text` is a number in `range`, else "'TEXT' is out of range [1, 64]" (or
// "is not a number ...", "is not a whole number ...").
template <typename T>
std::string numberProblem(const std::string& text, const NumberRange<T>& range);

// The names of the checks below (CLI::Option::get_validator finds them by it); the
// command-line test feeds each option that carries one the values it must refuse.
inline const std::string kNumberCheck = "number";
inline const std::string kNumberListCheck = "numbers";
inline const std::string kRealListCheck = "real numbers";  // numberListCheck of a real type
inline const std::string kSizeCheck = "size";
inline const std::string kSizeListCheck = "sizes";
inline const std::string kLookaheadCheck = "lookahead";
inline const std::string kLookaheadListCheck = "lookaheads";

// Adds `--name` bound to `value`, with "; range ..." appended to `help` and the range
// checked when the command line is parsed.
template <typename T>
CLI::Option* addNumber(CLI::App& app, const std::string& name, T& value,
                       const NumberRange<T>& range, const std::string& help) {
  static_assert(std::is_arithmetic_v<T>, "addNumber: numbers only");
  CLI::Validator check([range](std::string& text) { return numberProblem(text, range); }, "",
                       kNumberCheck);
  return app.add_option(name, value, help + "; range " + range.text())->check(check);
}

// A check for a comma-separated list of numbers (empty items are skipped, as splitList()
// does), each in `range`; add "; each in range ..." to the option's help.
template <typename T>
CLI::Validator numberListCheck(const NumberRange<T>& range);

// WIDTHxHEIGHT as parseSize() reads it (values.hpp); say sizeForm() in the help.
CLI::Validator sizeCheck();
CLI::Validator sizeListCheck();
// A lookahead as parseLookahead() reads it; say lookaheadRange() in the help.
CLI::Validator lookaheadCheck();
CLI::Validator lookaheadListCheck();

}  // namespace logrid::samples
