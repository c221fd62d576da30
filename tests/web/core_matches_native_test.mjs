// The WebAssembly core (web/, built by scripts/build-web.sh into web/dist/) against native talkinghead on the
// same 64 s of speech: `animate --online`'s frames, and the live default preset's decoder streamed in blocks of
// 128 samples against `live --headless --dump`'s; each FAP within 0.01 FAP units (web/tools/compare_native.mjs).
// And its errors: a bad preset is one line, as natively.
//
// Environment: TALKINGHEAD (the native program), TALKINGHEAD_DATA (the shared data).
import assert from 'node:assert/strict';
import { execFileSync, spawnSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import test from 'node:test';
import { fileURLToPath } from 'node:url';

const repo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
const dist = path.join(repo, 'web/dist');
const native = process.env.TALKINGHEAD;
const speech = path.join(process.env.TALKINGHEAD_DATA ?? path.join(repo, '../shared/data'), 'beat2/2_scott_0_1_1.wav');
const compare = path.join(repo, 'web/tools/compare_native.mjs');
const work = fs.mkdtempSync(path.join(os.tmpdir(), 'web-core-'));
test.after(() => fs.rmSync(work, { recursive: true, force: true }));

test('the module is built (bash scripts/build-web.sh)', () => {
  assert.ok(fs.existsSync(path.join(dist, 'talkinghead_core.wasm')), `${dist}: no talkinghead_core.wasm`);
});

function compared(nativeCsv, extra = []) {
  const run = spawnSync('node', [compare, speech, nativeCsv, ...extra], { encoding: 'utf8' });
  process.stdout.write(run.stdout);
  assert.equal(run.status, 0, run.stdout + run.stderr);
}

test('animateOnline makes the frames of native animate --online', () => {
  const csv = path.join(work, 'online.csv');
  execFileSync(native, ['animate', speech, '-o', csv, '--online'], { stdio: 'ignore' });
  compared(csv);
});

test("the default preset's stream decoder makes the frames of native live", () => {
  const csv = path.join(work, 'live.csv');
  execFileSync(native, ['live', '--headless', '--input', speech, '--speed', '20', '--no-idle', '--dump', csv],
               { stdio: 'ignore' });
  compared(csv, ['--stream', 'default']);
});

test('a preset that does not exist is one clear error', async () => {
  const { default: createTalkingheadCore } = await import(path.join(dist, 'talkinghead_core.js'));
  const core = await createTalkingheadCore({ wasmBinary: fs.readFileSync(path.join(dist, 'talkinghead_core.wasm')) });
  core.FS.mkdir('/models');
  for (const name of fs.readdirSync(path.join(repo, 'models')))
    core.FS.writeFile(`/models/${name}`, fs.readFileSync(path.join(repo, 'models', name)));
  assert.throws(() => new core.StreamDecoder('fastest', false), /no preset "fastest" \(there are default, low-latency, accurate\)/);
  const decoder = new core.StreamDecoder('low-latency', false);
  assert.throws(() => decoder.accept(5000), /a block holds at most 4096 samples/);
  decoder.delete();
});
