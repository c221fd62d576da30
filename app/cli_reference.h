// The command-line reference, written from the CLI11 commands themselves (and so from the option registry that
// makes most of their options): every command and subcommand, each option with its type, range or choices,
// default and help, as Markdown. `talkinghead reference` prints it; docs/cli.md is its output, and a test
// fails if the two differ.
//
// Thread contract: set-up code, one thread.
#pragma once

#include <CLI/CLI.hpp>
#include <ostream>

namespace th::app {

void writeCliReference(const CLI::App& app, std::ostream& out);

}  // namespace th::app
