// --config FILE: a configuration file (logrid/config.hpp; `logrid tune --auto` writes one)
// in place of the options it sets.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <string>

#include "cli/options.hpp"
#include "logrid/config.hpp"

namespace logrid::samples {

// What a configuration file sets, as a command's options: the method choice with its
// lookahead and coherence ("log-zfar:16:tc"), and the rest in WalkOptions (tile, reader,
// detect-colliding, approximate knobs, and the "scene" section's box granularity: leaf
// size and tree parts).
struct ConfigSettings {
  std::string method;
  WalkOptions options;
};

// The file's settings over `base`. Throws logrid::Error for a file that is not a
// configuration (loadCullerConfig's messages) or whose "scene" section holds a value of
// the wrong type.
ConfigSettings applyConfigFile(const std::string& path, const WalkOptions& base);

// The "scene" section tune writes beside the culler's: {"leaf": N, "tree_parts": "..."}.
std::string sceneSection(const WalkOptions& o);

// Adds --config FILE to a walkthrough command, after its other options: the file's
// settings go to `o` (the method choice to o.method) and, if given, the method choice to
// `use_method` too (bench adds it to its methods). The options the file sets (--method,
// --tile, --tiles, --reader, --lookahead, --coherence, --colliding, --leaf, --tree-parts,
// and the approximate knobs) cannot be given beside it.
CLI::Option* addConfigOption(CLI::App& app, WalkOptions& o,
                             std::function<void(const std::string& method)> use_method = {});

}  // namespace logrid::samples
