// WAV files to mono samples, for the Node command (a page decodes any format with decodeAudioData). Integer PCM
// of 8 to 32 bits and float of 32 or 64, plain or WAVE_FORMAT_EXTENSIBLE; channels are averaged. Errors name
// the file and what is wrong in one line.
export function decodeWav(bytes, name) {
  const fail = (what) => { throw new Error(`${name}: ${what}`); };
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const text = (at, n) => String.fromCharCode(...bytes.subarray(at, at + n));
  if (bytes.length < 12 || text(0, 4) !== 'RIFF' || text(8, 4) !== 'WAVE') fail('not a WAV file (no RIFF/WAVE header)');
  let format = null;
  let data = null;
  for (let at = 12; at + 8 <= bytes.length;) {
    const id = text(at, 4);
    const size = view.getUint32(at + 4, true);
    const body = at + 8;
    if (id === 'fmt ') {
      if (size < 16 || body + 16 > bytes.length) fail('its fmt chunk is cut short');
      let tag = view.getUint16(body, true);
      if (tag === 0xfffe && size >= 40) tag = view.getUint16(body + 24, true);
      format = {
        tag, channels: view.getUint16(body + 2, true), rate: view.getUint32(body + 4, true),
        bits: view.getUint16(body + 14, true),
      };
    } else if (id === 'data') {
      data = bytes.subarray(body, Math.min(bytes.length, body + size));
    }
    at = body + size + (size % 2);
  }
  if (!format) fail('a WAV file without a fmt chunk');
  if (!data) fail('a WAV file without a data chunk');
  const { tag, channels, rate, bits } = format;
  if (channels < 1) fail('a WAV file of no channels');
  if (!(rate > 0)) fail(`a sample rate of ${rate} Hz`);
  const integer = tag === 1 && [8, 16, 24, 32].includes(bits);
  const float = tag === 3 && (bits === 32 || bits === 64);
  if (!integer && !float) fail(`WAV samples of format ${tag} and ${bits} bits (this reads integer PCM and float)`);
  const width = bits / 8;
  const frames = Math.floor(data.length / (width * channels));
  if (frames === 0) fail('a WAV file with no samples');
  const samples = new Float32Array(frames);
  const dv = new DataView(data.buffer, data.byteOffset, data.byteLength);
  const read = (at) => {
    if (float) return bits === 32 ? dv.getFloat32(at, true) : dv.getFloat64(at, true);
    if (bits === 8) return (dv.getUint8(at) - 128) / 128;
    if (bits === 16) return dv.getInt16(at, true) / 32768;
    if (bits === 24) return ((dv.getUint8(at) | (dv.getUint8(at + 1) << 8) | (dv.getInt8(at + 2) << 16))) / 8388608;
    return dv.getInt32(at, true) / 2147483648;
  };
  for (let f = 0; f < frames; ++f) {
    let sum = 0;
    for (let c = 0; c < channels; ++c) sum += read((f * channels + c) * width);
    samples[f] = sum / channels;
  }
  return { samples, sampleRate: rate };
}
