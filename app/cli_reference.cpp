#include "cli_reference.h"

#include <string>

namespace th::app {
namespace {

// A cell of a Markdown table: pipes escaped, on one line.
std::string cell(std::string text) {
  std::string out;
  for (const char c : text) {
    if (c == '|')
      out += "\\|";
    else if (c == '\n')
      out += ' ';
    else
      out += c;
  }
  return out;
}

void writeCommand(const CLI::App& command, const std::string& path, std::ostream& out) {
  out << "\n## `" << path << "`\n\n" << command.get_description() << "\n\n";
  const std::vector<const CLI::Option*> options =
      command.get_options([](const CLI::Option* option) { return option->get_name() != "--help"; });
  if (!options.empty()) {
    out << "| option | value | default | what it does |\n|---|---|---|---|\n";
    for (const CLI::Option* option : options) {
      std::string name = option->get_positional() ? option->get_name(true) : option->get_name(false, true);
      // A flag's names carry their values ("--no-peers{false}"): the names alone.
      for (std::size_t open = name.find('{'); open != std::string::npos; open = name.find('{'))
        name.erase(open, name.find('}', open) - open + 1);
      if (option->get_required()) name += " (required)";
      const std::string type = option->get_type_name();
      out << "| `" << cell(name) << "` | " << (type.empty() ? "" : "`" + cell(type) + "`") << " | "
          << (option->get_default_str().empty() ? "" : "`" + cell(option->get_default_str()) + "`") << " | "
          << cell(option->get_description()) << " |\n";
    }
  }
  for (const CLI::App* sub : command.get_subcommands([](const CLI::App* app) { return !app->get_group().empty(); }))
    writeCommand(*sub, path + " " + sub->get_name(), out);
}

}  // namespace

void writeCliReference(const CLI::App& app, std::ostream& out) {
  out << "# Command-line reference\n\n"
         "Every `talkinghead` command and its options, written by `build/talkinghead reference > docs/cli.md` from\n"
         "the commands themselves (tests/cli checks that this file is current). Options shared by several commands\n"
         "are declared once, in `engine/pipeline/options.h`, with their ranges and defaults; the live window's panel\n"
         "and settings file use the same declarations. A bool option that is on by default is turned off with\n"
         "`--no-NAME`.\n";
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App* command) { return !command->get_group().empty(); }))
    writeCommand(*sub, "talkinghead " + sub->get_name(), out);
}

}  // namespace th::app
