// The WebAssembly core's frames beside native talkinghead's on the same speech, FAP by FAP:
//
//   build/talkinghead animate SPEECH.wav -o native.csv --online
//   node web/tools/compare_native.mjs SPEECH.wav native.csv
//
//   build/talkinghead live --headless --input SPEECH.wav --speed 20 --no-idle --dump live.csv
//   node web/tools/compare_native.mjs SPEECH.wav live.csv --stream default      # the live preset's decoder
//
// With --stream PRESET the samples go through the core's StreamDecoder in blocks of 128 (an AudioWorklet's), and
// the time each block took is reported (median, 99th percentile, largest). SPEECH.wav: 16 kHz mono (16-bit or
// float; the core takes 16 kHz samples, and this tool does not resample). Prints the largest difference per FAP
// (FAP units) and the time the core took; exits 1 if a FAP differs by more than --tolerance (default 0.01 FAP
// units, a hundred-thousandth of the jaw's range), 2 on bad input.
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const repo = path.resolve(here, '../..');
const args = process.argv.slice(2);
function option(name, fallback) {
  const at = args.indexOf(name);
  return at >= 0 ? args.splice(at, 2)[1] : fallback;
}
const tolerance = Number(option('--tolerance', '0.01'));
const preset = option('--stream', null);
if (args.length !== 2 || !(tolerance >= 0)) {
  console.error('usage: node web/tools/compare_native.mjs SPEECH.wav NATIVE.csv [--stream PRESET] [--tolerance FAPU]');
  process.exit(2);
}
const [wavPath, csvPath] = args;

// A WAV's samples (16-bit PCM or 32-bit float, mono, 16 kHz).
function readWav(file) {
  const bytes = fs.readFileSync(file);
  if (bytes.toString('ascii', 0, 4) !== 'RIFF' || bytes.toString('ascii', 8, 12) !== 'WAVE')
    throw new Error(`${file}: not a WAV file`);
  let format = 0, bits = 0, channels = 0, rate = 0, data = null;
  for (let at = 12; at + 8 <= bytes.length;) {
    const id = bytes.toString('ascii', at, at + 4), size = bytes.readUInt32LE(at + 4);
    if (id === 'fmt ') {
      format = bytes.readUInt16LE(at + 8); channels = bytes.readUInt16LE(at + 10);
      rate = bytes.readUInt32LE(at + 12); bits = bytes.readUInt16LE(at + 22);
    } else if (id === 'data') {
      data = bytes.subarray(at + 8, Math.min(bytes.length, at + 8 + size));
      break;
    }
    at += 8 + size + (size & 1);
  }
  if (!data || channels !== 1 || rate !== 16000 || !((format === 1 && bits === 16) || (format === 3 && bits === 32)))
    throw new Error(`${file}: needs 16 kHz mono, 16-bit or float samples`);
  const count = data.length / (bits / 8);
  const samples = new Float32Array(count);
  for (let i = 0; i < count; ++i) samples[i] = format === 3 ? data.readFloatLE(4 * i) : data.readInt16LE(2 * i) / 32768;
  return samples;
}

// The core's frames: {faps: [numbers], frames: [Float64Array per frame]} and what the run took.
function animateAll(core, samples) {
  const track = core.animateOnline(samples);
  const frames = [];
  for (let at = 0; at < track.values.length; at += track.faps.length)
    frames.push(track.values.subarray(at, at + track.faps.length));
  return { faps: track.faps, frames };
}
function stream(core, samples, presetName) {
  const decoder = new core.StreamDecoder(presetName, false);
  const frames = [], blockMs = [];
  const take = () => { for (let frame; (frame = decoder.next()) !== null;) frames.push(frame.faps); };
  for (let at = 0; at < samples.length; at += 128) {
    const block = samples.subarray(at, Math.min(samples.length, at + 128));
    const started = performance.now();
    decoder.input().set(block);
    decoder.accept(block.length);
    take();
    blockMs.push(performance.now() - started);
  }
  decoder.finish();
  take();
  const faps = decoder.fapNumbers();
  decoder.delete();
  blockMs.sort((a, b) => a - b);
  const at = (q) => blockMs[Math.min(blockMs.length - 1, Math.floor(q * blockMs.length))].toFixed(3);
  console.log(`blocks of 128 samples: median ${at(0.5)} ms, 99th percentile ${at(0.99)} ms, largest ` +
              `${blockMs[blockMs.length - 1].toFixed(3)} ms`);
  return { faps, frames };
}

let samples;
try {
  samples = readWav(wavPath);
} catch (error) {
  console.error(`compare_native: ${error.message}`);
  process.exit(2);
}
const { default: createTalkingheadCore } = await import(path.join(repo, 'web/dist/talkinghead_core.js'));
const core = await createTalkingheadCore({ wasmBinary: fs.readFileSync(path.join(repo, 'web/dist/talkinghead_core.wasm')) });
core.FS.mkdir('/models');
for (const name of fs.readdirSync(path.join(repo, 'models')))
  core.FS.writeFile(`/models/${name}`, fs.readFileSync(path.join(repo, 'models', name)));

const started = performance.now();
const made = preset ? stream(core, samples, preset) : animateAll(core, samples);
const milliseconds = performance.now() - started;
const lines = fs.readFileSync(csvPath, 'utf8').trim().split('\n');
const header = lines[0].split(',');
if (made.frames.length !== lines.length - 1) {
  console.error(`compare_native: the core made ${made.frames.length} frames, ${csvPath} has ${lines.length - 1}`);
  process.exit(1);
}
const largest = new Map();
for (let t = 1; t < lines.length; ++t) {
  const row = lines[t].split(',').map(Number);
  for (let c = 1; c < header.length; ++c) {
    const fap = Number(header[c].replace('fap', ''));
    const column = made.faps.indexOf(fap);
    const value = column >= 0 ? made.frames[t - 1][column] : 0;  // a FAP the core does not set is 0
    const difference = Math.abs(value - row[c]);
    if (!(largest.get(fap)?.difference >= difference)) largest.set(fap, { difference, frame: t - 1 });
  }
}
const audioSeconds = samples.length / 16000;
console.log(`${made.frames.length} frames (${audioSeconds.toFixed(1)} s of speech) in ${(milliseconds / 1000).toFixed(2)} s ` +
            `(models loaded and run): ${(audioSeconds * 1000 / milliseconds).toFixed(0)} times real time`);
console.log('largest difference per FAP (FAP units, at frame):');
console.log([...largest].map(([fap, { difference, frame }]) => `${fap}: ${difference.toExponential(1)} (${frame})`).join(', '));
const worst = Math.max(...[...largest.values()].map((entry) => entry.difference));
console.log(`largest: ${worst.toExponential(2)}; tolerance ${tolerance}`);
process.exit(worst <= tolerance ? 0 : 1);
