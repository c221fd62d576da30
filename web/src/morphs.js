// A frame onto a character's morph targets, by their names: ARKit's 52 (eyeBlinkLeft, jawOpen, ...) and the
// Oculus visemes as Ready Player Me, TalkingHead and VRChat name them (viseme_sil, viseme_PP, ..., viseme_aa,
// viseme_E, viseme_I, viseme_O, viseme_U). three.js's meshes hold both as morphTargetDictionary and
// morphTargetInfluences; any engine with names and weights can use the same map.
//
//   const map = morphMap(mesh.morphTargetDictionary, names);      // names: await weightNames()
//   setMorphs(map, mesh.morphTargetInfluences, frame);            // per frame
//
// Where a character has both sets, the mouth comes from one (`mouth`: 'visemes' by default when it has viseme
// shapes, else 'arkit'); the eyes, brows and cheeks always from ARKit's.

// Our Oculus names (sil PP FF TH DD kk CH SS nn RR aa E ih oh ou) and the morph names characters use for them.
const visemeAliases = { ih: ['I', 'ih'], oh: ['O', 'oh'], ou: ['U', 'ou'] };
const isMouthShape = (name) => /^(jaw|mouth|tongue|cheekPuff)/.test(name);

export function morphMap(dictionary, names, mouth = 'auto') {
  const lower = new Map(Object.keys(dictionary).map((key) => [key.toLowerCase(), dictionary[key]]));
  const find = (candidates) => {
    for (const candidate of candidates) {
      const index = lower.get(candidate.toLowerCase());
      if (index !== undefined) return index;
    }
    return undefined;
  };
  const visemes = [];
  names.oculus.forEach((name, i) => {
    const index = find((visemeAliases[name] || [name]).map((alias) => `viseme_${alias}`));
    if (index !== undefined) visemes.push([index, i]);
  });
  const useVisemes = mouth === 'visemes' || (mouth === 'auto' && visemes.length >= 10);
  const arkit = [];
  names.arkit.forEach((name, i) => {
    const index = find([name]);
    if (index !== undefined && !(useVisemes && isMouthShape(name))) arkit.push([index, i]);
  });
  return { arkit, visemes: useVisemes ? visemes : [], all: [...arkit, ...visemes].map(([index]) => index) };
}

export function setMorphs(map, influences, frame) {
  for (const index of map.all) influences[index] = 0;
  for (const [index, i] of map.arkit) influences[index] = frame.arkit[i];
  for (const [index, i] of map.visemes) influences[index] = frame.visemes[i];
}
