// talkinghead-web: lips, jaw, head, blinks and gaze from speech, in the browser and in Node, with no server.
//
//   import { createLipSync, animate } from 'talkinghead-web';
//   const lipSync = await createLipSync(audioContext, { preset: 'default', onFrame: (frame) => pose(frame) });
//   audioContext.createMediaStreamSource(microphone).connect(lipSync);
//   ...
//   lipSync.disconnect();                                   // the worklet stops; no frame comes after
//
//   const { frames } = await animate(samples, 44100);       // offline: the same frames, in a page or in Node
//
// The frames: docs/web.md and types/index.d.ts.
import { coreBinary, fetchModels, installModels, loadCore, readBytes } from './core.js';
import { frameOf } from './frames.js';

export const PRESETS = ['default', 'low-latency', 'accurate'];
export { frameOf } from './frames.js';
export { morphMap, setMorphs } from './morphs.js';

const workletAdded = new WeakSet();

// The node a source connects to: an AudioWorkletNode whose port delivers frames; disconnect() (with no argument)
// or stop() ends its processor. (Made per node rather than as a subclass, so that Node, which has no
// AudioWorkletNode, can import this module for animate().)
function makeStoppable(node) {
  const disconnectOutputs = node.disconnect.bind(node);
  node.ended = false;
  node.stop = () => {
    if (node.ended) return;
    node.ended = true;
    node.port.postMessage({ type: 'stop' });
    node.port.onmessage = null;
  };
  // The input ended (a file, a TTS stream): the last frames come, then 'finished', and the processor ends.
  node.finish = () =>
    new Promise((resolve) => {
      if (node.ended) return resolve();
      node.finished = resolve;
      node.port.postMessage({ type: 'finish' });
    });
  node.disconnect = (...args) => {
    disconnectOutputs(...args);
    if (args.length === 0) node.stop();
  };
  return node;
}

function checkContext(audioContext) {
  const isContext = typeof BaseAudioContext !== 'undefined' && audioContext instanceof BaseAudioContext;
  if (!isContext) throw new Error('talkinghead: createLipSync needs an AudioContext (or an OfflineAudioContext)');
  if (audioContext.state === 'closed') throw new Error('talkinghead: the AudioContext is closed');
  if (!audioContext.audioWorklet) throw new Error('talkinghead: this context has no AudioWorklet (a page served over http(s)?)');
}

// An AudioWorkletNode decoding what is connected to it. Options: preset ('default', 'low-latency'; 'accurate'
// with `models`), models (where the model files are: a URL; default the package's), onFrame(frame),
// waitForHead (each frame waits for its own head: ~230 ms more, for a file played in sync), idle (blinks, gaze
// and the head at rest in pauses; default true), seed.
export async function createLipSync(audioContext, options = {}) {
  checkContext(audioContext);
  const preset = options.preset ?? 'default';
  if (!PRESETS.includes(preset)) throw new Error(`talkinghead: no preset "${preset}" (there are ${PRESETS.join(', ')})`);
  const core = await loadCore();
  const [wasm, models] = await Promise.all([coreBinary(), fetchModels(core, preset, options.models)]);
  if (!workletAdded.has(audioContext)) {
    await audioContext.audioWorklet.addModule(new URL('./worklet.js', import.meta.url));
    workletAdded.add(audioContext);
  }
  if (audioContext.state === 'closed') throw new Error('talkinghead: the AudioContext is closed');
  const node = makeStoppable(new AudioWorkletNode(audioContext, 'talkinghead-lipsync', {
    numberOfInputs: 1,
    numberOfOutputs: 0,
    channelCount: 1,
    channelCountMode: 'explicit',
    channelInterpretation: 'speakers',
    processorOptions: {
      wasm: wasm.slice().buffer, models, preset,
      waitForHead: !!options.waitForHead, idle: options.idle ?? true, seed: options.seed ?? 1,
    },
  }));
  node.onFrame = options.onFrame || null;
  await new Promise((resolve, reject) => {
    node.port.onmessage = (event) => {
      const message = event.data;
      if (message.type === 'ready') {
        node.lookaheadMs = message.lookaheadMs;
        node.preset = preset;
        resolve();
      } else if (message.type === 'error') {
        node.ended = true;
        reject(new Error(`talkinghead: ${message.message}`));
      }
    };
  });
  node.port.onmessage = (event) => {
    const message = event.data;
    if (message.type === 'frame' && node.onFrame && !node.ended) node.onFrame(message.frame);
    else if (message.type === 'finished') {
      node.ended = true;
      if (node.finished) node.finished();
    } else if (message.type === 'error' && node.onerror) node.onerror(new Error(`talkinghead: ${message.message}`));
  };
  return node;
}

