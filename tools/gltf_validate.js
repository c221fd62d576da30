#!/usr/bin/env node
// The Khronos glTF validator on one file: prints its report (JSON) and exits 1 when it has errors, 2 when the
// validator cannot be loaded or the file read.
//
//   NODE_PATH=build/node/node_modules node tools/gltf_validate.js out.glb
//
// The validator is the npm package gltf-validator (a library, no command): scripts/test.sh installs it into the
// build folder, and the tests point NODE_PATH there.
'use strict';
const fs = require('fs');
const path = require('path');

const file = process.argv[2];
if (!file) {
  console.error('usage: gltf_validate.js FILE.glb|FILE.gltf');
  process.exit(2);
}
let validator;
try {
  validator = require('gltf-validator');
} catch (e) {
  console.error(`gltf_validate: cannot load the npm package gltf-validator (NODE_PATH=${process.env.NODE_PATH || ''}): ${e.message}`);
  process.exit(2);
}
let bytes;
try {
  bytes = new Uint8Array(fs.readFileSync(file));
} catch (e) {
  console.error(`${file}: cannot be read: ${e.message}`);
  process.exit(2);
}
// External resources (a .gltf's .bin or images beside it) are read from the file's folder.
const folder = path.dirname(file);
validator
  .validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 200,
    externalResourceFunction: (uri) =>
      new Promise((resolve, reject) => {
        fs.readFile(path.join(folder, decodeURIComponent(uri)), (error, data) =>
          error ? reject(error.toString()) : resolve(new Uint8Array(data)));
      }),
  })
  .then((report) => {
    console.log(JSON.stringify(report, null, 2));
    const issues = report.issues;
    console.error(`${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ${issues.numInfos} infos, ${issues.numHints} hints`);
    process.exit(issues.numErrors > 0 ? 1 : 0);
  })
  .catch((error) => {
    console.error(`${file}: the validator failed: ${error}`);
    process.exit(2);
  });
