// talkinghead: speech in, talking head out. One executable, one subcommand per job.
#include <CLI/CLI.hpp>
#include <iostream>
#include <string>

#include "cli_reference.h"
#include "commands.h"
#include "core/error.h"

int main(int argc, char** argv) {
  CLI::App app{"talkinghead: a speech-driven 3-D talking head (features, models, face, live, export)"};
  app.require_subcommand(1);
  th::app::addFeaturesCommand(app);
  th::app::addEvalCommand(app);
  th::app::addHmmCommand(app);
  th::app::addTrainCommand(app);
  th::app::addAnimateCommand(app);
  th::app::addFaceCommands(app);
  th::app::addShowCommand(app);
  th::app::addLiveCommand(app);
  th::app::addTrackCommand(app);
  th::app::addSideBySideCommand(app);
  th::app::addRecordCommand(app);
  th::app::addStyleCommand(app);
  // docs/cli.md: the reference of every command above, from the commands themselves (hidden from --help).
  app.add_subcommand("reference", "Print the command-line reference (Markdown)")->group("")->callback([&app] {
    th::app::writeCliReference(app, std::cout);
  });
  // A mistyped command line is one line, as every other error (CLI11 adds a second, "Run with --help ...").
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    return "talkinghead: " + std::string(e.what()) + " (--help lists the options)\n";
  });
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const th::Error& e) {
    std::cerr << "talkinghead: " << e.what() << '\n';
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "talkinghead: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
