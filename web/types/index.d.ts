// talkinghead-web: lips, jaw, head, blinks and gaze from speech, in the browser (an AudioWorklet) and in Node.

/** A live preset: which models and how much look-ahead (docs/web.md lists each one's latency). */
export type Preset = 'default' | 'low-latency' | 'accurate';

/** One animation frame, 30 a second. */
export interface LipSyncFrame {
  /** Seconds: from createLipSync, the AudioContext time of the sound this frame shows; from animate(), from the start. */
  time: number;
  /** Frame number from the start of the stream. */
  index: number;
  /** From createLipSync: the context time by which its sound had arrived and it was decided (time + latency). */
  decidedTime?: number;
  /** From createLipSync: render quanta so far that the audio thread did not give the node (it fell behind), heard as silence. */
  skippedBlocks?: number;
  /** The mouth class shown (0 silence, 1 PP, ...; -1 none yet). */
  mouthClass: number;
  /** The sound's level, dB re full scale (NaN from animate()). */
  levelDb: number;
  /** Oculus/OpenXR's 15 viseme weights, summing to 1: sil PP FF TH DD kk CH SS nn RR aa E ih oh ou. */
  visemes: Float32Array;
  /** ARKit's 52 blendshape weights in [0, 1], in ARKit's order (weightNames().arkit). */
  arkit: Float32Array;
  /** VRM's five vowels: A I U E O. */
  vrm: Float32Array;
  /** The head's rotation [x, y, z, w] in glTF's axes (y up, z forward, x the character's left): R = Ry(yaw) Rx(pitch) Rz(roll). */
  headQuaternion: [number, number, number, number];
  /** The same in degrees: pitch down, yaw to the character's left, roll to its right positive. */
  headDegrees: { pitch: number; yaw: number; roll: number };
  /** Eyelids closed: 0 open, 1 shut. */
  blink: { left: number; right: number };
  /** Where the eyes look, degrees: yaw to the character's left, pitch down positive. */
  gaze: { yaw: number; pitch: number };
}

export interface LipSyncOptions {
  /** Default 'default'. 'accurate' needs `models` (its models are not in the package). */
  preset?: Preset;
  /** Where the model files are: a URL (default: the package's dist/models/). */
  models?: string | URL;
  /** Called on the page's thread for each frame, as the worklet decides it. */
  onFrame?: (frame: LipSyncFrame) => void;
  /** Each frame waits for its own head (~230 ms more): for a file played in sync. Default false: the head shown late. */
  waitForHead?: boolean;
  /** Blinks, gaze shifts and the head at rest in pauses. Default true. */
  idle?: boolean;
  /** Seed of the head's variation and the idle behaviour. Default 1. */
  seed?: number;
}

/** The AudioWorkletNode createLipSync makes: connect any source to it. */
export interface LipSyncNode extends AudioWorkletNode {
  /** How long after its sound a frame is decided, ms (the preset's look-ahead and the resampler's). */
  readonly lookaheadMs: number;
  readonly preset: Preset;
  onFrame: ((frame: LipSyncFrame) => void) | null;
  onerror: ((error: Error) => void) | null;
  /** True once stopped: no frame comes after. */
  readonly ended: boolean;
  /** The input ended: the last frames come, then the processor stops. */
  finish(): Promise<void>;
  /** Stops the processor (disconnect() with no argument does too). */
  stop(): void;
}

/** An AudioWorkletNode decoding what is connected to it. Rejects with one clear Error for a closed context, a rate
 * it cannot resample (outside 8 to 384 kHz), an unknown preset or models it cannot load. */
export function createLipSync(audioContext: BaseAudioContext, options?: LipSyncOptions): Promise<LipSyncNode>;

export interface AnimateOptions {
  /** A live preset (default 'default'): the frames of `talkinghead animate --online --preset P`. null: those of
   * `talkinghead animate --online` (the offline models, from `models`). */
  preset?: Preset | null;
  models?: string | URL;
  idle?: boolean;
  seed?: number;
  /** Native animate's formats to write: 'csv', 'json', 'fap', 'arkit', 'oculus', 'oculus-json', 'vrm', 'vrm-json',
   * 'rhubarb-tsv', 'rhubarb-xml', 'rhubarb-json', 'moho'. */
  formats?: string[];
  /** Also return the FAP curves. */
  fapTrack?: boolean;
}

export interface Animation {
  framesPerSecond: number;
  frames: LipSyncFrame[];
  /** texts[format]: the text native `talkinghead animate --format F` writes. */
  texts: Record<string, string>;
  fapTrack?: { framesPerSecond: number; faps: number[]; values: Float64Array };
}

/** Mono samples (or an AudioBuffer's first channel) at any rate from 8 kHz -> their frames, offline. */
export function animate(samples: Float32Array | AudioBuffer, sampleRate?: number, options?: AnimateOptions): Promise<Animation>;

/** An audio file -> its frames: a File or Blob (a page decodes any format its browser does), a path (Node reads
 * WAV), or the bytes (with options.name for messages). */
export function animateFile(
  file: Blob | string | ArrayBuffer | Uint8Array,
  options?: AnimateOptions & { name?: string },
): Promise<Animation>;

/** The names of the weights, in the frames' order. */
export function weightNames(): Promise<{ oculus: string[]; arkit: string[]; vrm: string[] }>;

export interface MorphMap {
  arkit: Array<[number, number]>;
  visemes: Array<[number, number]>;
  all: number[];
}
/** Which of a character's morph targets (three.js's morphTargetDictionary) take which weight: ARKit names and
 * viseme_sil ... viseme_U. mouth: 'auto' (visemes where the character has them), 'visemes' or 'arkit'. */
export function morphMap(
  dictionary: Record<string, number>,
  names: { oculus: string[]; arkit: string[] },
  mouth?: 'auto' | 'visemes' | 'arkit',
): MorphMap;
/** The frame's weights into the influences (three.js's morphTargetInfluences). */
export function setMorphs(map: MorphMap, influences: number[], frame: LipSyncFrame): void;

export const PRESETS: Preset[];
/** A core record as a frame (for code that runs the core itself). */
export function frameOf(record: Float64Array, layout: object, timeOffset?: number): LipSyncFrame;
