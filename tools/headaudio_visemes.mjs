#!/usr/bin/env node
// Oculus-15 viseme weights from HeadAudio, the browser lip-sync peer, for judging ours against it.
//
//   bash scripts/install-node-tools.sh build
//   node tools/headaudio_visemes.mjs --modules build/node/node_modules IN.wav [IN2.wav ...] -o OUT_DIR
//        [--shift-ms 0] [--rate 48000] [--layer node|processor] [--param NAME=VALUE ...]
//
// writes OUT_DIR/<stem>.csv per input in the layout of `talkinghead animate --format oculus` (docs/formats.md):
//   time_s,sil,PP,FF,TH,DD,kk,CH,SS,nn,RR,aa,E,ih,oh,ou
// a row per frame at 30 fps, frame i at i/30 s (6 decimals), ceil(duration * 30) rows, weights to 4 decimals.
//
// HeadAudio (npm @met4citizen/headaudio, pinned by scripts/install-node-tools.sh) is an AudioWorklet: a processor
// (modules/headworklet.mjs + processor.mjs) that pre-emphasises the audio, downsamples it to 16 kHz, takes
// 12 MFCCs of a 512-sample window every 256 samples (16 ms), gates them with an energy VAD and classifies them
// with Gaussian prototypes (Mahalanobis distance, majority vote over the last 6), posting 'viseme'/'started'/
// 'ended' messages; and a node (modules/headaudio.mjs, class HeadAudio) that turns them into blend-shape values in
// its update(dt), called from the page's animation loop: the active viseme ramps up over 100 ms (sigmoid-eased)
// while the others ramp down, scaled to 0.65 (0.75 for PP and FF), and are handed out via onvalue(key, value).
//
// How it runs here: both files are loaded from the package in node_modules at run time and run unchanged (nothing
// of HeadAudio is copied into this repository). Around them this tool provides what the browser would: for the
// worklet, the globals AudioWorkletProcessor, registerProcessor, sampleRate, currentFrame and currentTime; for
// the page, AudioWorkletNode (parameters from the processor's parameterDescriptors and the node's parameterData,
// an AudioContext with audioWorklet.addModule), a MessagePort pair between node and processor (structured-clone
// copies, queued and delivered deterministically: page -> processor before each render quantum, processor -> page
// before each animation frame), and fetch() for the file: URL of the package's model dist/model-en-mixed.bin,
// which the page would fetch over HTTP. The page's steps are those of HeadAudio's README: addModule, new
// HeadAudio(ctx) with the package's default parameters (change them with --param), loadModel(model) (it posts
// 'reset' and 'model'), onvalue. No 'start' message is needed (the processor starts running); no silence
// calibration is done (silMode 1 waits for the page to call calibrate(); only the model's trained silence is used).
//
// Audio: the WAV (16-bit PCM or 32-bit float, mono or stereo mixed to mono as (L+R)/2) is resampled to the
// AudioContext rate, 48 kHz by default (--rate; HeadAudio takes any context rate and downsamples to 16 kHz itself),
// with a Kaiser-windowed sinc (beta 8.6, 16 zero crossings a side, cut-off 0.95 of the lower Nyquist; none when the
// rates are equal), and fed to the processor in 128-sample render quanta starting at context time 0 (the last one
// zero-padded; after the end the input has no channels, as after a source node stops).
//
// Frame mapping: the page's animation loop runs at 30 fps in audio time. For frame i at t = i/30 s, every render
// quantum that ends at or before t + shift is processed, the processor's messages are delivered to the node, then
// node.update(1000/30) runs, and the row holds the blend-shape values as they then stand, i.e. HeadAudio's latest
// output at or before that time. --shift-ms N (default 0) takes them at t + N ms instead, i.e. shifts HeadAudio's
// outputs N ms earlier. HeadAudio has latency by design, which this tool does NOT compensate unless asked: its
// README puts the end-to-end latency at about 50 ms (the 512-sample window at 16 kHz, the 256-sample hop, a vote
// that needs about three agreeing windows) and has the page delay the audio by 50-100 ms with a DelayNode (its
// example: 100 ms). Besides, a 'viseme' message is stamped t = the window's centre, 16 ms before it is posted, and
// the node's 100 ms ramp is half way after 50 ms.
//
// The weights (--layer node, the default; what an avatar driven by HeadAudio shows): the 14 non-silence columns are
// HeadAudio's blend-shape values exactly as onvalue gives them (0-0.65, 0-0.75 for PP and FF; not a distribution:
// during a cross-fade two or three are non-zero, in silence none). HeadAudio never drives viseme_sil (its value
// stays 0: it maps silence to "no viseme active"), so the sil column is made by this tool from HeadAudio's own
// silence state: while the node has no active viseme (before speech, after an 'ended' message), the rest weight
// 1 - sum(value / max) over the other 14, clipped to [0, 1] (1 in silence, growing as the last viseme fades out);
// while a viseme is active, 0 (in a quick run of visemes the values may all be small mid-fade, and the argmax is
// then the one most shown, not sil). The scorer takes the argmax per frame.
// Note: HeadAudio 0.1.0's node ignores viseme id 0 (its 'viseme' handler tests `if (viseme)`), so viseme_aa is
// never set active and an /aa/ keeps the viseme before it; --layer processor shows the processor's decisions
// without the node: a one-hot row of the latest viseme it posted (aa included), sil before the first and after an
// 'ended' message.
//
// HeadAudio's viseme names (ids 0-14: aa E I O U PP SS TH DD FF kk nn RR CH sil, all "viseme_" + name) map to
// ours by name: I -> ih, O -> oh, U -> ou, the rest unchanged.
//
// A file that cannot be read gets one line on stderr (the file and what is wrong), no CSV, and exit code 1 (the
// other inputs are still done); usage errors exit 2. Needs Node 18+ (structuredClone, fetch, Response).

