// The web package in a real browser: Debian's Chromium, headless, driven through the DevTools protocol
// (puppeteer-core with the system browser; nothing is downloaded).
//
//   node tests/web/browser_test.mjs --talkinghead build/talkinghead --block-cost build/bench/block_cost --out DIR
//        [--passes 5]
//
// 1. Equality: BEAT2's 64 s played through the worklet (an OfflineAudioContext at the file's 16 kHz, every
//    sample as in the file; the default preset, each frame with its own head) against native
//    `talkinghead animate --online --preset default` of the same file: every frame's Oculus visemes against native's
//    oculus CSV, its ARKit weights, head quaternion, blinks and gaze against the same made from native's FAP CSV
//    by the package's own conversion. Within 1e-4, and the class shown the same.
// 2. The example page, live: its character (the shared Ready Player Me avatar) driven from a fake microphone
//    playing silence, speech, silence; screenshots with the mouth open on speech and shut in silence (the mouth's
//    pixels differ between them), the sound-to-frame latency against the preset's look-ahead.
// 3. The error paths (a closed context, a rate it cannot resample, an unknown preset, a file that is no sound) and
//    disconnect() (no frame after it).
// 4. The benchmark: the worklet's per-block work in WebAssembly on a cross-origin isolated page, beside the native
//    build's (bench/block_cost), the same steps on the same samples, each block the least of --passes passes; the
//    ratio is printed, not asserted.
// 5. The recipe for TalkingHead's users (web/examples/talkinghead.html): its avatar speaks from our frames.
// Writes DIR/report.json and the screenshots; exits 1 on a failed check.
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { createRequire } from 'node:module';
import { serve } from '../../web/tools/serve.mjs';
import { readCsv } from '../../web/tools/compare_csv.mjs';
import { decodeWav } from '../../web/src/wav.js';
import { loadCore } from '../../web/src/core.js';
import { frameOf } from '../../web/src/frames.js';

const here = path.dirname(fileURLToPath(import.meta.url));
// puppeteer-core is the web package's development dependency (web/node_modules, scripts/build-web.sh).
const fromWeb = createRequire(path.join(here, '../../web/package.json'));
const puppeteer = (await import(fromWeb.resolve('puppeteer-core'))).default;
const args = process.argv.slice(2);
const option = (name, fallback) => { const at = args.indexOf(name); return at >= 0 ? args[at + 1] : fallback; };
const talkinghead = option('--talkinghead');
const blockCost = option('--block-cost');
const passes = Number(option('--passes', '5'));
const data = path.resolve(option('--data', process.env.TALKINGHEAD_DATA || path.join(here, '../../../shared/data')));
const out = path.resolve(option('--out', '') || fs.mkdtempSync('/tmp/talkinghead-web-'));
const browserPath = option('--browser', process.env.CHROMIUM || '/usr/bin/chromium');
fs.mkdirSync(out, { recursive: true });

const failures = [];
const check = (ok, what) => {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failures.push(what);
};
const report = {};

function run(command, commandArgs) {
  const result = spawnSync(command, commandArgs, { encoding: 'utf8' });
  if (result.status !== 0) throw new Error(`${command} ${commandArgs.join(' ')}: ${result.stderr || result.error}`);
  return result.stdout;
}

// A 16 kHz 16-bit WAV of the samples.
function writeWav(file, samples, rate) {
  const bytes = Buffer.alloc(44 + 2 * samples.length);
  bytes.write('RIFF', 0); bytes.writeUInt32LE(36 + 2 * samples.length, 4); bytes.write('WAVEfmt ', 8);
  bytes.writeUInt32LE(16, 16); bytes.writeUInt16LE(1, 20); bytes.writeUInt16LE(1, 22); bytes.writeUInt32LE(rate, 24);
  bytes.writeUInt32LE(2 * rate, 28); bytes.writeUInt16LE(2, 32); bytes.writeUInt16LE(16, 34); bytes.write('data', 36);
  bytes.writeUInt32LE(2 * samples.length, 40);
  samples.forEach((v, i) => bytes.writeInt16LE(Math.max(-32768, Math.min(32767, Math.round(v * 32767))), 44 + 2 * i));
  fs.writeFileSync(file, bytes);
}

