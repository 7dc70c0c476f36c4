#include "viewer/panel.hpp"

#include <imgui.h>

#include <algorithm>
#include <cinttypes>
#include <cstdio>

#include "cli/readers.hpp"

namespace logrid::viewer {
namespace {

// Three columns: what, this frame, the last second's mean.
void row(const char* label, double live, double mean, const char* format) {
  ImGui::TableNextRow();
  ImGui::TableSetColumnIndex(0);
  ImGui::TextUnformatted(label);
  ImGui::TableSetColumnIndex(1);
  ImGui::Text(format, live);
  ImGui::TableSetColumnIndex(2);
  ImGui::Text(format, mean);
}

bool combo(const char* label, std::string& value, const std::vector<std::string>& items,
           const std::vector<bool>& usable, const std::vector<std::string>& tips) {
  bool changed = false;
  if (ImGui::BeginCombo(label, value.c_str())) {
    for (std::size_t i = 0; i < items.size(); ++i) {
      const bool ok = usable.empty() || usable[i];
      if (ImGui::Selectable(items[i].c_str(), items[i] == value,
                            ok ? 0 : ImGuiSelectableFlags_Disabled)) {
        changed = items[i] != value;
        value = items[i];
      }
      if (i < tips.size() && !tips[i].empty() && ImGui::IsItemHovered()) {
        ImGui::SetTooltip("%s", tips[i].c_str());
      }
    }
    ImGui::EndCombo();
  }
  return changed;
}

void statsSection(const PanelModel& m) {
  const FrameSample* live = m.stats ? m.stats->last() : nullptr;
  if (!live) {
    ImGui::TextUnformatted("no frame yet");
    return;
  }
  const FrameSample mean = m.stats->mean();
  if (ImGui::BeginTable("stats", 3, ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingFixedFit)) {
    ImGui::TableSetupColumn("");
    ImGui::TableSetupColumn("frame");
    ImGui::TableSetupColumn("1 s mean");
    ImGui::TableHeadersRow();
    row("cull + draw ms", live->cull_ms, mean.cull_ms, "%.2f");
    row("whole frame ms", live->loop_ms, mean.loop_ms, "%.2f");
    row("drawn objects", live->objects, mean.objects, "%.0f");
    row("drawn triangles", live->triangles, mean.triangles, "%.0f");
    row("pixels read", live->pixels_read, mean.pixels_read, "%.0f");
    row("boxes tested", live->boxes_tested, mean.boxes_tested, "%.0f");
    row("tiles per box", live->tiles_per_box, mean.tiles_per_box, "%.2f");
    row("flushes", live->flushes, mean.flushes, "%.1f");
    row("batches", live->batches, mean.batches, "%.1f");
    row("queries", live->queries, mean.queries, "%.0f");
    if (live->visible >= 0) {
      row("visible objects", live->visible, mean.visible, "%.0f");
      row("missed", live->missed, std::max(mean.missed, 0.0), "%.2f");
    }
    ImGui::EndTable();
  }
  if (mean.loop_ms > 0) ImGui::Text("%.1f frames per second", 1000.0 / mean.loop_ms);
}

void cullingSection(PanelModel& m) {
  CullSettings& s = *m.settings;
  const std::vector<std::string> methods = methodChoices();
  std::vector<std::string> method_tips;
  for (const std::string& name : methods) {
    const auto method = parseMethod(name);
    method_tips.push_back(method ? methodInfo(*method).description
                                 : "exactly the visible set, from an untimed object-ID pass");
  }
  combo("method (M)", s.method, methods, {}, method_tips);
  const auto method = parseMethod(s.method);
  const MethodInfo* info = method ? &methodInfo(*method) : nullptr;

  std::vector<std::string> readers, reader_tips;
  std::vector<bool> usable;
  for (const samples::ReaderInfo& r : samples::readerTable()) {
    readers.push_back(r.name);
    reader_tips.push_back(r.description);
    usable.push_back(!info || !info->needs.depth_values || r.reads_depth);
  }
  combo("reader (N)", s.reader, readers, usable, reader_tips);

  int tile = int(s.tile);
  if (ImGui::InputInt("tile size", &tile, 1, 8)) s.tile = std::uint32_t(std::clamp(tile, 1, 1024));
  const char* formats[] = {"16", "24", "32f"};
  int format = int(s.format);
  if (ImGui::Combo("depth format", &format, formats, 3)) s.format = DepthFormat(format);
  const char* conventions[] = {"standard", "reversed"};
  int convention = int(s.convention);
  if (ImGui::Combo("depth convention", &convention, conventions, 2)) {
    s.convention = DepthConvention(convention);
  }

  ImGui::BeginDisabled(!info || !info->takes.lookahead);
  bool all = s.lookahead == kUnlimitedLookahead;
  int k = all ? 1 : int(std::min<std::uint32_t>(s.lookahead, 1 << 20));
  ImGui::BeginDisabled(all);
  if (ImGui::InputInt("lookahead K", &k, 1, 16))
    s.lookahead = std::uint32_t(std::clamp(k, 1, 1 << 20));
  ImGui::EndDisabled();
  ImGui::SameLine();
  if (ImGui::Checkbox("all", &all)) s.lookahead = all ? kUnlimitedLookahead : 1;
  ImGui::EndDisabled();
  ImGui::BeginDisabled(!info || !info->takes.temporal_coherence);
  ImGui::Checkbox("temporal coherence", &s.coherence);
  ImGui::EndDisabled();

  if (ImGui::TreeNode("approximate (speed for accuracy)")) {
    GridApproximation& a = s.approximation;
    ImGui::BeginDisabled(!info || !info->takes.visible_pixels);
    int pixels = int(std::min<std::uint32_t>(a.visible_pixels, 1 << 24));
    if (ImGui::InputInt("visible pixels", &pixels, 1, 10)) {
      a.visible_pixels = std::uint32_t(std::clamp(pixels, 0, 1 << 24));
    }
    ImGui::EndDisabled();
    ImGui::BeginDisabled(!info || !info->takes.full_fraction);
    ImGui::SliderFloat("full fraction", &a.full_free_fraction, 0.0f, 0.5f, "%.3f");
    ImGui::EndDisabled();
    ImGui::BeginDisabled(!info || !info->takes.row_stride);
    int stride = int(a.row_stride);
    if (ImGui::SliderInt("row stride", &stride, 1, 16)) a.row_stride = std::uint32_t(stride);
    ImGui::EndDisabled();
    if (ImGui::Button("exact")) a = GridApproximation{};
    ImGui::TreePop();
  }
}

void viewsSection(PanelModel& m) {
  DisplaySettings& d = *m.display;
  ImGui::Checkbox("tile grid (G)", &d.grid);
  ImGui::SameLine();
  const char* shades[] = {"auto", "states", "zfar"};
  int shade = int(d.shade);
  ImGui::SetNextItemWidth(80);
  if (ImGui::Combo("shade", &shade, shades, 3)) d.shade = ShadeChoice(shade);
  ImGui::Checkbox("tested boxes (B)", &d.boxes);
  ImGui::SameLine();
  ImGui::Checkbox("top view (T)", &d.top_view);
  ImGui::Checkbox("verify every frame (V)", &m.settings->verify);
  if (m.verified_frames > 0) {
    ImGui::Text("checked %zu frames: %zu missed objects in %zu frames", m.verified_frames,
                m.missed_total, m.frames_with_misses);
  }
}

void pathSection(PanelModel& m) {
  ImGui::Text("path frame %.1f of %zu", m.path_frame, m.frame_count);
  if (ImGui::Button(m.playing ? "pause (Space)" : "play (Space)")) m.toggle_play = true;
  ImGui::SameLine();
  if (ImGui::Button("<")) m.step = -1;
  ImGui::SameLine();
  if (ImGui::Button(">")) m.step = 1;
  ImGui::SameLine();
  if (ImGui::Button(m.recording ? "stop recording (R)" : "record (R)")) m.toggle_record = true;
  if (m.recording) {
    ImGui::SameLine();
    ImGui::TextColored(ImVec4(1, 0.4f, 0.2f, 1), "%.1f s", m.record_seconds);
  }
  if (ImGui::Button("screenshot (F12)")) m.screenshot = true;
  ImGui::SameLine();
  ImGui::Text("speed %.3g/s (wheel)", m.speed);
}

}  // namespace

void drawPanel(PanelModel& m) {
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(340, 0), ImGuiCond_Always);
  ImGui::SetNextWindowBgAlpha(0.85f);
  ImGui::Begin("logrid", nullptr, ImGuiWindowFlags_NoResize);
  ImGui::PushTextWrapPos(0);
  ImGui::TextUnformatted(m.scene.c_str());
  ImGui::TextDisabled("%s", m.renderer.c_str());
  ImGui::PopTextWrapPos();
  statsSection(m);
  ImGui::PushItemWidth(150);
  if (ImGui::BeginTabBar("sections")) {
    if (ImGui::BeginTabItem("culling")) {
      cullingSection(m);
      ImGui::EndTabItem();
    }
    if (ImGui::BeginTabItem("views")) {
      viewsSection(m);
      ImGui::EndTabItem();
    }
    if (ImGui::BeginTabItem("path")) {
      pathSection(m);
      ImGui::EndTabItem();
    }
    ImGui::EndTabBar();
  }
  ImGui::PopItemWidth();
  ImGui::PushTextWrapPos(0);
  if (!m.error.empty()) ImGui::TextColored(ImVec4(1, 0.35f, 0.3f, 1), "%s", m.error.c_str());
  if (!m.message.empty()) ImGui::TextDisabled("%s", m.message.c_str());
  ImGui::PopTextWrapPos();
  ImGui::TextDisabled("F1: keys and mouse");
  ImGui::End();
}

