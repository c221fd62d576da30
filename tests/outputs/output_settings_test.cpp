// The rule live_output.h states, kept true for every output in OutputKinds: its options are declared once under
// its prefix, it gives the window's panel at least one row, a row switched on opens that output (its status
// under the row's name), and the settings file holds its options under their keys.
#include "outputs/output_settings.h"

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "core/options.h"

namespace {

using th::outputs::LiveSessionSettings;
using th::outputs::OutputSettings;

class Names final : public th::OptionVisitor {
 public:
  std::vector<th::OptionSpec> specs;
  std::vector<std::string> names;
  void option(bool&, const th::OptionSpec& spec) override { add(spec); }
  void option(int&, const th::OptionSpec& spec) override { add(spec); }
  void option(unsigned&, const th::OptionSpec& spec) override { add(spec); }
  void option(double&, const th::OptionSpec& spec) override { add(spec); }
  void option(std::string&, const th::OptionSpec& spec) override { add(spec); }

 private:
  void add(const th::OptionSpec& spec) { names.emplace_back(spec.name); }
};

std::vector<std::string> prefixes() {
  std::vector<std::string> prefixes;
  std::apply([&](const auto&... kind) { (prefixes.emplace_back(std::remove_cvref_t<decltype(kind)>::kPrefix), ...); },
             th::outputs::OutputKinds{});
  return prefixes;
}

TEST(OutputSettings, EachOutputsOptionsCarryItsPrefixAndAreDeclaredOnce) {
  OutputSettings settings;
  Names visited;
  settings.visitOptions(visited);
  const std::vector<std::string> kinds = prefixes();
  ASSERT_EQ(kinds.size(), std::tuple_size_v<th::outputs::OutputKinds>);
  std::set<std::string> seen;
  for (const std::string& name : visited.names) {
    EXPECT_TRUE(seen.insert(name).second) << name << " declared twice";
    if (name == "mirror-head") continue;  // shared by VMC and VTube Studio
    bool under = false;
    for (const std::string& prefix : kinds) under |= name == prefix || name.rfind(prefix + "-", 0) == 0;
    EXPECT_TRUE(under) << name << " is under no output's prefix";
  }
  for (const std::string& prefix : kinds)
    EXPECT_TRUE(seen.count(prefix)) << "--" << prefix << ": each output is switched on by its prefix";
  // The flags users and saved settings know.
  for (const char* name : {"vmc", "vmc-assistant", "vmc-names", "vmc-neck-length-m", "vmc-head-length-m",
                           "vmc-neck-share", "vrchat", "vrchat-prefix", "vrchat-bits", "osc", "vts", "vts-token"})
    EXPECT_TRUE(seen.count(name)) << name;
}

TEST(OutputSettings, EachPanelRowSwitchedOnOpensItsOutput) {
  OutputSettings settings;
  const std::vector<th::outputs::OutputRow> rows = settings.rows();
  EXPECT_GE(rows.size(), std::tuple_size_v<th::outputs::OutputKinds>);
  EXPECT_TRUE(settings.open(th::outputs::OutputContext{}).empty()) << "all off by default";
  for (const th::outputs::OutputRow& row : rows) {
    OutputSettings one;
    for (th::outputs::OutputRow& other : one.rows())
      if (other.name == row.name) *other.address = std::string(other.defaultAddress);
    const auto outputs = one.open({.faps = {3, 48}, .tokenIssued = {}});
    ASSERT_EQ(outputs.size(), 1u) << row.name;
    EXPECT_EQ(outputs.front()->status().name, row.name);
    EXPECT_EQ(outputs.front()->status().target.find("localhost") != std::string::npos ||
                  outputs.front()->status().target.find("127.0.0.1") != std::string::npos,
              true)
        << row.name << " at " << outputs.front()->status().target;
  }
}

TEST(OutputSettings, TheSettingsFileHoldsTheOutputsBesideTheDecodersOptions) {
  LiveSessionSettings settings;
  settings.outputs.get<th::outputs::VmcSettings>().address = "127.0.0.1:40000";
  settings.outputs.get<th::outputs::VrchatSettings>().bits = 4;
  settings.outputs.mirrorHead = true;
  const th::Json saved = th::optionsToJson(settings);
  EXPECT_EQ(saved.at("vmc"), "127.0.0.1:40000");
  EXPECT_EQ(saved.at("vrchat_bits"), 4);
  EXPECT_EQ(saved.at("mirror_head"), true);
  EXPECT_TRUE(saved.contains("lag_frames")) << "the decoder's options too";
  LiveSessionSettings back;
  th::optionsFromJson(saved, back, "live.json");
  EXPECT_EQ(back.outputs.get<th::outputs::VmcSettings>().address, "127.0.0.1:40000");
  EXPECT_EQ(back.outputs.get<th::outputs::VrchatSettings>().bits, 4);
  settings.outputs.get<th::outputs::VrchatSettings>().bits = 9;
  EXPECT_THROW(settings.check(), th::Error) << "the outputs' ranges are checked with the rest";
}

}  // namespace
