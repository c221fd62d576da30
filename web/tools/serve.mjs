// A static server for the package's pages (the example, the tests' pages): web/ at /, and folders mounted under
// other names. No dependencies.
//
//   node web/tools/serve.mjs [--port 8080] [--mount /avatars=../shared/data/face/avatars] [--isolated]
//
// --isolated sends the headers that make a page cross-origin isolated (finer timers, for the benchmark page);
// the package itself needs none.
import http from 'node:http';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const types = {
  '.html': 'text/html; charset=utf-8', '.js': 'text/javascript', '.mjs': 'text/javascript', '.json': 'application/json',
  '.wasm': 'application/wasm', '.glb': 'model/gltf-binary', '.gltf': 'model/gltf+json', '.vrm': 'model/gltf-binary',
  '.wav': 'audio/wav', '.png': 'image/png', '.css': 'text/css', '.map': 'application/json',
};

export function serve({ port = 0, mounts = {}, isolated = false } = {}) {
  const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
  const folders = [...Object.entries(mounts).map(([prefix, folder]) => [prefix.replace(/\/?$/, '/'), path.resolve(folder)]), ['/', root]];
  const server = http.createServer((request, response) => {
    const url = new URL(request.url, 'http://localhost');
    const [prefix, folder] = folders.find(([p]) => url.pathname.startsWith(p));
    let file = path.join(folder, decodeURIComponent(url.pathname.slice(prefix.length)));
    if (url.pathname.endsWith('/')) file = path.join(file, 'index.html');
    if (!file.startsWith(folder + path.sep) && file !== folder) { response.writeHead(403).end(); return; }
    fs.readFile(file, (error, bytes) => {
      if (error) { response.writeHead(404, { 'Content-Type': 'text/plain' }).end(`${url.pathname}: not found`); return; }
      const headers = { 'Content-Type': types[path.extname(file).toLowerCase()] || 'application/octet-stream', 'Cache-Control': 'no-store' };
      if (isolated) Object.assign(headers, { 'Cross-Origin-Opener-Policy': 'same-origin', 'Cross-Origin-Embedder-Policy': 'require-corp' });
      response.writeHead(200, headers).end(bytes);
    });
  });
  return new Promise((resolve) => server.listen(port, '127.0.0.1', () => resolve(server)));
}

if (import.meta.url === `file://${process.argv[1]}`) {
  const args = process.argv.slice(2);
  const option = (name) => { const at = args.indexOf(name); return at >= 0 ? args[at + 1] : undefined; };
  const mounts = {};
  args.forEach((arg, i) => { if (arg === '--mount') { const [prefix, folder] = args[i + 1].split('='); mounts[prefix] = folder; } });
  const server = await serve({ port: Number(option('--port') || 8080), mounts, isolated: args.includes('--isolated') });
  console.log(`serving web/ on http://127.0.0.1:${server.address().port}/ (the example: /examples/)`);
}