import fs from 'node:fs';
import path from 'node:path';
import { pathToFileURL, fileURLToPath } from 'node:url';

const FPS = 30;
const RENDER_QUANTUM = 128;
const PINNED_VERSION = '0.1.0';
const OCULUS = ['sil', 'PP', 'FF', 'TH', 'DD', 'kk', 'CH', 'SS', 'nn', 'RR', 'aa', 'E', 'ih', 'oh', 'ou'];
// HeadAudio's blend-shape key for each of our columns.
const HEADAUDIO_KEY = {
  sil: 'viseme_sil', PP: 'viseme_PP', FF: 'viseme_FF', TH: 'viseme_TH', DD: 'viseme_DD', kk: 'viseme_kk',
  CH: 'viseme_CH', SS: 'viseme_SS', nn: 'viseme_nn', RR: 'viseme_RR', aa: 'viseme_aa', E: 'viseme_E',
  ih: 'viseme_I', oh: 'viseme_O', ou: 'viseme_U',
};

// ---------------------------------------------------------------------------------------------------------------
// Command line

function usage(message) {
  if (message) console.error(`headaudio_visemes: ${message}`);
  console.error(
    'usage: node tools/headaudio_visemes.mjs --modules NODE_MODULES IN.wav [IN2.wav ...] -o OUT_DIR\n' +
    '         [--shift-ms N] [--rate HZ] [--layer node|processor] [--param NAME=VALUE ...]');
  process.exit(2);
}

function parseArgs(argv) {
  const o = { modules: process.env.HEADAUDIO_MODULES || '', out: '', shiftMs: 0, rate: 48000, layer: 'node',
              params: {}, inputs: [] };
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    const value = () => {
      if (i + 1 >= argv.length) usage(`${a} needs a value`);
      return argv[++i];
    };
    const number = (s, what) => {
      const x = Number(s);
      if (s === '' || !Number.isFinite(x)) usage(`${what}: not a number: ${s}`);
      return x;
    };
    if (a === '--modules') o.modules = value();
    else if (a === '-o' || a === '--out') o.out = value();
    else if (a === '--shift-ms') o.shiftMs = number(value(), '--shift-ms');
    else if (a === '--rate') o.rate = number(value(), '--rate');
    else if (a === '--layer') o.layer = value();
    else if (a === '--param') {
      const s = value();
      const eq = s.indexOf('=');
      if (eq <= 0) usage(`--param needs NAME=VALUE: ${s}`);
      o.params[s.slice(0, eq)] = number(s.slice(eq + 1), `--param ${s.slice(0, eq)}`);
    } else if (a === '-h' || a === '--help') usage();
    else if (a.startsWith('-') && a !== '-') usage(`unknown option ${a}`);
    else o.inputs.push(a);
  }
  if (!o.modules) usage('--modules NODE_MODULES (or HEADAUDIO_MODULES) is needed');
  if (!o.out) usage('-o OUT_DIR is needed');
  if (o.inputs.length === 0) usage('no input WAV');
  if (!Number.isInteger(o.rate) || o.rate < 3000 || o.rate > 768000) usage(`--rate: ${o.rate} Hz is not a context rate`);
  if (o.layer !== 'node' && o.layer !== 'processor') usage(`--layer is node or processor, not ${o.layer}`);
  const stems = new Map();
  for (const f of o.inputs) {
    const stem = path.basename(f).replace(/\.[^.]*$/, '');
    if (stems.has(stem)) usage(`${stems.get(stem)} and ${f} would both write ${stem}.csv`);
    stems.set(stem, f);
  }
  return o;
}

