// auto: chooses among exact settings from a cost model measured on the running machine
// (costs.hpp, CullerDesc::costs, refined every frame by Culler::costEstimate): per node,
// whether a test can pay at all (the reasonability test of Guthe, Balázs, Klein 2006,
// §4.1, applied to grid tests); per frame, the lookahead K, temporal coherence and the
// grid variant (log-state or log-zfar). Every choice is exact; the depth source is the
// application's. The choices are in log/src/auto_policy.hpp, docs/AUTO.md describes them,
// and FrameStats::setting records what each frame ran.
#include "method_def.hpp"

namespace logrid::detail {

const MethodDef& autoMethod() {
  static const MethodDef def = [] {
    // What the frame runs is log-state's or log-zfar's (the culler switches between
    // them); the info describes the first, and what both need.
    MethodDef m = methodLike(logStateMethod(), Method::Auto, "auto",
                             "chooses per node and per frame among the exact grid settings "
                             "from measured costs (log-state or log-zfar, K, coherence)");
    // Lookahead and coherence are its own choice; no approximate knob: auto is exact.
    m.info.takes = {};
    return m;
  }();
  return def;
}

}  // namespace logrid::detail
