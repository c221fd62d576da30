// The example page: a GLB character (ARKit or Oculus morph targets, a Head bone) driven live by the package from
// the microphone or a dropped sound, with the preset switch and a latency readout. ?avatar=URL picks the
// character (else drop one on the page); window.demo is what the page's test reads.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { createLipSync, morphMap, setMorphs, weightNames } from '../src/index.js';

const view = document.getElementById('view');
const readout = document.getElementById('readout');
const presetSelect = document.getElementById('preset');
const mouthSelect = document.getElementById('mouth');
const microphoneButton = document.getElementById('microphone');
const stopButton = document.getElementById('stop');

const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio);
renderer.setSize(view.clientWidth, view.clientHeight);
renderer.outputColorSpace = THREE.SRGBColorSpace;
view.appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0x2a2f38);
scene.add(new THREE.HemisphereLight(0xffffff, 0x445566, 2.2));
const key = new THREE.DirectionalLight(0xffffff, 2.0);
key.position.set(0.5, 1.5, 2.0);
scene.add(key);
const camera = new THREE.PerspectiveCamera(22, view.clientWidth / view.clientHeight, 0.01, 50);

const demo = (window.demo = {
  ready: false, frames: 0, lastFrame: null, latencies: [], errors: [], lookaheadMs: null, preset: 'default',
  character: null, source: null,
});
let names = null;
let character = null;  // {root, meshes: [{mesh, map}], head, headRest}
let context = null;
let lipSync = null;
let sourceNode = null;
let mediaStream = null;

function frameOn(object) {
  // The camera on the head: its world position, looking at the face from the front (glTF: the character faces +z).
  const box = new THREE.Box3().setFromObject(object);
  const head = character.head;
  const target = head ? head.getWorldPosition(new THREE.Vector3()) : box.getCenter(new THREE.Vector3());
  if (head) target.y += 0.06;
  camera.position.set(target.x, target.y, target.z + 0.85);
  camera.lookAt(target);
}

function attachCharacter(gltf, label) {
  if (character) scene.remove(character.root);
  const root = gltf.scene;
  const meshes = [];
  let head = null;
  root.traverse((node) => {
    if (node.isMesh && node.morphTargetDictionary) meshes.push({ mesh: node, map: null });
    if (!head && node.isBone && /(^|_)head$/i.test(node.name)) head = node;
  });
  if (!head) root.traverse((node) => { if (!head && /head$/i.test(node.name)) head = node; });
  character = { root, meshes, head, headRest: head ? head.quaternion.clone() : null, label };
  remap();
  scene.add(root);
  root.updateMatrixWorld(true);
  frameOn(root);
  demo.character = { label, morphMeshes: meshes.length, head: head ? head.name : null };
}

function remap() {
  if (!character || !names) return;
  for (const entry of character.meshes) entry.map = morphMap(entry.mesh.morphTargetDictionary, names, mouthSelect.value);
}

async function loadCharacter(url, label) {
  const gltf = await new GLTFLoader().loadAsync(url);
  attachCharacter(gltf, label);
}

const headTurn = new THREE.Quaternion();
function pose(frame) {
  if (!character) return;
  for (const { mesh, map } of character.meshes) if (map) setMorphs(map, mesh.morphTargetInfluences, frame);
  if (character.head) {
    const [x, y, z, w] = frame.headQuaternion;
    character.head.quaternion.copy(character.headRest).multiply(headTurn.set(x, y, z, w));
  }
}

function onFrame(frame) {
  demo.frames += 1;
  demo.lastFrame = frame;
  demo.latencies.push(1000 * (frame.decidedTime - frame.time));
  if (demo.latencies.length > 300) demo.latencies.shift();
  pose(frame);
}

async function start(makeSource) {
  try {
    await stop();
    context = context || new AudioContext();
    if (context.state === 'suspended') await context.resume();
    lipSync = await createLipSync(context, { preset: presetSelect.value, onFrame });
    demo.lookaheadMs = lipSync.lookaheadMs;
    demo.preset = presetSelect.value;
    sourceNode = await makeSource(context);
    sourceNode.connect(lipSync);
    stopButton.disabled = false;
  } catch (error) {
    demo.errors.push(error.message);
    readout.textContent = error.message;
  }
}

async function stop() {
  if (lipSync) lipSync.disconnect();
  if (sourceNode) {
    sourceNode.disconnect();
    if (sourceNode.stop) sourceNode.stop();
  }
  if (mediaStream) mediaStream.getTracks().forEach((track) => track.stop());
  lipSync = sourceNode = mediaStream = null;
  stopButton.disabled = true;
}

