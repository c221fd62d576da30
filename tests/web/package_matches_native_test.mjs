// The web package under Node (web/, built by scripts/build-web.sh into web/dist/) against native talkinghead on
// the same 64 s of speech:
// - animate() with the default preset and with animate --online's own decoding: each FAP within 0.01 FAP units
//   (web/tools/compare_native.mjs; the jaw's range is about 1,000);
// - the command `talkinghead-web animate IN.wav -o OUT --format oculus|arkit|csv`: the text native animate writes,
//   each weight within one unit of its last printed digit (the two builds' roundings may fall either side);
// - another sample rate: the package's resampler against libsoxr's, the jaw within 0.02 of ARKit's range;
// - bad input: one line naming the file, exit status 1, no output file.
//
// Environment: TALKINGHEAD (the native program), TALKINGHEAD_DATA (the shared data).
import assert from 'node:assert/strict';
import { execFileSync, spawnSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import test from 'node:test';
import { fileURLToPath } from 'node:url';
import { compareCsv, readCsv } from '../../web/tools/compare_csv.mjs';

const repo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
const native = process.env.TALKINGHEAD;
const data = process.env.TALKINGHEAD_DATA ?? path.join(repo, '../shared/data');
const speech = path.join(data, 'beat2/2_scott_0_1_1.wav');
const command = path.join(repo, 'web/bin/talkinghead-web.js');
const work = fs.mkdtempSync(path.join(os.tmpdir(), 'web-package-'));
test.after(() => fs.rmSync(work, { recursive: true, force: true }));

test('the package is built (bash scripts/build-web.sh)', () => {
  for (const file of ['talkinghead_core.wasm', 'talkinghead_core.js', 'models/articulation_live.json'])
    assert.ok(fs.existsSync(path.join(repo, 'web/dist', file)), `web/dist/${file}: missing`);
});

function nativeAnimate(input, output, extra) {
  execFileSync(native, ['animate', input, '-o', output, '--online', ...extra], { stdio: 'ignore' });
}

function compareFaps(nativeCsv, extra) {
  const run = spawnSync('node', [path.join(repo, 'web/tools/compare_native.mjs'), speech, nativeCsv, ...extra], { encoding: 'utf8' });
  process.stdout.write(run.stdout.split('\n').filter((line) => !line.startsWith('  ')).join('\n'));
  assert.equal(run.status, 0, run.stdout + run.stderr);
}

test("animate() with the default preset makes native animate --online --preset default's frames", () => {
  const csv = path.join(work, 'preset.csv');
  nativeAnimate(speech, csv, ['--preset', 'default']);
  compareFaps(csv, ['--preset', 'default']);
});

test("animate() with no preset makes native animate --online's frames (the offline models from models/)", () => {
  const csv = path.join(work, 'online.csv');
  nativeAnimate(speech, csv, []);
  compareFaps(csv, ['--preset', 'none', '--models', path.join(repo, 'models')]);
});

test('talkinghead-web animate writes the text native animate writes', () => {
  for (const format of ['oculus', 'arkit', 'vrm']) {
    const ours = path.join(work, `web_${format}.csv`), theirs = path.join(work, `native_${format}.csv`);
    nativeAnimate(speech, theirs, ['--preset', 'default', '--format', format]);
    const run = spawnSync('node', [command, 'animate', speech, '-o', ours, '--format', format], { encoding: 'utf8' });
    assert.equal(run.status, 0, run.stderr);
    assert.match(run.stdout, new RegExp(`wrote .*web_${format}.csv \\(${format}\\): 1923 frames at 30 fps`));
    const result = compareCsv(readCsv(theirs), readCsv(ours), 1e-4 + 1e-9);
    assert.equal(result.error, undefined, result.error);
    console.log(`${format}: ${result.frames} frames, largest difference ${result.largest.toExponential(2)}`);
    assert.deepEqual(result.over, [], `${format}: more than one unit of the last digit apart`);
  }
});

test("at another rate the package's resampler and libsoxr give the same motion within 0.02", () => {
  const arctic = path.join(data, 'speech/arctic/arctic_a0001.wav');  // 24 kHz
  const ours = path.join(work, 'arctic_web.csv'), theirs = path.join(work, 'arctic_native.csv');
  nativeAnimate(arctic, theirs, ['--preset', 'default', '--format', 'arkit']);
  const run = spawnSync('node', [command, 'animate', arctic, '-o', ours, '--format', 'arkit'], { encoding: 'utf8' });
  assert.equal(run.status, 0, run.stderr);
  const result = compareCsv(readCsv(theirs), readCsv(ours), 0.02);
  console.log(`24 kHz: largest ARKit difference ${result.largest.toExponential(2)}`);
  assert.equal(result.error, undefined, result.error);
  assert.deepEqual(result.over, []);
});

test('bad input fails in one line naming the file, and leaves no output', () => {
  const notWav = path.join(work, 'notes.wav');
  fs.writeFileSync(notWav, 'these are notes, not a sound');
  const low = path.join(work, 'low.wav');
  const header = Buffer.alloc(44 + 8000);  // 1 s of silence at 4 kHz
  header.write('RIFF', 0); header.writeUInt32LE(36 + 8000, 4); header.write('WAVEfmt ', 8); header.writeUInt32LE(16, 16);
  header.writeUInt16LE(1, 20); header.writeUInt16LE(1, 22); header.writeUInt32LE(4000, 24); header.writeUInt32LE(8000, 28);
  header.writeUInt16LE(2, 32); header.writeUInt16LE(16, 34); header.write('data', 36); header.writeUInt32LE(8000, 40);
  fs.writeFileSync(low, header);
  const cases = [
    [[notWav, '--format', 'oculus'], 'notes.wav: not a WAV file'],
    [[path.join(work, 'missing.wav')], 'missing.wav: no such file'],
    [[low], 'low.wav: cannot resample 4000 Hz'],
    [[speech, '--preset', 'fastest'], 'no preset "fastest"'],
    [[speech, '--format', 'mp3'], 'mp3'],
  ];
  for (const [extra, reason] of cases) {
    const output = path.join(work, 'out.csv');
    const run = spawnSync('node', [command, 'animate', extra[0], '-o', output, ...extra.slice(1)], { encoding: 'utf8' });
    assert.equal(run.status, 1, `${extra.join(' ')}: exit ${run.status}`);
    assert.equal(run.stderr.trim().split('\n').length, 1, run.stderr);
    assert.ok(run.stderr.includes(reason), `${run.stderr} lacks "${reason}"`);
    assert.ok(!fs.existsSync(output), `${extra.join(' ')}: left ${output}`);
    assert.deepEqual(fs.readdirSync(work).filter((name) => name.endsWith('.partial')), []);
  }
});
