// Loading the engine's WebAssembly core and its models, in a page, a worker, an AudioWorklet or Node.
//
//   const core = await loadCore();                       // once per realm; later calls give the same module
//   await loadModels(core, 'default');                   // the preset's files into the module's /models/
//
// In a page the .wasm and the models are fetched next to this package (dist/); `models` (a URL or, in Node, a
// folder) fetches them from elsewhere, e.g. the repository's models/ for the accurate preset, which the package
// does not carry. In Node, where fetch cannot read a file path, they are read from the disk.
import createTalkingheadCore from '../dist/talkinghead_core.js';

const inNode = typeof process !== 'undefined' && !!(process.versions && process.versions.node);

// Made when asked, not at load: an AudioWorklet's scope, which imports this module too, has no URL.
export const packageModels = () => new URL('../dist/models/', import.meta.url);

// The bytes at a URL, or in Node at a file: URL or a path.
export async function readBytes(where) {
  if (inNode) {
    const fs = await import('node:fs/promises');
    const { fileURLToPath } = await import('node:url');
    const path = where instanceof URL || String(where).startsWith('file:') ? fileURLToPath(where) : String(where);
    try {
      return new Uint8Array(await fs.readFile(path));
    } catch (error) {
      throw new Error(`talkinghead: ${path}: ${error.code === 'ENOENT' ? 'no such file' : error.message}`);
    }
  }
  let response;
  try {
    response = await fetch(where);
  } catch (error) {
    throw new Error(`talkinghead: ${where}: ${error.message}`);
  }
  if (!response.ok) throw new Error(`talkinghead: ${where}: HTTP ${response.status}`);
  return new Uint8Array(await response.arrayBuffer());
}

let wasmBytes = null;
// The core's .wasm, fetched once (the worklet gets these bytes: it cannot fetch).
export async function coreBinary() {
  if (!wasmBytes) wasmBytes = await readBytes(new URL('../dist/talkinghead_core.wasm', import.meta.url));
  return wasmBytes;
}

let loaded = null;
// The core, instantiated once per realm. `wasmBinary`: its bytes where this realm cannot fetch (a worklet).
export function loadCore(wasmBinary) {
  if (!loaded) {
    loaded = (async () => {
      // locateFile: the module would otherwise make a URL of its .wasm, which it is given.
      const core = await createTalkingheadCore({
        wasmBinary: wasmBinary || (await coreBinary()),
        locateFile: (file) => file,
      });
      core.FS.mkdir('/models');
      core.layout = core.frameLayout();
      return core;
    })();
  }
  return loaded;
}

// The folder (URL) models come from: `models` as given (a URL, a path relative to the page, or in Node a folder),
// else the package's.
export function modelsBase(models) {
  if (!models) return packageModels();
  if (models instanceof URL) return models;
  const text = String(models).endsWith('/') ? String(models) : `${models}/`;
  if (inNode && !/^[a-z]+:/i.test(text)) return new URL(text, `file://${process.cwd()}/`);
  return new URL(text, typeof location !== 'undefined' ? location.href : undefined);
}

// The preset's model files ("" for animate --online's own): {name: bytes}, fetched from `models`.
export async function fetchModels(core, preset, models) {
  const base = modelsBase(models);
  const names = core.modelFiles(preset);
  const files = {};
  await Promise.all(names.map(async (name) => { files[name] = await readBytes(new URL(name, base)); }));
  return files;
}

// Files into the module's /models/ (a file already there is kept: the same name is the same model).
export function installModels(core, files) {
  for (const [name, bytes] of Object.entries(files)) {
    const path = `/models/${name}`;
    if (!core.FS.analyzePath(path).exists) core.FS.writeFile(path, bytes);
  }
}

export async function loadModels(core, preset, models) {
  installModels(core, await fetchModels(core, preset, models));
}
