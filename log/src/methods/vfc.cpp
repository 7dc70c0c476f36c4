// vfc: hierarchical view-frustum culling only, the baseline every occlusion method must
// beat; it reads nothing.
#include "method_def.hpp"

namespace logrid::detail {

const MethodDef& vfcMethod() {
  static const MethodDef def = [] {
    MethodDef m = methodNamed(Method::Vfc, "vfc", "view-frustum culling only");
    m.info.traversal = Traversal::FrontToBack;
    m.info.semantics = TestSemantics::None;
    m.make_tester = noTester;
    return m;
  }();
  return def;
}

}  // namespace logrid::detail
