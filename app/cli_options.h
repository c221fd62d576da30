// The command line made from the option registry (core/options.h): each field of an options struct becomes
// `--NAME` on a command, with its range or choices checked by CLI11 and its default shown in --help.
//
//   th::pipeline::IdleOptions idle;
//   th::app::addOptions(*command, idle);                    // --no-idle, --blinks-per-minute, --seed
//   ...after parsing...
//   th::app::copyTypedOptions(*command, given, settings);  // only what was typed overrides the settings
//
// A bool on by default is switched off by --no-NAME; one off by default is switched on by --NAME.
// Thread contract: set-up code, one thread.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

#include "core/options.h"

namespace th::app {

// `group`: the --help section the options are listed under (empty: CLI11's "Options").
void addOptionsFrom(CLI::App& command, const std::function<void(OptionVisitor&)>& visit, const std::string& group = {});
// The typed options' values, as a settings object (core/options.h's keys).
Json typedOptionsFrom(const CLI::App& command, const std::function<void(OptionVisitor&)>& visit);

// The options bound to `options`: they must outlive the command's parsing.
template <typename Options>
void addOptions(CLI::App& command, Options& options, const std::string& group = {}) {
  addOptionsFrom(
      command, [&](OptionVisitor& v) { options.visitOptions(v); }, group);
}

// The options typed on `command` (bound to `given`) copied into `target`; the others keep target's values.
template <typename Options>
void copyTypedOptions(const CLI::App& command, Options& given, Options& target) {
  const Json typed = typedOptionsFrom(command, [&](OptionVisitor& v) { given.visitOptions(v); });
  optionsFromJson(typed, target, "the command line");
}

// The CLI option's flag for a spec: "--no-idle" for a bool on by default, "--NAME" otherwise.
std::string flagOf(const OptionSpec& spec, bool boolOnByDefault);

}  // namespace th::app