// ---------------------------------------------------------------------------------------------------------------
// WAV reading: 16-bit PCM or 32-bit float, mono or stereo -> mono Float32Array.

class WavError extends Error {}

function readWav(file) {
  let bytes;
  try {
    bytes = fs.readFileSync(file);
  } catch (e) {
    throw new WavError(`cannot be read: ${e.code || e.message}`);
  }
  if (bytes.length < 12 || bytes.toString('latin1', 0, 4) !== 'RIFF' || bytes.toString('latin1', 8, 12) !== 'WAVE')
    throw new WavError('not a RIFF/WAVE file');
  let fmt = null;
  let data = null;
  for (let pos = 12; pos + 8 <= bytes.length;) {
    const id = bytes.toString('latin1', pos, pos + 4);
    const size = bytes.readUInt32LE(pos + 4);
    const body = pos + 8;
    if (id === 'fmt ') {
      if (size < 16 || body + 16 > bytes.length) throw new WavError('its fmt chunk is too short');
      let format = bytes.readUInt16LE(body);
      if (format === 0xfffe && size >= 40 && body + 26 <= bytes.length) format = bytes.readUInt16LE(body + 24);
      fmt = { format, channels: bytes.readUInt16LE(body + 2), rate: bytes.readUInt32LE(body + 4),
              bits: bytes.readUInt16LE(body + 14) };
    } else if (id === 'data') {
      data = { start: body, size: Math.min(size, bytes.length - body) };  // a truncated file keeps what it has
      break;
    }
    pos = body + size + (size & 1);
  }
  if (!fmt) throw new WavError('has no fmt chunk');
  if (!data) throw new WavError('has no data chunk');
  const pcm16 = fmt.format === 1 && fmt.bits === 16;
  const float32 = fmt.format === 3 && fmt.bits === 32;
  if (!pcm16 && !float32)
    throw new WavError(`is format ${fmt.format} with ${fmt.bits} bits (needs 16-bit PCM or 32-bit float)`);
  if (fmt.channels !== 1 && fmt.channels !== 2) throw new WavError(`has ${fmt.channels} channels (needs 1 or 2)`);
  if (fmt.rate < 1000 || fmt.rate > 768000) throw new WavError(`has a sample rate of ${fmt.rate} Hz`);
  const frameBytes = fmt.channels * fmt.bits / 8;
  const n = Math.floor(data.size / frameBytes);
  if (n === 0) throw new WavError('has no samples');
  const out = new Float32Array(n);
  for (let i = 0; i < n; i++) {
    let sum = 0;
    for (let c = 0; c < fmt.channels; c++) {
      const at = data.start + i * frameBytes + c * fmt.bits / 8;
      sum += pcm16 ? bytes.readInt16LE(at) / 32768 : bytes.readFloatLE(at);
    }
    const v = sum / fmt.channels;
    if (!Number.isFinite(v)) throw new WavError(`has a sample that is not a finite number (frame ${i})`);
    out[i] = v;
  }
  return { samples: out, rate: fmt.rate };
}

// ---------------------------------------------------------------------------------------------------------------
// Resampling: Kaiser-windowed sinc, the kernel tabulated finely and interpolated linearly.

function besselI0(x) {
  let sum = 1, term = 1;
  for (let k = 1; k < 50; k++) {
    term *= (x / (2 * k)) * (x / (2 * k));
    sum += term;
    if (term < 1e-12 * sum) break;
  }
  return sum;
}

