// The AudioWorklet processor: the engine's live decoder (WebAssembly) on the audio thread, fed each 128-sample
// block of its input's first channel at the context's rate, posting each frame it decides to the node
// (index.js's createLipSync) as a plain message. The page's thread sends the core's bytes and the preset's
// models in processorOptions (a worklet cannot fetch); the stream is made once the core is instantiated.
//
// Per block: the samples go into the module's memory (no copy into a new array), the decoder runs there; a frame
// (30 a second) is copied out of the core's record into one message. Nothing is allocated per block otherwise.
import { installModels, loadCore } from './core.js';
import { frameOf } from './frames.js';

class LipSyncProcessor extends AudioWorkletProcessor {
  constructor(options) {
    super();
    const { wasm, models, preset, waitForHead, idle, seed } = options.processorOptions;
    this.stream = null;
    this.stopped = false;
    this.startTime = -1;  // the context time of the first sample decoded
    // What a block without input is, once the stream has started: a source that pauses (a paused media
    // element, a muted track, an oscillator not yet running) leaves the input with no channels, and the stream
    // must hear that silence, or every later frame would be stamped as early as the blocks it missed.
    this.silence = new Float32Array(128);
    // The context time the next block starts at. A block later than that follows render quanta this node was not
    // called for (the audio thread behind under load): the time missed is heard as silence, so the stream's
    // clock (samples decoded) stays the context's and every later frame keeps its time.
    this.nextTime = -1;
    this.skippedBlocks = 0;  // how many such blocks, reported with each frame
    this.port.onmessage = (event) => {
      const type = event.data && event.data.type;
      if (type === 'stop') this.stop();
      else if (type === 'finish') this.finish();
    };
    loadCore(wasm)
      .then((core) => {
        if (this.stopped) return;
        installModels(core, models);
        this.core = core;
        this.stream = new core.LipSyncStream(preset, sampleRate, waitForHead, idle, seed);
        this.input = this.stream.input();
        this.record = this.stream.record();
        this.port.postMessage({ type: 'ready', lookaheadMs: this.stream.lookaheadMs(), sampleRate });
      })
      .catch((error) => {
        this.stopped = true;
        this.port.postMessage({ type: 'error', message: error && error.message ? error.message : String(error) });
      });
  }

  stop() {
    if (this.stopped) return;
    this.stopped = true;
    if (this.stream) {
      this.stream.delete();
      this.stream = null;
    }
    this.port.postMessage({ type: 'stopped' });
    this.port.close();
  }

  // The input ended: the frames still due (their look-ahead reaching past the end hears nothing more).
  finish() {
    if (this.stopped || !this.stream) return;
    this.stream.finish();
    this.post(currentTime);
    this.port.postMessage({ type: 'finished' });
    this.stop();
  }

  process(inputs) {
    if (this.stopped) return false;  // the processor ends: nothing runs after disconnect()
    if (!this.stream) return true;   // not instantiated yet
    let channel = inputs[0] && inputs[0][0];
    if (!channel) {
      if (this.startTime < 0) return true;  // nothing has been heard yet: the stream starts with the first sound
      channel = this.silence;
    }
    if (this.startTime < 0) this.startTime = this.nextTime = currentTime;
    const missed = Math.round((currentTime - this.nextTime) * sampleRate / 128);
    // At most a quarter of a second of them in one call (a block of silence costs what a block of sound does);
    // a longer gap moves the stream's start instead, its frames' times jumping with the context's.
    const filled = Math.min(Math.max(missed, 0), Math.ceil(0.25 * sampleRate / 128));
    for (let i = 0; i < filled; ++i) this.decode(this.silence);
    if (missed > filled) this.startTime += ((missed - filled) * 128) / sampleRate;
    this.skippedBlocks += Math.max(missed, 0);
    this.decode(channel);
    this.nextTime = currentTime + channel.length / sampleRate;
    this.post(this.nextTime);
    return true;
  }

  decode(samples) {
    // The memory view is re-made when the module's memory has grown (the old view is detached then).
    if (this.input.length === 0) this.input = this.stream.input();
    this.input.set(samples);
    this.stream.accept(samples.length);
  }

  post(decidedTime) {
    while (this.stream.next()) {
      if (this.record.length === 0) this.record = this.stream.record();
      const frame = frameOf(this.record, this.core.layout, this.startTime);
      frame.decidedTime = decidedTime;  // the context time by which its sound had arrived and it was decided
      frame.skippedBlocks = this.skippedBlocks;
      this.port.postMessage({ type: 'frame', frame });
    }
  }
}

registerProcessor('talkinghead-lipsync', LipSyncProcessor);
