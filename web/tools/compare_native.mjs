// The package's frames beside native talkinghead's on the same recording, FAP by FAP:
//
//   build/talkinghead animate SPEECH.wav -o native.csv --online --preset default
//   node web/tools/compare_native.mjs SPEECH.wav native.csv --preset default
//
//   build/talkinghead animate SPEECH.wav -o native.csv --online
//   node web/tools/compare_native.mjs SPEECH.wav native.csv --preset none --models models   # animate --online's own
//
// SPEECH.wav: any WAV the package reads (web/src/wav.js); at another rate than 16 kHz the package resamples with
// its own converter, natively libsoxr does. Prints the largest difference per FAP (FAP units; the jaw's range is
// about 1,000) and the time the package took; exits 1 if a FAP differs by more than --tolerance (default 0.01),
// 2 on bad input.
import fs from 'node:fs';
import { animate } from '../src/index.js';
import { decodeWav } from '../src/wav.js';
import { readCsv } from './compare_csv.mjs';

const args = process.argv.slice(2);
function option(name, fallback) {
  const at = args.indexOf(name);
  return at >= 0 ? args.splice(at, 2)[1] : fallback;
}
const tolerance = Number(option('--tolerance', '0.01'));
const preset = option('--preset', 'default');
const models = option('--models', undefined);
if (args.length !== 2 || !(tolerance >= 0)) {
  console.error('usage: node web/tools/compare_native.mjs SPEECH.wav NATIVE.csv [--preset P|none] [--models DIR] [--tolerance FAPU]');
  process.exit(2);
}
const [wavPath, csvPath] = args;
let wav, native;
try {
  wav = decodeWav(new Uint8Array(fs.readFileSync(wavPath)), wavPath);
  native = readCsv(csvPath);
} catch (error) {
  console.error(error.message);
  process.exit(2);
}
const started = performance.now();
const result = await animate(wav.samples, wav.sampleRate, { preset: preset === 'none' ? null : preset, models, fapTrack: true });
const seconds = (performance.now() - started) / 1000;
const { faps, values } = result.fapTrack;
const columns = native.header.slice(1).map((name) => Number(name.replace('fap', '')));
const frames = Math.min(native.rows.length, result.frames.length);
let worst = 0;
const lines = [];
for (const [c, fap] of columns.entries()) {
  const row = faps.indexOf(fap);
  if (row < 0) { lines.push(`  fap${fap}: not in the package's frames`); worst = Infinity; continue; }
  let largest = 0;
  for (let t = 0; t < frames; ++t) largest = Math.max(largest, Math.abs(values[t * faps.length + row] - native.rows[t][c + 1]));
  worst = Math.max(worst, largest);
  lines.push(`  fap${fap}: ${largest.toExponential(2)}`);
}
console.log(`${frames} frames (native ${native.rows.length}, package ${result.frames.length}); the package took ` +
            `${seconds.toFixed(2)} s (${(wav.samples.length / wav.sampleRate / seconds).toFixed(0)} times real time)`);
console.log(lines.join('\n'));
console.log(`largest difference ${worst.toExponential(2)} FAP units (tolerance ${tolerance})`);
process.exit(worst <= tolerance && native.rows.length === result.frames.length ? 0 : 1);