function resample(x, rateIn, rateOut) {
  if (rateIn === rateOut) return x;
  const ZEROS = 16, BETA = 8.6, STEPS = 2048;
  const g = 0.95 * Math.min(1, rateOut / rateIn);  // cut-off, as a fraction of the input's Nyquist
  const width = ZEROS / g;                         // kernel half-width, input samples
  const tableN = Math.ceil(width * STEPS) + 2;
  const table = new Float64Array(tableN);
  const i0Beta = besselI0(BETA);
  for (let j = 0; j < tableN; j++) {
    const t = j / STEPS;
    if (t >= width) continue;
    const u = t / width;
    const sinc = t === 0 ? 1 : Math.sin(Math.PI * g * t) / (Math.PI * g * t);
    table[j] = g * sinc * besselI0(BETA * Math.sqrt(1 - u * u)) / i0Beta;
  }
  const nOut = Math.ceil(x.length * rateOut / rateIn);
  const y = new Float32Array(nOut);
  const step = rateIn / rateOut;
  for (let n = 0; n < nOut; n++) {
    const p = n * step;
    const k0 = Math.max(0, Math.ceil(p - width));
    const k1 = Math.min(x.length - 1, Math.floor(p + width));
    let acc = 0;
    for (let k = k0; k <= k1; k++) {
      const f = Math.abs(p - k) * STEPS;
      const j = Math.floor(f);
      if (j + 1 >= tableN) continue;
      acc += x[k] * (table[j] + (f - j) * (table[j + 1] - table[j]));
    }
    y[n] = acc;
  }
  return y;
}

// ---------------------------------------------------------------------------------------------------------------
// The browser around HeadAudio: worklet globals, AudioWorkletNode, MessagePort pair, AudioContext, fetch(file:).

const processors = new Map();  // registerProcessor's registry
const renderClock = { frame: 0, rate: 48000 };
let portForNextProcessor = null;
const PROCESSOR = Symbol('processor');

class QueuedPort {
  constructor() {
    this.onmessage = null;
    this.peer = null;
    this.queue = [];
    this.tap = null;  // sees each message delivered (the tool's own observer, for --layer processor)
  }
  postMessage(data, transfer) {
    const list = Array.isArray(transfer) ? transfer : (transfer?.transfer || []);
    this.peer.queue.push(structuredClone(data, { transfer: list }));
  }
  deliver() {
    while (this.queue.length) {
      const data = this.queue.shift();
      if (this.tap) this.tap(data);
      if (typeof this.onmessage === 'function') this.onmessage({ data, type: 'message' });
    }
  }
  start() {}
  close() {}
}

function installBrowserShims() {
  // AudioWorkletGlobalScope
  globalThis.AudioWorkletProcessor = class AudioWorkletProcessor {
    constructor() {
      if (!portForNextProcessor) throw new TypeError('AudioWorkletProcessor is constructed by an AudioWorkletNode');
      this.port = portForNextProcessor;
      portForNextProcessor = null;
    }
  };
  globalThis.registerProcessor = (name, cls) => {
    if (processors.has(name)) throw new Error(`registerProcessor: "${name}" is already registered`);
    processors.set(name, cls);
  };
  Object.defineProperty(globalThis, 'currentFrame', { get: () => renderClock.frame, configurable: true });
  Object.defineProperty(globalThis, 'currentTime', { get: () => renderClock.frame / renderClock.rate,
                                                     configurable: true });
  Object.defineProperty(globalThis, 'sampleRate', { get: () => renderClock.rate, configurable: true });

  // Window: AudioWorkletNode
  globalThis.AudioWorkletNode = class AudioWorkletNode {
    constructor(context, name, options = {}) {
      const Processor = processors.get(name);
      if (!Processor) throw new Error(`AudioWorkletNode: no processor "${name}" is registered`);
      this.context = context;
      this.port = new QueuedPort();
      const processorPort = new QueuedPort();
      this.port.peer = processorPort;
      processorPort.peer = this.port;
      const parameterData = options.parameterData || {};
      this.parameters = new Map();
      for (const d of Processor.parameterDescriptors || []) {
        const min = d.minValue ?? -3.4028234663852886e38, max = d.maxValue ?? 3.4028234663852886e38;
        let value = Math.fround(d.defaultValue ?? 0);
        const param = {
          defaultValue: d.defaultValue ?? 0, minValue: min, maxValue: max, automationRate: d.automationRate || 'a-rate',
          get value() { return value; },
          set value(v) { value = Math.fround(Math.min(max, Math.max(min, v))); },
        };
        if (d.name in parameterData) param.value = parameterData[d.name];
        this.parameters.set(d.name, param);
      }
      for (const key of Object.keys(parameterData))
        if (!this.parameters.has(key)) throw new Error(`AudioWorkletNode: "${name}" has no parameter "${key}"`);
      this.onprocessorerror = null;
      const processorOptions = structuredClone({
        numberOfInputs: options.numberOfInputs ?? 1, numberOfOutputs: options.numberOfOutputs ?? 1,
        outputChannelCount: options.outputChannelCount, channelCount: options.channelCount ?? 2,
        channelCountMode: options.channelCountMode ?? 'max',
        channelInterpretation: options.channelInterpretation ?? 'speakers',
        parameterData, processorOptions: options.processorOptions ?? {},
      });
      portForNextProcessor = processorPort;
      this[PROCESSOR] = { instance: new Processor(processorOptions), port: processorPort, alive: true,
                          numberOfOutputs: processorOptions.numberOfOutputs };
    }
    connect() {}
    disconnect() {}
  };
}

