// The values of text options: comma-separated lists, viewport sizes, depth set-ups, the
// forest's tree parts, cluster methods and lookaheads. Each parse function throws logrid::Error
// (InvalidArgument) with a message that names the text and what it may be.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "logrid/types.hpp"
#include "scene/clusters.hpp"
#include "scene/generators.hpp"

namespace logrid::samples {

// Splits a comma-separated list ("forest,city"), dropping empty items.
std::vector<std::string> splitList(const std::string& text);

// Parses "WxH", each side from 1 to kMaxViewportSide.
std::pair<std::uint32_t, std::uint32_t> parseSize(const std::string& text);
// "WIDTHxHEIGHT, each side in range [1, 32768]", for help texts.
std::string sizeForm();

DepthFormat parseDepthFormat(const std::string& text);
DepthConvention parseDepthConvention(const std::string& text);
TreeParts parseTreeParts(const std::string& text);
// "grow" or "scan".
ClusterMethod parseClusterMethod(const std::string& text);

// "1", "16", ... or "all" (kUnlimitedLookahead).
std::uint32_t parseLookahead(const std::string& text);
// "range [1, 4294967294] or all", for help texts.
std::string lookaheadRange();
// A lookahead as parseLookahead() reads it ("all" for kUnlimitedLookahead).
std::string lookaheadText(std::uint32_t k);

}  // namespace logrid::samples
