#include "cli_options.h"

#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace th::app {
namespace {

std::string helpOf(const OptionSpec& spec) {
  std::string help(spec.help);
  if (!spec.unit.empty()) help += " (" + std::string(spec.unit) + ")";
  return help;
}

// The option's flag, and its former name's after it: "--window-frames,--window".
std::string namesOf(const OptionSpec& spec, bool boolOnByDefault) {
  std::string names = flagOf(spec, boolOnByDefault);
  if (!spec.formerName.empty())
    names += "," + flagOf(OptionSpec{.name = spec.formerName, .help = spec.help}, boolOnByDefault);
  return names;
}

class CliBinder final : public OptionVisitor {
 public:
  CliBinder(CLI::App& command, std::string group) : command_(command), group_(std::move(group)) {}

  void option(bool& value, const OptionSpec& spec) override {
    if (value) {
      grouped(command_.add_flag(
          namesOf(spec, true), [&value](std::int64_t) { value = false; },
          "Turn off " + helpOf(spec) + " (on by default)"));
    } else {
      grouped(command_.add_flag(namesOf(spec, false), value, helpOf(spec)));
    }
  }
  void option(int& value, const OptionSpec& spec) override { number(value, spec); }
  void option(unsigned& value, const OptionSpec& spec) override { number(value, spec); }
  void option(double& value, const OptionSpec& spec) override { number(value, spec); }
  void option(std::string& value, const OptionSpec& spec) override {
    if (!spec.implicitValue.empty()) {  // "--vmc" alone, or "--vmc 9000"
      grouped(command_.add_option(
                  namesOf(spec, false),
                  [&value, implicit = std::string(spec.implicitValue)](const CLI::results_t& results) {
                    value = results.empty() || results.front().empty() ? implicit : results.front();
                    return true;
                  },
                  helpOf(spec) + " (alone: " + std::string(spec.implicitValue) + ")"))
          ->expected(0, 1);
      return;
    }
    CLI::Option* option = grouped(command_.add_option(namesOf(spec, false), value, helpOf(spec)));
    if (!spec.choices.empty()) {
      std::vector<std::string> names(spec.choices.begin(), spec.choices.end());
      option->check(CLI::IsMember(names));
    }
    if (!value.empty()) option->capture_default_str();
  }

 private:
  template <typename T>
  void number(T& value, const OptionSpec& spec) {
    CLI::Option* option = grouped(command_.add_option(namesOf(spec, false), value, helpOf(spec)));
    if (std::isfinite(spec.min) && std::isfinite(spec.max))
      option->check(CLI::Range(static_cast<T>(spec.min), static_cast<T>(spec.max)));
    option->capture_default_str();
  }

  CLI::Option* grouped(CLI::Option* option) const {
    if (!group_.empty()) option->group(group_);
    return option;
  }

  CLI::App& command_;
  std::string group_;
};

// The typed options' current values (as bound), under their settings keys.
class TypedCollector final : public OptionVisitor {
 public:
  explicit TypedCollector(const CLI::App& command) : command_(command) {}
  Json typed = Json::object();

  void option(bool& value, const OptionSpec& spec) override {
    // Either flag form counts; the bound value is already what was typed.
    if (has(flagOf(spec, true)) || has(flagOf(spec, false))) typed[settingsKey(spec.name)] = value;
  }
  void option(int& value, const OptionSpec& spec) override { take(value, spec); }
  void option(unsigned& value, const OptionSpec& spec) override { take(value, spec); }
  void option(double& value, const OptionSpec& spec) override { take(value, spec); }
  void option(std::string& value, const OptionSpec& spec) override { take(value, spec); }

 private:
  template <typename T>
  void take(const T& value, const OptionSpec& spec) {
    if (has(flagOf(spec, false))) typed[settingsKey(spec.name)] = value;
  }
  bool has(const std::string& flag) const {
    try {
      return command_.count(flag) > 0;
    } catch (const CLI::OptionNotFound&) {
      return false;
    }
  }

  const CLI::App& command_;
};

}  // namespace

std::string flagOf(const OptionSpec& spec, bool boolOnByDefault) {
  return (boolOnByDefault ? "--no-" : "--") + std::string(spec.name);
}

void addOptionsFrom(CLI::App& command, const std::function<void(OptionVisitor&)>& visit, const std::string& group) {
  CliBinder binder(command, group);
  visit(binder);
}

Json typedOptionsFrom(const CLI::App& command, const std::function<void(OptionVisitor&)>& visit) {
  TypedCollector collector(command);
  visit(collector);
  return collector.typed;
}

}  // namespace th::app