class OfflineAudioContextShim {
  constructor(rate) {
    this.sampleRate = rate;
    this.state = 'running';
    this.audioWorklet = { addModule: async (url) => { await import(url); } };
  }
  get currentTime() { return renderClock.frame / renderClock.rate; }
}

// One render quantum for a node: page -> processor messages first, then process().
function renderQuantum(node, channelData) {
  const p = node[PROCESSOR];
  p.port.deliver();
  if (!p.alive) return;
  const parameters = {};
  for (const [name, param] of node.parameters) parameters[name] = new Float32Array([param.value]);
  const inputs = [channelData ? [channelData] : []];
  const outputs = Array.from({ length: p.numberOfOutputs }, () => []);
  try {
    p.alive = !!p.instance.process(inputs, outputs, parameters);
  } catch (e) {
    p.alive = false;
    throw new Error(`HeadAudio's processor threw: ${e.stack || e}`);
  }
}

function installFileFetch() {
  const networkFetch = globalThis.fetch;
  globalThis.fetch = async (resource, init) => {
    const href = resource instanceof URL ? resource.href : (typeof resource === 'string' ? resource : resource?.url);
    if (href && href.startsWith('file:')) {
      try {
        return new Response(fs.readFileSync(fileURLToPath(href)), { status: 200, statusText: 'OK' });
      } catch (e) {
        return new Response(null, { status: 404, statusText: `Not Found (${e.code || e.message})` });
      }
    }
    if (!networkFetch) throw new TypeError('fetch is not available');
    return networkFetch(resource, init);
  };
}

// ---------------------------------------------------------------------------------------------------------------
// Running HeadAudio on one recording

async function loadHeadAudio(modulesDir, rate) {
  const packageDir = path.resolve(modulesDir, '@met4citizen', 'headaudio');
  const packageJson = path.join(packageDir, 'package.json');
  if (!fs.existsSync(packageJson))
    throw new Error(`@met4citizen/headaudio is not in ${modulesDir} (bash scripts/install-node-tools.sh BUILD)`);
  const version = JSON.parse(fs.readFileSync(packageJson, 'utf8')).version;
  renderClock.rate = rate;
  installBrowserShims();
  installFileFetch();
  const context = new OfflineAudioContextShim(rate);
  await context.audioWorklet.addModule(pathToFileURL(path.join(packageDir, 'modules', 'headworklet.mjs')).href);
  const { HeadAudio } = await import(pathToFileURL(path.join(packageDir, 'modules', 'headaudio.mjs')).href);
  const modelUrl = pathToFileURL(path.join(packageDir, 'dist', 'model-en-mixed.bin')).href;
  return { HeadAudio, context, modelUrl, version };
}