async function microphone() {
  await start(async (ctx) => {
    mediaStream = await navigator.mediaDevices.getUserMedia({ audio: { echoCancellation: false, noiseSuppression: false, autoGainControl: false } });
    demo.source = 'microphone';
    return ctx.createMediaStreamSource(mediaStream);
  });
}

async function playFile(file) {
  await start(async (ctx) => {
    const buffer = await ctx.decodeAudioData(await file.arrayBuffer()).catch(() => {
      throw new Error(`${file.name}: not a sound this browser can decode`);
    });
    const player = ctx.createBufferSource();
    player.buffer = buffer;
    // The sound is heard as late as the frames: delayed by the preset's look-ahead, the lips in sync.
    const delay = ctx.createDelay(1.0);
    delay.delayTime.value = lipSync.lookaheadMs / 1000;
    player.connect(delay).connect(ctx.destination);
    player.start();
    demo.source = file.name;
    return player;
  });
}

function median(values) {
  if (!values.length) return NaN;
  const sorted = [...values].sort((a, b) => a - b);
  return sorted[Math.floor(sorted.length / 2)];
}

function render() {
  requestAnimationFrame(render);
  const frame = demo.lastFrame;
  readout.textContent = [
    `character: ${character ? character.label : 'none (drop a .glb)'}`,
    `preset: ${demo.preset}, look-ahead ${demo.lookaheadMs === null ? '–' : demo.lookaheadMs.toFixed(0)} ms`,
    `sound → frame: median ${median(demo.latencies).toFixed(0)} ms`,
    `frames: ${demo.frames}${frame ? `, level ${frame.levelDb.toFixed(0)} dB` : ''}`,
  ].join('\n');
  renderer.render(scene, camera);
}

window.addEventListener('resize', () => {
  renderer.setSize(view.clientWidth, view.clientHeight);
  camera.aspect = view.clientWidth / view.clientHeight;
  camera.updateProjectionMatrix();
});
microphoneButton.addEventListener('click', microphone);
stopButton.addEventListener('click', stop);
presetSelect.addEventListener('change', () => { if (demo.source === 'microphone') microphone(); });
mouthSelect.addEventListener('change', remap);
window.addEventListener('dragover', (event) => { event.preventDefault(); document.body.classList.add('dragging'); });
window.addEventListener('dragleave', () => document.body.classList.remove('dragging'));
window.addEventListener('drop', async (event) => {
  event.preventDefault();
  document.body.classList.remove('dragging');
  const file = event.dataTransfer.files[0];
  if (!file) return;
  if (/\.(glb|gltf|vrm)$/i.test(file.name)) {
    const url = URL.createObjectURL(file);
    await loadCharacter(url, file.name).catch((error) => demo.errors.push(`${file.name}: ${error.message}`));
    URL.revokeObjectURL(url);
  } else {
    await playFile(file);
  }
});

// The screen rectangle of the mouth: the vertices the character's jaw-opening shape moves, where they are now.
demo.mouthRect = () => {
  for (const { mesh } of character ? character.meshes : []) {
    const dictionary = mesh.morphTargetDictionary;
    const shape = dictionary.jawOpen ?? dictionary.viseme_aa;
    if (shape === undefined) continue;
    const moved = mesh.geometry.morphAttributes.position[shape];
    let largest = 0;
    for (let i = 0; i < moved.count; ++i) largest = Math.max(largest, Math.hypot(moved.getX(i), moved.getY(i), moved.getZ(i)));
    const box = new THREE.Box2(new THREE.Vector2(Infinity, Infinity), new THREE.Vector2(-Infinity, -Infinity));
    const point = new THREE.Vector3();
    mesh.updateMatrixWorld(true);
    for (let i = 0; i < moved.count; ++i) {
      if (Math.hypot(moved.getX(i), moved.getY(i), moved.getZ(i)) < 0.3 * largest) continue;
      mesh.getVertexPosition(i, point);
      mesh.localToWorld(point).project(camera);
      box.expandByPoint(new THREE.Vector2((point.x + 1) / 2 * view.clientWidth, (1 - point.y) / 2 * view.clientHeight));
    }
    return { x: box.min.x, y: box.min.y, width: box.max.x - box.min.x, height: box.max.y - box.min.y };
  }
  return null;
};
demo.start = microphone;
demo.playFile = playFile;
demo.stop = stop;

names = await weightNames();
const avatar = new URLSearchParams(location.search).get('avatar');
if (avatar) await loadCharacter(avatar, avatar.split('/').pop()).catch((error) => demo.errors.push(error.message));
remap();
demo.ready = true;
render();
