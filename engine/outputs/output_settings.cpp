#include "outputs/output_settings.h"

#include <mutex>
#include <set>
#include <string>
#include <utility>

namespace th::outputs {
namespace {

// A name kept for the life of the program: a visitor may keep the specs it is given (the help, docs, tests), and
// a prefixed name has no other home.
std::string_view keptName(std::string name) {
  static std::mutex mutex;
  static std::set<std::string> names;  // a node's string does not move
  const std::lock_guard lock(mutex);
  return *names.insert(std::move(name)).first;
}

// An output's options under its prefix: "names" becomes "vmc-names", the option named "" the prefix alone.
class PrefixedVisitor final : public OptionVisitor {
 public:
  PrefixedVisitor(OptionVisitor& visitor, std::string_view prefix) : visitor_(visitor), prefix_(prefix) {}
  void option(bool& value, const OptionSpec& spec) override { forward(value, spec); }
  void option(int& value, const OptionSpec& spec) override { forward(value, spec); }
  void option(unsigned& value, const OptionSpec& spec) override { forward(value, spec); }
  void option(double& value, const OptionSpec& spec) override { forward(value, spec); }
  void option(std::string& value, const OptionSpec& spec) override { forward(value, spec); }

 private:
  std::string_view prefixed(std::string_view name) const {
    return keptName(name.empty() ? std::string(prefix_) : std::string(prefix_) + "-" + std::string(name));
  }
  template <typename T>
  void forward(T& value, const OptionSpec& spec) {
    OptionSpec named = spec;
    named.name = prefixed(spec.name);
    if (!spec.formerName.empty()) named.formerName = prefixed(spec.formerName);
    visitor_.option(value, named);
  }

  OptionVisitor& visitor_;
  std::string_view prefix_;
};

}  // namespace

void OutputSettings::visitOptions(OptionVisitor& v) {
  std::apply(
      [&](auto&... kind) {
        (
            [&](auto& settings) {
              PrefixedVisitor prefixed(v, std::remove_reference_t<decltype(settings)>::kPrefix);
              settings.visitOptions(prefixed);
            }(kind),
            ...);
      },
      kinds);
  v.option(mirrorHead, {.name = "mirror-head",
                        .help = "VMC and VTube Studio: the avatar turns as the speaker's mirror image (to its right "
                                "when the speaker turns to their left), not as the speaker does",
                        .panel = false});
}

std::vector<OutputRow> OutputSettings::rows() {
  std::vector<OutputRow> rows;
  std::apply([&](auto&... kind) { (kind.addRows(rows), ...); }, kinds);
  return rows;
}

std::vector<std::unique_ptr<LiveOutput>> OutputSettings::open(OutputContext context) const {
  context.mirrorHead = mirrorHead;
  std::vector<std::unique_ptr<LiveOutput>> outputs;
  std::apply([&](const auto&... kind) { (kind.open(context, outputs), ...); }, kinds);
  return outputs;
}

void LiveSessionSettings::visitOptions(OptionVisitor& v) {
  pipeline::LiveSettings::visitOptions(v);
  outputs.visitOptions(v);
}

void LiveSessionSettings::check() {
  pipeline::LiveSettings::check();
  checkOptions(outputs);
}

}  // namespace th::outputs
