// The talkinghead subcommands. Each add*Command registers its options on the CLI11 app and the function
// that runs it; errors are thrown as th::Error and printed by main() as one line.
#pragma once

#include <CLI/CLI.hpp>

namespace th::app {

void addFeaturesCommand(CLI::App& app);
void addEvalCommand(CLI::App& app);
void addHmmCommand(CLI::App& app);
void addTrainCommand(CLI::App& app);
void addEvalHeadCommand(CLI::App& eval);            // `eval head`, registered by addEvalCommand
void addEvalMouthCommand(CLI::App& eval);           // `eval mouth`, likewise
void addTrainMouthCommand(CLI::App& train);         // `train mouth`, registered by addTrainCommand
void addTrainVisemesCommand(CLI::App& train);       // `train visemes`, likewise
void addTrainArticulationCommand(CLI::App& train);  // `train articulation`, likewise
void addEvalVisemesCommand(CLI::App& eval);         // `eval visemes`, registered by addEvalCommand
void addTrainVideoOptions(CLI::App& train);         // `train --video DIR`, likewise
void addAnimateCommand(CLI::App& app);
void addFaceCommands(CLI::App& app);  // render, poses, export
void addShowCommand(CLI::App& app);
void addLiveCommand(CLI::App& app);        // live: the window, or --headless
void addTrackCommand(CLI::App& app);       // track: a talking video -> landmarks per frame
void addSideBySideCommand(CLI::App& app);  // sidebyside: a clip beside our face driven by its sound
void addRecordCommand(CLI::App& app);      // record: webcam + microphone, a take for train --video
void addStyleCommand(CLI::App& app);       // style: a talking clip -> the person's head style

}  // namespace th::app
