#include "cli/report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "logrid/error.hpp"

namespace logrid::samples {

void writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  if (!out) throw Error(ErrorCode::Environment, "cannot write '" + path + "' (check the folder)");
}

namespace {
std::string g_command_line;
}

void setCommandLine(int argc, char** argv) {
  g_command_line.clear();
  for (int i = 0; i < argc; ++i) {
    if (i) g_command_line += ' ';
    const std::string arg = i == 0 ? "logrid" : argv[i];
    const bool quote = arg.find_first_of(" \t'\"") != std::string::npos;
    g_command_line += quote ? "'" + arg + "'" : arg;
  }
}

const std::string& commandLine() { return g_command_line; }

void writeJson(const std::string& path, const nlohmann::json& json) {
  writeText(path, json.dump(2) + "\n");
}

std::string formatFixed(double value, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, value);
  return buf;
}

std::string formatRatio(double a, double b, const char* suffix) {
  return b > 0 ? formatFixed(a / b, 2) + suffix : "–";
}

std::string linkFrom(const std::string& document, const std::string& target) {
  namespace fs = std::filesystem;
  return fs::relative(fs::absolute(target), fs::absolute(document).parent_path()).string();
}

std::string framesAlong(std::size_t frames, double time_step) {
  if (time_step > 0) {
    return std::to_string(frames) + " frames " + formatFixed(time_step, 3) +
           " s of path time apart from the walkthrough's start";
  }
  return std::to_string(frames) + " frames along the walkthrough";
}

std::string grouped(double v) {
  std::string digits = std::to_string(static_cast<long long>(std::llround(v)));
  for (int i = int(digits.size()) - 3; i > 0 && digits[std::size_t(i) - 1] != '-'; i -= 3) {
    digits.insert(std::size_t(i), ",");
  }
  return digits;
}

}  // namespace logrid::samples
