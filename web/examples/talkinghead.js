// The recipe for TalkingHead's users (npm @met4citizen/talkinghead): its avatar, its idle life and its camera,
// with the lips, blinks and head from our frames instead of word timestamps, live from the microphone.
// ?avatar=URL picks a Ready Player Me style GLB (Oculus viseme_* and ARKit morph targets). window.recipe is
// what the page's test reads.
import { TalkingHead } from 'talkinghead';
import { createLipSync } from '../src/index.js';

// Our Oculus visemes (sil PP FF TH DD kk CH SS nn RR aa E ih oh ou) by TalkingHead's morph target names.
const visemeTargets = ['sil', 'PP', 'FF', 'TH', 'DD', 'kk', 'CH', 'SS', 'nn', 'RR', 'aa', 'E', 'I', 'O', 'U']
  .map((name) => `viseme_${name}`);

const recipe = (window.recipe = { ready: false, frames: 0, errors: [], lastFrame: null });
const status = document.getElementById('status');
const head = new TalkingHead(document.getElementById('avatar'), {
  ttsEndpoint: null, lipsyncModules: [], cameraView: 'head', avatarMood: 'neutral',
});

// Each frame, as TalkingHead's "realtime" values: they override its own animation of these targets, at once.
function realtime(target, value) {
  const morph = head.mtAvatar[target];
  if (morph) Object.assign(morph, { realtime: value, needsUpdate: true });
}
function onFrame(frame) {
  visemeTargets.forEach((target, i) => realtime(target, frame.visemes[i]));
  realtime('eyeBlinkLeft', frame.blink.left);
  realtime('eyeBlinkRight', frame.blink.right);
  // The head's turn as TalkingHead's head rotation (its Head bone's quaternion deltas; small angles).
  realtime('headRotateX', frame.headQuaternion[0]);
  realtime('headRotateY', frame.headQuaternion[1]);
  realtime('headRotateZ', frame.headQuaternion[2]);
  recipe.frames += 1;
  recipe.lastFrame = frame;
}

async function microphone() {
  try {
    // TalkingHead's own audio context: its speech and ours share a clock.
    const lipSync = await createLipSync(head.audioCtx, { onFrame });
    const stream = await navigator.mediaDevices.getUserMedia({ audio: true });
    head.audioCtx.createMediaStreamSource(stream).connect(lipSync);
    if (head.audioCtx.state === 'suspended') await head.audioCtx.resume();
    status.textContent = `listening (look-ahead ${lipSync.lookaheadMs.toFixed(0)} ms)`;
  } catch (error) {
    recipe.errors.push(error.message);
    status.textContent = error.message;
  }
}

document.getElementById('microphone').addEventListener('click', microphone);
recipe.start = microphone;
recipe.viseme = (name) => head.mtAvatar[`viseme_${name}`]?.applied ?? null;
const avatar = new URLSearchParams(location.search).get('avatar') || './avatar.glb';
try {
  await head.showAvatar({ url: avatar, body: 'F', lipsyncLang: 'en' });
  status.textContent = 'ready: press Microphone';
  recipe.ready = true;
} catch (error) {
  recipe.errors.push(`${avatar}: ${error.message}`);
  status.textContent = `${avatar}: ${error.message}`;
}
