// A frame's record (the core's Float64Array, rewritten per frame) as the object the package hands out.
export function frameOf(record, layout, timeOffset = 0) {
  const slice = (at, n) => Float32Array.from(record.subarray(at, at + n));
  const head = layout.headDegrees;
  return {
    time: record[layout.time] + timeOffset,
    index: record[layout.index],
    mouthClass: record[layout.mouthClass],
    levelDb: record[layout.levelDb],
    visemes: slice(layout.oculus, 15),
    arkit: slice(layout.arkit, 52),
    vrm: slice(layout.vrm, 5),
    headQuaternion: Array.from(record.subarray(layout.headQuaternion, layout.headQuaternion + 4)),
    headDegrees: { pitch: record[head], yaw: record[head + 1], roll: record[head + 2] },
    blink: { left: record[layout.blink], right: record[layout.blink + 1] },
    gaze: { yaw: record[layout.gaze], pitch: record[layout.gaze + 1] },
  };
}