// Samples (a Float32Array, mono, at `sampleRate`; or an AudioBuffer, its first channel) -> the frames offline.
// Options: preset ('default' and 'low-latency': the frames live shows of this sound with each frame's own head,
// as `talkinghead animate --online --preset P`; null: `animate --online`'s own, with the offline models from
// `models`), models, idle, seed, formats (names of native animate's formats: 'csv', 'arkit', 'oculus', 'vrm',
// 'json', 'rhubarb-tsv', ...), fapTrack (true: the FAP curves too). Resolves to {framesPerSecond, frames, texts,
// fapTrack}: texts[format] is the text native `talkinghead animate --format F` writes of the same frames.
export async function animate(samples, sampleRate, options = {}) {
  if (typeof AudioBuffer !== 'undefined' && samples instanceof AudioBuffer) {
    sampleRate = samples.sampleRate;
    samples = samples.getChannelData(0);
  }
  if (!(samples instanceof Float32Array)) throw new Error('talkinghead: animate takes a Float32Array of samples or an AudioBuffer');
  const preset = options.preset === undefined ? 'default' : options.preset ?? '';
  if (preset !== '' && !PRESETS.includes(preset)) throw new Error(`talkinghead: no preset "${preset}" (there are ${PRESETS.join(', ')})`);
  const core = await loadCore();
  installModels(core, await fetchModels(core, preset, options.models));
  let animation;
  try {
    animation = core.animateSamples(samples, Number(sampleRate), preset, options.idle ?? true, options.seed ?? 1);
  } catch (error) {
    throw new Error(`talkinghead: ${error.message}`);
  }
  try {
    const frames = [];
    for (let i = 0; i < animation.numFrames(); ++i) {
      animation.select(i);
      frames.push(frameOf(animation.record(), core.layout));
    }
    const texts = {};
    for (const format of options.formats || []) texts[format] = animation.write(format);
    return {
      framesPerSecond: animation.framesPerSecond(),
      frames,
      fapTrack: options.fapTrack ? animation.fapTrack() : undefined,
      texts,
    };
  } finally {
    animation.delete();
  }
}

// An audio file -> its frames, as animate(). `file`: a File or Blob (a page), a path (Node), or the bytes (an
// ArrayBuffer or Uint8Array, with options.name for messages). A page decodes any format its browser does; Node
// reads WAV. A file that is no sound fails with one line naming it.
export async function animateFile(file, options = {}) {
  const name = options.name || file.name || (typeof file === 'string' ? file : 'the audio file');
  let bytes;
  if (typeof file === 'string') bytes = await readBytes(file);
  else if (typeof Blob !== 'undefined' && file instanceof Blob) bytes = new Uint8Array(await file.arrayBuffer());
  else bytes = file instanceof Uint8Array ? file : new Uint8Array(file);
  if (typeof OfflineAudioContext === 'undefined') {
    const { decodeWav } = await import('./wav.js');
    const wav = (() => {
      try {
        return decodeWav(bytes, name);
      } catch (error) {
        throw new Error(`talkinghead: ${error.message}`);
      }
    })();
    return animate(wav.samples, wav.sampleRate, options);
  }
  // The browser decodes at a context's rate: 16 kHz, the engine's (no second resampling).
  const context = new OfflineAudioContext(1, 1, 16000);
  const buffer = await context.decodeAudioData(bytes.slice().buffer).catch(() => {
    throw new Error(`talkinghead: ${name}: not an audio file this browser can decode`);
  });
  return animate(buffer, buffer.sampleRate, options);
}

// The names of the weights, in the frames' order.
export async function weightNames() {
  const core = await loadCore();
  return core.layout.names;
}