async function runHeadAudio(lib, samples, durationS, options) {
  const { HeadAudio, context, modelUrl } = lib;
  const rate = context.sampleRate;
  renderClock.frame = 0;
  const node = new HeadAudio(context, { processorOptions: {}, parameterData: { ...options.params } });
  const values = new Map(node.visemeNames.map((k) => [k, 0]));
  node.onvalue = (key, value) => { values.set(key, value); };
  const silId = node.visemeNames.indexOf('viseme_sil');
  let processorViseme = silId;
  node.port.tap = (data) => {
    if (data.event === 'viseme' && data.viseme !== null && data.viseme !== undefined) processorViseme = data.viseme;
    else if (data.event === 'ended') processorViseme = silId;
  };
  await node.loadModel(modelUrl);

  const maxOf = new Map(node.visemeNames.map((k, i) => [k, node.visemeMaxs[i]]));
  const idOf = new Map(node.visemeNames.map((k, i) => [k, i]));
  const frames = Math.max(1, Math.ceil(durationS * FPS - 1e-9));
  const quanta = Math.ceil(samples.length / RENDER_QUANTUM);
  const dtMs = 1000 / FPS;
  let done = 0;  // render quanta processed
  const lines = ['time_s,' + OCULUS.join(',')];
  const row = new Array(OCULUS.length);
  for (let i = 0; i < frames; i++) {
    const t = i / FPS;
    const until = Math.floor(((t + options.shiftMs / 1000) * rate + 1e-6) / RENDER_QUANTUM);  // quanta ending <= t
    for (; done < until; done++) {
      renderClock.frame = done * RENDER_QUANTUM;
      let block = null;
      if (done < quanta) {
        block = new Float32Array(RENDER_QUANTUM);
        block.set(samples.subarray(done * RENDER_QUANTUM, Math.min(samples.length, (done + 1) * RENDER_QUANTUM)));
      }
      renderQuantum(node, block);
    }
    renderClock.frame = Math.max(0, done) * RENDER_QUANTUM;
    node.port.deliver();
    node.update(dtMs);
    if (options.layer === 'node') {
      let active = 0;
      for (let c = 1; c < OCULUS.length; c++) {
        const key = HEADAUDIO_KEY[OCULUS[c]];
        row[c] = values.get(key);
        active += row[c] / maxOf.get(key);
      }
      row[0] = node.visemeActive === -1 ? Math.min(1, Math.max(0, 1 - active)) : 0;
    } else {
      for (let c = 0; c < OCULUS.length; c++) row[c] = idOf.get(HEADAUDIO_KEY[OCULUS[c]]) === processorViseme ? 1 : 0;
    }
    lines.push(t.toFixed(6) + ',' + row.map((w) => (Math.abs(w) < 5e-5 ? 0 : w).toFixed(4)).join(','));
  }
  return lines.join('\n') + '\n';
}

// ---------------------------------------------------------------------------------------------------------------

async function main() {
  const options = parseArgs(process.argv.slice(2));
  let lib;
  try {
    lib = await loadHeadAudio(options.modules, options.rate);
  } catch (e) {
    console.error(`headaudio_visemes: cannot load HeadAudio: ${e.message}`);
    process.exit(2);
  }
  const descriptors = processors.get('headworklet')?.parameterDescriptors || [];
  for (const name of Object.keys(options.params))
    if (!descriptors.some((d) => d.name === name))
      usage(`--param: HeadAudio has no parameter ${name} (it has ${descriptors.map((d) => d.name).join(', ')})`);
  if (lib.version !== PINNED_VERSION)
    console.log(`headaudio_visemes: note: HeadAudio ${lib.version} (this tool was written against ${PINNED_VERSION})`);
  console.log(`headaudio_visemes: HeadAudio ${lib.version}, context ${options.rate} Hz, layer ${options.layer}, ` +
              `shift ${options.shiftMs} ms. Design latency: about 50 ms end to end by HeadAudio's README (it ` +
              'advises delaying the audio 50-100 ms); not compensated beyond --shift-ms.');
  fs.mkdirSync(options.out, { recursive: true });
  let failed = false;
  for (const file of options.inputs) {
    const stem = path.basename(file).replace(/\.[^.]*$/, '');
    const target = path.join(options.out, `${stem}.csv`);
    const temporary = path.join(options.out, `.${stem}.csv.${process.pid}.tmp`);
    try {
      const started = process.hrtime.bigint();
      const wav = readWav(file);
      const durationS = wav.samples.length / wav.rate;
      const audio = resample(wav.samples, wav.rate, options.rate);
      const csv = await runHeadAudio(lib, audio, durationS, options);
      fs.writeFileSync(temporary, csv);
      fs.renameSync(temporary, target);
      const seconds = Number(process.hrtime.bigint() - started) / 1e9;
      console.log(`${file}: ${durationS.toFixed(2)} s at ${wav.rate} Hz -> ${target} ` +
                  `(${csv.split('\n').length - 2} frames, ${seconds.toFixed(2)} s)`);
    } catch (e) {
      failed = true;
      fs.rmSync(temporary, { force: true });
      fs.rmSync(target, { force: true });
      const what = e instanceof WavError ? e.message : `failed: ${String(e.message || e).split('\n')[0]}`;
      console.error(`${file}: ${what}`);
    }
  }
  process.exitCode = failed ? 1 : 0;
}

main().catch((e) => {
  console.error(`headaudio_visemes: ${e.stack || e}`);
  process.exitCode = 2;
});
