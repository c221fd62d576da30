#include "live/option_widgets.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>

namespace th::app {
namespace {

std::string labelOf(const OptionSpec& spec) {
  std::string label(spec.name);
  std::replace(label.begin(), label.end(), '-', ' ');
  if (!spec.unit.empty()) label += " (" + std::string(spec.unit) + ")";
  return label;
}

class WidgetDrawer final : public OptionVisitor {
 public:
  explicit WidgetDrawer(std::vector<WidgetRecord>* record) : record_(record) {}
  bool changed = false;

  void option(bool& value, const OptionSpec& spec) override {
    if (!spec.panel) return;
    note(spec, "checkbox");
    changed |= ImGui::Checkbox(labelOf(spec).c_str(), &value);
    tooltip(spec);
  }
  void option(int& value, const OptionSpec& spec) override {
    if (!spec.panel) return;
    note(spec, "slider");
    changed |= ImGui::SliderInt(labelOf(spec).c_str(), &value, static_cast<int>(spec.min), static_cast<int>(spec.max),
                                "%d", flags(spec));
    tooltip(spec);
  }
  void option(unsigned& value, const OptionSpec& spec) override {
    if (!spec.panel) return;
    note(spec, "slider");
    int shown = static_cast<int>(value);
    if (ImGui::SliderInt(labelOf(spec).c_str(), &shown, static_cast<int>(spec.min), static_cast<int>(spec.max), "%d",
                         flags(spec))) {
      value = static_cast<unsigned>(shown);
      changed = true;
    }
    tooltip(spec);
  }
  void option(double& value, const OptionSpec& spec) override {
    if (!spec.panel) return;
    note(spec, "slider");
    float shown = static_cast<float>(value);
    if (ImGui::SliderFloat(labelOf(spec).c_str(), &shown, static_cast<float>(spec.min), static_cast<float>(spec.max),
                           "%.2f", flags(spec))) {
      value = shown;
      changed = true;
    }
    tooltip(spec);
  }
  void option(std::string& value, const OptionSpec& spec) override {
    if (!spec.panel || spec.choices.empty()) return;  // free text (paths) has widgets of its own
    note(spec, "combo");
    if (ImGui::BeginCombo(labelOf(spec).c_str(), value.c_str())) {
      for (std::string_view choice : spec.choices) {
        const std::string name(choice);
        if (ImGui::Selectable(name.c_str(), value == name) && value != name) {
          value = name;
          changed = true;
        }
      }
      ImGui::EndCombo();
    }
    tooltip(spec);
  }

 private:
  static ImGuiSliderFlags flags(const OptionSpec& spec) {
    return ImGuiSliderFlags_AlwaysClamp | (spec.logarithmic ? ImGuiSliderFlags_Logarithmic : 0);
  }
  static void tooltip(const OptionSpec& spec) {
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", std::string(spec.help).c_str());
  }
  void note(const OptionSpec& spec, const char* kind) {
    if (record_ == nullptr) return;
    WidgetRecord line{std::string(spec.name), kind, spec.min, spec.max, {}};
    for (std::string_view choice : spec.choices) line.choices.emplace_back(choice);
    record_->push_back(std::move(line));
  }

  std::vector<WidgetRecord>* record_;
};

}  // namespace

bool optionWidgetsFrom(const std::function<void(OptionVisitor&)>& visit, std::vector<WidgetRecord>* record) {
  WidgetDrawer drawer(record);
  visit(drawer);
  return drawer.changed;
}

}  // namespace th::app
