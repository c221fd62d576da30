#!/usr/bin/env node
// talkinghead-web animate IN.wav -o OUT [--format F] [--preset P] [--models DIR] [--no-idle] [--seed N]
//
// The package's command for Node: a WAV file in, the animation native `talkinghead animate --online --preset P`
// writes out (the format named, else by the output's extension: .csv FAPs, or --format arkit / oculus / vrm /
// json / rhubarb-tsv ...). --preset none: `animate --online`'s own decoding, with the offline models from --models
// (the repository's models/). Errors: one line naming the file, exit status 1, no output file left behind.
import fs from 'node:fs';
import path from 'node:path';
import { animate, PRESETS } from '../src/index.js';
import { loadCore } from '../src/core.js';
import { decodeWav } from '../src/wav.js';

const usage = `usage: talkinghead-web animate IN.wav -o OUT [--format F] [--preset ${PRESETS.join('|')}|none] [--models DIR] [--no-idle] [--seed N]`;

function parse(argv) {
  const args = { preset: 'default', idle: true, seed: 1 };
  if (argv[0] !== 'animate') throw new Error(usage);
  for (let i = 1; i < argv.length; ++i) {
    const arg = argv[i];
    const value = () => {
      if (i + 1 >= argv.length) throw new Error(`${arg} needs a value\n${usage}`);
      return argv[++i];
    };
    if (arg === '-o' || arg === '--output') args.output = value();
    else if (arg === '--format') args.format = value();
    else if (arg === '--preset') args.preset = value();
    else if (arg === '--models') args.models = value();
    else if (arg === '--seed') args.seed = Number(value());
    else if (arg === '--no-idle') args.idle = false;
    else if (arg === '-h' || arg === '--help') { console.log(usage); process.exit(0); }
    else if (arg.startsWith('-')) throw new Error(`unknown option ${arg}\n${usage}`);
    else if (!args.input) args.input = arg;
    else throw new Error(`one input only\n${usage}`);
  }
  if (!args.input || !args.output) throw new Error(usage);
  if (args.preset !== 'none' && !PRESETS.includes(args.preset))
    throw new Error(`--preset: no preset "${args.preset}" (there are ${PRESETS.join(', ')}, none)`);
  if (!Number.isInteger(args.seed) || args.seed < 0 || args.seed > 4294967295) throw new Error('--seed: a whole number 0 to 4294967295');
  return args;
}

async function main() {
  const args = parse(process.argv.slice(2));
  const core = await loadCore();
  let format;
  try {
    format = core.formatFor(args.output, args.format || '');
  } catch (error) {
    throw new Error(error.message);
  }
  const directory = path.dirname(path.resolve(args.output));
  if (!fs.existsSync(directory)) throw new Error(`${args.output}: its folder does not exist`);
  let bytes;
  try {
    bytes = fs.readFileSync(args.input);
  } catch (error) {
    throw new Error(`${args.input}: ${error.code === 'ENOENT' ? 'no such file' : error.message}`);
  }
  const { samples, sampleRate } = decodeWav(new Uint8Array(bytes.buffer, bytes.byteOffset, bytes.length), args.input);
  const result = await animate(samples, sampleRate, {
    preset: args.preset === 'none' ? null : args.preset, models: args.models, idle: args.idle, seed: args.seed,
    formats: [format],
  }).catch((error) => { throw new Error(`${args.input}: ${error.message.replace(/^talkinghead: /, '')}`); });
  // Written whole under another name, then renamed: an error leaves no partial file.
  const temporary = path.join(directory, `.${path.basename(args.output)}.${process.pid}.partial`);
  try {
    fs.writeFileSync(temporary, result.texts[format]);
    fs.renameSync(temporary, args.output);
  } catch (error) {
    fs.rmSync(temporary, { force: true });
    throw new Error(`${args.output}: ${error.message}`);
  }
  const frames = result.frames.length;
  console.log(`wrote ${args.output} (${format}): ${frames} frames at ${result.framesPerSecond} fps ` +
              `(${(frames / result.framesPerSecond).toFixed(1)} s), preset ${args.preset}`);
}

main().catch((error) => {
  console.error(`talkinghead-web: ${error.message}`);
  process.exit(1);
});
