// A culler's configuration as a file: the setting `logrid tune --auto` found fastest on a
// scene's own frames, for an application to load (loadCullerConfig) or for walk, bench,
// view and tune to take with --config FILE.
//
// The file (JSON; unknown keys are ignored, so that tools may add their own: tune adds
// "scene", the box granularity the samples apply, and "report", what it measured):
//   { "format": "logrid-config", "version": 1,
//     "source": "pbo",
//     "culler": { "method": "log-zfar", "tile_size": 16, "lookahead": 16,
//                 "temporal_coherence": true, "detect_colliding": false,
//                 "approximation": { "visible_pixels": 0, "full_free_fraction": 0,
//                                    "row_stride": 1 } } }
// Every key of "culler" is optional (CullerDesc's default where absent); "lookahead" is a
// count or "all" (kUnlimitedLookahead). The query methods' settings, projection and costs
// are not part of the file: an application sets them as before.
#pragma once

#include <string>

#include "logrid/culler.hpp"
#include "logrid/error.hpp"

namespace logrid {

struct CullerConfig {
  CullerDesc culler;
  // The depth source it was chosen with (DepthSourceTraits::name, e.g. "pbo"); empty if
  // the file names none. Costs and the best lookahead depend on it.
  std::string source;
};

// Parses a configuration file's text; `origin` names it in messages. ErrorCode::BadInput
// for text that is not such a file (not JSON, another format or version, a value of the
// wrong type), an unknown method, or a value out of range (validateCullerDesc); the
// message names the origin and the key. Both forms (error.hpp).
Result<CullerConfig> tryParseCullerConfig(const std::string& text,
                                          const std::string& origin = "config");
CullerConfig parseCullerConfig(const std::string& text, const std::string& origin = "config");
// Reads and parses a configuration file (ErrorCode::Environment if it cannot be read).
Result<CullerConfig> tryLoadCullerConfig(const std::string& path);
CullerConfig loadCullerConfig(const std::string& path);
// The file's text: format, version, source, culler; parseCullerConfig reads back `config`.
std::string formatCullerConfig(const CullerConfig& config);

#if LOGRID_HAS_EXCEPTIONS
inline CullerConfig parseCullerConfig(const std::string& text, const std::string& origin) {
  return orThrow(tryParseCullerConfig(text, origin));
}
inline CullerConfig loadCullerConfig(const std::string& path) {
  return orThrow(tryLoadCullerConfig(path));
}
#endif

}  // namespace logrid
