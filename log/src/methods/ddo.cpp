// ddo: directional discretized occluders (Bernardini, El-Sana, Klosowski 2000). The
// occluder pre-pass selects the octree faces valid for the viewpoint into a CPU occlusion
// map (OccluderUse::Map; logrid::ddo's OccluderPass), and every box of the hierarchy is
// tested against that map front to back: no depth read, no GL query. Objects the
// occluders' octree does not hold (moving ones) are tested like the others, since the
// map only says where static geometry already hides everything behind.
#include "method_def.hpp"

namespace logrid::detail {

const MethodDef& ddoMethod() {
  static const MethodDef def = [] {
    MethodDef m =
        methodNamed(Method::Ddo, "ddo",
                    "directional discretized occluders: boxes tested against the CPU map of the "
                    "occluders valid for the viewpoint (no depth reads)");
    m.info.traversal = Traversal::FrontToBack;
    m.info.semantics = TestSemantics::Depth;
    m.info.occluders = OccluderUse::Map;
    m.info.needs.occluders = true;
    m.make_tester = [](const CullerDesc&, const MethodInfo&) { return makeOccluderMapTester(); };
    return m;
  }();
  return def;
}

}  // namespace logrid::detail