const beat2 = path.join(data, 'beat2/2_scott_0_1_1.wav');
const avatars = path.join(data, 'face/avatars');
const { samples: speech, sampleRate } = decodeWav(new Uint8Array(fs.readFileSync(beat2)), beat2);
// The fake microphone's sound: 1.5 s of silence, 4 s of speech, 2.5 s of silence (it loops).
const clip = path.join(out, 'silence_speech_silence.wav');
const gap = (seconds) => new Float32Array(Math.round(seconds * sampleRate));
writeWav(clip, Float32Array.from([...gap(1.5), ...speech.subarray(2 * sampleRate, 6 * sampleRate), ...gap(2.5)]), sampleRate);

// The recording the worklet plays, cut to whole 128-sample blocks (an AudioWorklet hears whole blocks: a last part
// block would reach it padded with silence).
const played16k = path.join(out, 'beat2_blocks.wav');
writeWav(played16k, speech.subarray(0, speech.length - (speech.length % 128)), sampleRate);

// Native, first: the frames the worklet must equal.
const nativeFaps = path.join(out, 'native.csv');
const nativeOculus = path.join(out, 'native_oculus.csv');
run(talkinghead, ['animate', played16k, '-o', nativeFaps, '--online', '--preset', 'default']);
run(talkinghead, ['animate', played16k, '-o', nativeOculus, '--online', '--preset', 'default', '--format', 'oculus']);

const server = await serve({ mounts: { '/models': path.join(here, '../../models'), '/avatars': avatars, '/clips': out, '/data': path.dirname(beat2), '/tests': path.join(here, 'pages') }, isolated: true });
const origin = `http://127.0.0.1:${server.address().port}`;
// Chromium's sound goes to no server: the live device tests start and kill a PulseAudio daemon beside this test,
// and a browser whose output stream was on it stopped rendering (its AudioContext never resumed, the page's calls
// hung until the protocol's 180 s timeout). With no server it plays to its own fake output, on its own clock.
const browser = await puppeteer.launch({
  executablePath: browserPath,
  headless: true,
  env: { ...process.env, PULSE_SERVER: 'unix:/nonexistent/talkinghead-browser-test' },
  args: ['--no-sandbox', '--autoplay-policy=no-user-gesture-required', '--use-fake-ui-for-media-stream',
         '--use-fake-device-for-media-stream', `--use-file-for-fake-audio-capture=${clip}`, '--enable-unsafe-swiftshader',
         '--use-angle=swiftshader'],
});
const pageErrors = [];
async function open(url) {
  const page = await browser.newPage();
  page.on('pageerror', (error) => pageErrors.push(`${url}: ${error.message}`));
  await page.setViewport({ width: 640, height: 640 });
  await page.goto(`${origin}${url}`);
  return page;
}

