#include "logrid/method.hpp"

#include <cassert>

namespace logrid {

const std::vector<MethodInfo>& methodTable() {
  // clang-format off
  static const std::vector<MethodInfo> table = {
    // method, name, description,
    //   two_list_order, state_semantics, tests_occlusion, needs_depth_values, lookahead,
    //   uses_depth_source, box_queries, visible_pixels, full_fraction, row_stride
    {Method::LogState, "log-state",
     "lazy occlusion grid, occlusion-state variant (two-list traversal)",
     true, true, true, false, true, true, false, true, true, true},
    {Method::LogZfar, "log-zfar",
     "lazy occlusion grid, zfar variant (depth tests, any front-to-back order)",
     false, false, true, false, true, true, false, true, false, true},
    {Method::Bog, "bog",
     "busy occlusion grid: tiles refreshed right after each draw",
     true, true, true, false, false, true, false, true, true, true},
    {Method::Hzb, "hzb",
     "hierarchical z-buffer, refreshed from the drawn box's area after each draw",
     true, false, true, true, false, true, false, false, false, false},
    {Method::Pq, "pq",
     "one pixel-level query over each tested box's whole rectangle",
     true, true, true, false, true, true, false, true, false, false},
    {Method::Vfc, "vfc",
     "view-frustum culling only",
     false, false, false, false, false, false, false, false, false, false},
    {Method::Hwq, "hwq",
     "one hardware occlusion query per tested box, waited for at once",
     false, false, true, false, false, false, true, false, false, false},
    {Method::Chc, "chc",
     "CHC++: visible leaves drawn at once, invisible nodes queried in multi-query batches",
     false, false, true, false, false, false, true, false, false, false},
    {Method::Stat, "stat",
     "statistically optimised queries (Kovalcik & Sochor): visible nodes queried less often",
     false, false, true, false, false, false, true, false, false, false},
    {Method::Nohc, "nohc",
     "near-optimal hierarchical culling (Guthe et al.): a query only where it pays",
     false, false, true, false, false, false, true, false, false, false},
    {Method::LogHwq, "log+hwq",
     "the lazy grid's records decide what they can, the rest is queried (CullerDesc::queries)",
     false, false, true, false, false, true, true, false, false, false},
  };
  // clang-format on
  return table;
}

const MethodInfo& methodInfo(Method method) {
  const auto& table = methodTable();
  assert(std::size_t(method) < table.size() && "methodInfo: unknown method");
  return table[std::size_t(method)];
}

const char* toString(Method method) {
  const auto& table = methodTable();
  return std::size_t(method) < table.size() ? table[std::size_t(method)].name : "?";
}

std::optional<Method> parseMethod(const std::string& name) {
  for (const MethodInfo& m : methodTable()) {
    if (name == m.name) return m.method;
  }
  return std::nullopt;
}

std::string methodNames() {
  std::string out;
  for (const MethodInfo& m : methodTable()) {
    if (!out.empty()) out += ", ";
    out += m.name;
  }
  return out;
}

}  // namespace logrid