void drawHelp(bool* open) {
  const ImGuiIO& io = ImGui::GetIO();
  ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x * 0.5f, io.DisplaySize.y * 0.5f),
                          ImGuiCond_Always, ImVec2(0.5f, 0.5f));
  ImGui::SetNextWindowBgAlpha(0.92f);
  if (!ImGui::Begin("help", open,
                    ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse)) {
    ImGui::End();
    return;
  }
  static const char* const kLines[][2] = {
      {"W A S D / arrows", "fly forward, left, back, right"},
      {"E / Page Up, Q / Page Down", "fly up, down"},
      {"Shift, Ctrl", "4x faster, 4x slower while held"},
      {"mouse wheel", "flying speed"},
      {"right drag (or left drag)", "look around"},
      {"Space", "play or pause the camera path"},
      {". and ,", "step the path one frame forward, back"},
      {"M, Shift+M", "next, previous culling method"},
      {"N, Shift+N", "next, previous depth reader"},
      {"G", "tile-grid overlay (free/partial/full or zfar; outdated hatched)"},
      {"B", "tested boxes: red occluded, cyan visible, green drawn leaves"},
      {"T", "top view: frustum, drawn and culled objects"},
      {"V", "verify every frame with the object-ID oracle (misses flash red)"},
      {"Tab", "hide or show the panel"},
      {"F12 or P", "screenshot (PNG)"},
      {"R", "record the flight as a camera path (walk --path, bench)"},
      {"F1", "this help"},
      {"Esc", "quit"},
  };
  if (ImGui::BeginTable("keys", 2, ImGuiTableFlags_SizingFixedFit)) {
    for (const auto& line : kLines) {
      ImGui::TableNextRow();
      ImGui::TableSetColumnIndex(0);
      ImGui::TextColored(ImVec4(1, 0.85f, 0.4f, 1), "%s", line[0]);
      ImGui::TableSetColumnIndex(1);
      ImGui::TextUnformatted(line[1]);
    }
    ImGui::EndTable();
  }
  ImGui::End();
}

}  // namespace logrid::viewer
