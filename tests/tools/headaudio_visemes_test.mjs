// tools/headaudio_visemes.mjs (HeadAudio, the browser lip-sync peer, run under Node) on BEAT2's 2_scott_0_1_1.wav:
// a row per 30 fps frame, finite non-negative weights, silence before the first word (1.42 s by the TextGrid)
// read as sil, and several visemes over the recording; a file that is not a WAV fails cleanly.
//
//   bash scripts/install-node-tools.sh build
//   HEADAUDIO_MODULES=build/node/node_modules node --test tests/tools/headaudio_visemes_test.mjs
//
// TALKINGHEAD_DATA is the shared data folder (default ../shared/data beside the checkout). CTest runs it with the
// build's node modules (tests/tools/CMakeLists.txt); it fails when HeadAudio is not installed there.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const tool = path.resolve(here, '..', '..', 'tools', 'headaudio_visemes.mjs');
const modules = process.env.HEADAUDIO_MODULES || '';
const data = process.env.TALKINGHEAD_DATA || path.resolve(here, '..', '..', '..', 'shared', 'data');
const wav = path.join(data, 'beat2', '2_scott_0_1_1.wav');
const HEADER = 'time_s,sil,PP,FF,TH,DD,kk,CH,SS,nn,RR,aa,E,ih,oh,ou';

function missing() {
  if (!modules) return 'HEADAUDIO_MODULES is not set';
  if (!fs.existsSync(path.join(modules, '@met4citizen', 'headaudio', 'package.json')))
    return `@met4citizen/headaudio is not in ${modules}`;
  return '';
}

function run(args) {
  return spawnSync(process.execPath, [tool, '--modules', modules, ...args], { encoding: 'utf8' });
}

// Duration of a WAV from its fmt and data chunks.
function wavSeconds(file) {
  const b = fs.readFileSync(file);
  let rate = 0, blockAlign = 0;
  for (let pos = 12; pos + 8 <= b.length;) {
    const id = b.toString('latin1', pos, pos + 4);
    const size = b.readUInt32LE(pos + 4);
    if (id === 'fmt ') {
      rate = b.readUInt32LE(pos + 12);
      blockAlign = b.readUInt16LE(pos + 20);
    } else if (id === 'data') {
      return Math.floor(Math.min(size, b.length - pos - 8) / blockAlign) / rate;
    }
    pos += 8 + size + (size & 1);
  }
  throw new Error(`${file}: no data chunk`);
}

test('HeadAudio reads BEAT2 speech frame by frame', () => {
  assert.equal(missing(), '', 'HeadAudio must be installed (scripts/install-node-tools.sh BUILD)');
  assert.ok(fs.existsSync(wav), `${wav} is not there`);
  const out = fs.mkdtempSync(path.join(os.tmpdir(), 'headaudio-'));
  try {
    const r = run([wav, '-o', out]);
    assert.equal(r.status, 0, r.stderr);
    const lines = fs.readFileSync(path.join(out, '2_scott_0_1_1.csv'), 'utf8').trimEnd().split('\n');
    assert.equal(lines[0], HEADER);
    const rows = lines.slice(1).map((line) => line.split(',').map(Number));
    const expected = Math.ceil(wavSeconds(wav) * 30);
    assert.ok(Math.abs(rows.length - expected) <= 1, `${rows.length} rows for ${expected} frames`);
    const names = HEADER.split(',').slice(1);
    const argmax = rows.map((row, i) => {
      assert.equal(row.length, 16, `row ${i}`);
      assert.ok(Math.abs(row[0] - i / 30) < 1e-5, `row ${i} is at ${row[0]} s`);
      const w = row.slice(1);
      assert.ok(w.every((x) => Number.isFinite(x) && x >= 0), `row ${i}: ${lines[i + 1]}`);
      return names[w.indexOf(Math.max(...w))];
    });
    const before = argmax.filter((_, i) => i / 30 < 1.2);
    const silent = before.filter((v) => v === 'sil').length;
    assert.ok(silent >= 0.8 * before.length, `${silent} of ${before.length} frames before speech are sil`);
    const distinct = new Set(argmax);
    assert.ok(distinct.size >= 5, `argmax visemes: ${[...distinct].join(' ')}`);
  } finally {
    fs.rmSync(out, { recursive: true, force: true });
  }
});

test('a file that is not a WAV fails with one line and no CSV', () => {
  assert.equal(missing(), '', 'HeadAudio must be installed (scripts/install-node-tools.sh BUILD)');
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'headaudio-bad-'));
  try {
    const bad = path.join(dir, 'x.wav');
    fs.writeFileSync(bad, 'this is text, not sound\n');
    const out = path.join(dir, 'out');
    const r = run([bad, '-o', out]);
    assert.equal(r.status, 1, r.stderr);
    const errors = r.stderr.trimEnd().split('\n');
    assert.equal(errors.length, 1, r.stderr);
    assert.ok(errors[0].includes(bad), errors[0]);
    const left = fs.existsSync(out) ? fs.readdirSync(out) : [];
    assert.deepEqual(left, []);
  } finally {
    fs.rmSync(dir, { recursive: true, force: true });
  }
});