try {
  // 1. Equality.
  const harness = await open('/tests/harness.html');
  await harness.waitForFunction(() => window.harness && window.harness.ready, { timeout: 30000 });
  const played = await harness.evaluate((url) => window.harness.worklet(url, { preset: 'default', waitForHead: true }),
    '/clips/beat2_blocks.wav');
  const native = readCsv(nativeFaps);
  const oculus = readCsv(nativeOculus);
  const core = await loadCore();
  const nativeAnimation = core.readAnimation(fs.readFileSync(nativeFaps, 'utf8'), 'csv');
  const largest = { visemes: 0, arkit: 0, headQuaternion: 0, blink: 0, gaze: 0 };
  const where = {};
  let classes = 0;
  const note = (field, difference, index) => { if (difference > largest[field]) { largest[field] = difference; where[field] = index; } };
  const frames = played.frames;
  check(frames.length === native.rows.length, `the worklet gave ${frames.length} frames, native ${native.rows.length}`);
  for (let i = 0; i < Math.min(frames.length, native.rows.length); ++i) {
    const web = frames[i];
    nativeAnimation.select(i);
    const ours = frameOf(nativeAnimation.record(), core.layout);
    web.visemes.forEach((v, k) => note('visemes', Math.abs(v - oculus.rows[i][k + 1]), i));
    web.arkit.forEach((v, k) => note('arkit', Math.abs(v - ours.arkit[k]), i));
    web.headQuaternion.forEach((v, k) => note('headQuaternion', Math.abs(v - ours.headQuaternion[k]), i));
    note('blink', Math.max(Math.abs(web.blink.left - ours.blink.left), Math.abs(web.blink.right - ours.blink.right)), i);
    note('gaze', Math.max(Math.abs(web.gaze.yaw - ours.gaze.yaw), Math.abs(web.gaze.pitch - ours.gaze.pitch)), i);
    const nativeClass = oculus.rows[i].slice(1).indexOf(Math.max(...oculus.rows[i].slice(1)));
    const webClass = web.visemes.indexOf(Math.max(...web.visemes));
    classes += nativeClass === webClass ? 1 : 0;
  }
  nativeAnimation.delete();
  report.equality = { frames: frames.length, largest, where, sameStrongestViseme: classes, lookaheadMs: played.lookaheadMs };
  for (const [field, value] of Object.entries(largest))
    check(value <= 1e-4, `${field}: the worklet's frames within ${value.toExponential(2)} of native animate --online --preset default's (at most 1e-4)`);
  check(classes === frames.length, `the strongest viseme the same on ${classes} of ${frames.length} frames`);

  // 3. Errors and disconnect().
  const errors = await harness.evaluate(() => window.harness.errors());
  report.errors = errors;
  check(/the AudioContext is closed/.test(errors.closedContext), `a closed context: "${errors.closedContext}"`);
  check(/cannot resample 4000 Hz/.test(errors.unsupportedRate), `a 4 kHz context: "${errors.unsupportedRate}"`);
  check(/no preset "fastest"/.test(errors.unknownPreset), `an unknown preset: "${errors.unknownPreset}"`);
  check(/notes\.txt: not an audio file/.test(errors.notAudio), `a file that is no sound: "${errors.notAudio}"`);
  check(/cannot resample 2000 Hz/.test(errors.animateRate), `animate() at 2 kHz: "${errors.animateRate}"`);
  for (const [what, message] of Object.entries(errors)) check(!message.includes('\n'), `${what}: one line`);
  const stopped = await harness.evaluate(() => window.harness.disconnect());
  report.disconnect = stopped;
  check(stopped.before >= 10 && stopped.after === stopped.atStop && stopped.ended,
    `disconnect(): ${stopped.before} frames before, ${stopped.after - stopped.atStop} in the second after`);

  // Each preset's latency: stated (the look-ahead) and measured (sound to frame, live).
  report.latency = {};
  for (const preset of ['default', 'low-latency', 'accurate']) {
    const measured = await harness.evaluate((p) => window.harness.latency(p, p === 'accurate' ? '/models/' : undefined), preset);
    report.latency[preset] = measured;
    console.log(`     ${preset}: look-ahead ${measured.lookaheadMs.toFixed(1)} ms, sound to frame median ${measured.medianMs.toFixed(1)} ms, ` +
                `${measured.skippedBlocks} render quanta skipped by the audio thread`);
    check(measured.medianMs >= measured.lookaheadMs - 1 && measured.medianMs <= measured.lookaheadMs + 2 * 128 / 48 + 1,
      `${preset}: frames ${measured.medianMs.toFixed(1)} ms after their sound, the look-ahead ${measured.lookaheadMs.toFixed(1)} ms`);
  }

  // 4. The benchmark, WebAssembly beside native.
  // On a page of its own, the harness's closed: nothing else of this test runs in the browser while it times.
  await harness.close();
  const benchPage = await open('/tests/harness.html');
  await benchPage.waitForFunction(() => window.harness && window.harness.ready, { timeout: 30000 });
  const wasm = await benchPage.evaluate((url, n) => window.harness.bench(url, 'default', 48000, n), '/data/2_scott_0_1_1.wav', passes);
  await benchPage.close();
  const nativeCost = JSON.parse(run(blockCost, [beat2, '--preset', 'default', '--rate', '48000', '--passes', String(passes)]));
  report.benchmark = { wasm, native: nativeCost, medianRatio: wasm.median_ms / nativeCost.median_ms, p99Ratio: wasm.p99_ms / nativeCost.p99_ms };
  console.log(`     per 128-sample block at 48 kHz, the least of ${wasm.passes} passes: WebAssembly median ${wasm.median_ms.toFixed(3)} ms, ` +
              `p99 ${wasm.p99_ms.toFixed(3)} ms; native median ${nativeCost.median_ms.toFixed(3)} ms, p99 ${nativeCost.p99_ms.toFixed(3)} ms ` +
              `(${report.benchmark.medianRatio.toFixed(2)}x, ${report.benchmark.p99Ratio.toFixed(2)}x); the slowest pass's p99 as timed: ` +
              `WebAssembly ${wasm.slowest_pass_p99_ms.toFixed(3)} ms, native ${nativeCost.slowest_pass_p99_ms.toFixed(3)} ms`);
  check(wasm.isolated && wasm.blocks === nativeCost.blocks && wasm.passes === nativeCost.passes,
    `the benchmark page timed ${wasm.blocks} blocks ${wasm.passes} times, native ${nativeCost.blocks} ${nativeCost.passes} times`);

  // 2. The example page, live from the (fake) microphone.
  const example = await open('/examples/?avatar=/avatars/brunette-t.glb');
  await example.waitForFunction(() => window.demo && window.demo.ready, { timeout: 60000 });
  await example.evaluate(() => window.demo.start());
  const state = () => example.evaluate(() => {
    const f = window.demo.lastFrame;
    return { frames: window.demo.frames, errors: window.demo.errors, lookaheadMs: window.demo.lookaheadMs,
             latencies: window.demo.latencies.slice(-60), character: window.demo.character,
             jaw: f ? f.arkit[17] : null, level: f ? f.levelDb : null,
             open: f ? 1 - f.visemes[0] : null };
  });
  const shots = {};
  let quietSince = null;
  const started = Date.now();
  while (Date.now() - started < 20000 && !(shots.open && shots.shut)) {
    const s = await state();
    if (s.open !== null && !shots.open && s.open > 0.9 && s.jaw > 0.3) {
      shots.open = { file: path.join(out, 'mouth_open.png'), state: s };
      await example.screenshot({ path: shots.open.file });
    }
    if (s.level !== null && s.level < -60) quietSince = quietSince ?? Date.now();
    else quietSince = null;
    if (shots.open && !shots.shut && quietSince && Date.now() - quietSince > 700) {
      shots.shut = { file: path.join(out, 'mouth_shut.png'), state: s };
      await example.screenshot({ path: shots.shut.file });
    }
    await new Promise((resolve) => setTimeout(resolve, 40));
  }
  const live = await state();
  const rect = await example.evaluate(() => window.demo.mouthRect());
  report.example = { character: live.character, frames: live.frames, lookaheadMs: live.lookaheadMs,
                     latencyMs: live.latencies, mouthRect: rect, open: shots.open?.state, shut: shots.shut?.state, errors: live.errors };
  check(live.character && live.character.morphMeshes > 0 && live.character.head, `the example drew ${live.character?.label} with its morph targets and Head bone`);
  check(!!shots.open && !!shots.shut, 'screenshots with the mouth open on speech and shut in silence');
  if (shots.open && shots.shut && rect) {
    // The mouth's pixels: darker and different when open. The same measure on the forehead, for scale.
    const { mouthDifference, elsewhere } = await example.evaluate(async (a, b, r) => {
      const load = (src) => new Promise((resolve) => { const image = new Image(); image.onload = () => resolve(image); image.src = src; });
      const pixels = async (src, x, y, w, h) => {
        const image = await load(src);
        const canvas = new OffscreenCanvas(image.width, image.height);
        const context = canvas.getContext('2d');
        context.drawImage(image, 0, 0);
        return context.getImageData(Math.round(x), Math.round(y), Math.max(1, Math.round(w)), Math.max(1, Math.round(h))).data;
      };
      const difference = async (x, y, w, h) => {
        const [p, q] = [await pixels(a, x, y, w, h), await pixels(b, x, y, w, h)];
        let sum = 0;
        for (let i = 0; i < p.length; i += 4) sum += Math.abs(p[i] - q[i]) + Math.abs(p[i + 1] - q[i + 1]) + Math.abs(p[i + 2] - q[i + 2]);
        return sum / (p.length / 4) / 3;
      };
      return { mouthDifference: await difference(r.x, r.y, r.width, r.height),
               elsewhere: await difference(r.x, r.y - 2.2 * r.height, r.width, r.height) };
    }, `data:image/png;base64,${fs.readFileSync(shots.open.file).toString('base64')}`,
       `data:image/png;base64,${fs.readFileSync(shots.shut.file).toString('base64')}`, rect);
    report.example.pixels = { mouthDifference, elsewhere };
    check(mouthDifference > 8 && mouthDifference > 3 * elsewhere,
      `the mouth's pixels differ by ${mouthDifference.toFixed(1)} levels between open and shut (the nose's ${elsewhere.toFixed(1)})`);
  }
  const latencies = live.latencies.slice().sort((a, b) => a - b);
  const medianLatency = latencies[Math.floor(latencies.length / 2)];
  report.example.medianLatencyMs = medianLatency;
  check(medianLatency >= live.lookaheadMs - 1 && medianLatency <= live.lookaheadMs + 2 * 128 / 48 + 1,
    `sound to frame: median ${medianLatency?.toFixed(1)} ms, the preset's look-ahead ${live.lookaheadMs?.toFixed(1)} ms`);
  check(live.errors.length === 0, `the example page reported no errors (${live.errors.join('; ')})`);
  // A dropped sound file plays through the node; a dropped file that is no sound is one message.
  const dropped = await example.evaluate(async () => {
    const wav = await (await fetch('/clips/silence_speech_silence.wav')).blob();
    await window.demo.playFile(new File([wav], 'clip.wav'));
    // Frames of it until 50 have come (1.7 s of its sound), or 10 s: on a loaded machine the browser's audio
    // clock runs behind the wall clock (38 frames in 2.5 s were seen), and what this checks is that it plays.
    const before = window.demo.frames;
    const started = performance.now();
    while (window.demo.frames - before < 50 && performance.now() - started < 10000)
      await new Promise((resolve) => setTimeout(resolve, 50));
    const played = window.demo.frames - before;
    const seconds = (performance.now() - started) / 1000;
    await window.demo.playFile(new File(['not a sound'], 'notes.txt'));
    return { played, seconds, source: window.demo.source, errors: window.demo.errors };
  });
  report.example.dropped = dropped;
  check(dropped.played >= 50 && dropped.source === 'clip.wav',
    `a dropped sound file: ${dropped.played} frames in ${dropped.seconds.toFixed(1)} s`);
  check(dropped.errors.length === 1 && /notes\.txt: not a sound/.test(dropped.errors[0]),
    `a dropped file that is no sound: "${dropped.errors.join('; ')}"`);
  await example.close();

  // 5. The recipe for TalkingHead's users: its avatar's viseme targets take our frames.
  const recipe = await open('/examples/talkinghead.html?avatar=/avatars/brunette-t.glb');
  await recipe.waitForFunction(() => window.recipe && (window.recipe.ready || window.recipe.errors.length), { timeout: 60000 });
  await recipe.evaluate(() => window.recipe.start());
  let opened = 0, silent = 0;
  const recipeStarted = Date.now();
  while (Date.now() - recipeStarted < 45000 && !(opened > 0.3 && silent > 0.9)) {
    const r = await recipe.evaluate(() => ({ aa: window.recipe.viseme('aa'), sil: window.recipe.viseme('sil') }));
    if (r.aa > opened) {
      opened = r.aa;
      if (opened > 0.3) await recipe.screenshot({ path: path.join(out, 'talkinghead_recipe.png') });
    }
    if (opened > 0.3) silent = Math.max(silent, r.sil ?? 0);
    await new Promise((resolve) => setTimeout(resolve, 40));
  }
  const recipeErrors = await recipe.evaluate(() => window.recipe.errors);
  report.recipe = { largestAa: opened, silenceAfter: silent, errors: recipeErrors };
  check(opened > 0.3 && silent > 0.9 && recipeErrors.length === 0,
    `TalkingHead's avatar: viseme_aa up to ${opened.toFixed(2)} on speech, viseme_sil ${silent.toFixed(2)} in silence`);
} finally {
  await browser.close();
  server.close();
}
check(pageErrors.length === 0, `no uncaught page errors${pageErrors.length ? `: ${pageErrors.join('; ')}` : ''}`);
fs.writeFileSync(path.join(out, 'report.json'), JSON.stringify(report, null, 1));
console.log(`report and screenshots in ${out}`);
process.exit(failures.length ? 1 : 0);
