#include "cli/values.hpp"

#include <sstream>

#include "logrid/camera.hpp"
#include "logrid/culler.hpp"
#include "logrid/error.hpp"

namespace logrid::samples {
namespace {

// A digit first and no blank anywhere: what istream would skip, wrap or round is refused.
bool startsWithDigit(const std::string& text) {
  return !text.empty() && text[0] >= '0' && text[0] <= '9' &&
         text.find_first_of(" \t\n\r\f\v") == std::string::npos;
}

}  // namespace

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

std::pair<std::uint32_t, std::uint32_t> parseSize(const std::string& text) {
  unsigned long w = 0, h = 0;
  char x = 0, extra = 0;
  std::istringstream in(text);
  // Digits first: istream would read "-1" as a huge unsigned number, and "+5" as 5.
  const bool digits = startsWithDigit(text);
  if (!digits || !(in >> w >> x) || (x != 'x' && x != 'X') || in.peek() < '0' || in.peek() > '9' ||
      !(in >> h) || (in >> extra) || w < 1 || h < 1 || w > kMaxViewportSide ||
      h > kMaxViewportSide) {
    throw Error(ErrorCode::InvalidArgument,
                "size '" + text + "' is invalid; use " + sizeForm() + ", e.g. 640x480");
  }
  return {std::uint32_t(w), std::uint32_t(h)};
}

std::string sizeForm() {
  return "WIDTHxHEIGHT, each side in range [1, " + std::to_string(kMaxViewportSide) + "]";
}

DepthFormat parseDepthFormat(const std::string& text) {
  if (text == "16") return DepthFormat::D16;
  if (text == "24") return DepthFormat::D24;
  if (text == "32f" || text == "32F") return DepthFormat::D32F;
  throw Error(ErrorCode::InvalidArgument,
              "depth format '" + text + "' is unknown; use 16, 24 or 32f");
}

DepthConvention parseDepthConvention(const std::string& text) {
  if (text == "standard") return DepthConvention::Standard;
  if (text == "reversed") return DepthConvention::Reversed;
  throw Error(ErrorCode::InvalidArgument,
              "depth convention '" + text + "' is unknown; use standard or reversed");
}

TreeParts parseTreeParts(const std::string& text) {
  for (TreeParts p : {TreeParts::Whole, TreeParts::TrunkCrown, TreeParts::Tiers}) {
    if (text == toString(p)) return p;
  }
  throw Error(ErrorCode::InvalidArgument,
              "tree parts '" + text + "' is unknown; use whole, trunk-crown or tiers");
}

ClusterMethod parseClusterMethod(const std::string& text) {
  if (text == "grow") return ClusterMethod::Grow;
  if (text == "scan") return ClusterMethod::Scan;
  throw Error(ErrorCode::InvalidArgument,
              "cluster method '" + text + "' is unknown; use grow or scan");
}

std::uint32_t parseLookahead(const std::string& text) {
  if (text == "all") return kUnlimitedLookahead;
  unsigned long k = 0;
  char extra = 0;
  std::istringstream in(text);
  const bool digits = startsWithDigit(text);
  if (!digits || !(in >> k) || (in >> extra) || k < 1 || k >= kUnlimitedLookahead) {
    throw Error(ErrorCode::InvalidArgument, "lookahead '" + text + "' is invalid; use a whole " +
                                                "number of boxes in " + lookaheadRange());
  }
  return std::uint32_t(k);
}

std::string lookaheadRange() {
  return "range [1, " + std::to_string(kUnlimitedLookahead - 1) + "] or all";
}

std::string lookaheadText(std::uint32_t k) {
  return k == kUnlimitedLookahead ? "all" : std::to_string(k);
}

}  // namespace logrid::samples
