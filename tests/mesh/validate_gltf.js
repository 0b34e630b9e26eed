// Validates glTF files with the Khronos glTF validator (npm gltf-validator, fetched by
// data/fetch.sh into data/cache/npm/gltf-validator/; SSS_GLTF_VALIDATOR names another folder).
//   node tests/mesh/validate_gltf.js FILE.glb...
// Prints one summary line per file ("FILE: N errors, N warnings, N infos, N hints") and every
// error and warning; exits 1 when a file has an error or cannot be read, 2 on usage.
'use strict';
const fs = require('fs');
const path = require('path');

const files = process.argv.slice(2);
if (files.length === 0) {
  console.error('usage: node validate_gltf.js FILE.glb...');
  process.exit(2);
}
const validatorDir = process.env.SSS_GLTF_VALIDATOR ||
    path.join(__dirname, '..', '..', 'data', 'cache', 'npm', 'gltf-validator');
let validator;
try {
  validator = require(validatorDir);
} catch (e) {
  console.error(`validate_gltf: error: no glTF validator in ${validatorDir}: run data/fetch.sh`);
  process.exit(1);
}

async function validate(file) {
  const bytes = new Uint8Array(fs.readFileSync(file));
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 0,
    // Our GLBs are self-contained: any external resource is an error.
    externalResourceFunction: (uri) => Promise.reject(new Error(`external resource ${uri}`)),
  });
  const i = report.issues;
  console.log(`${file}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ` +
              `${i.numHints} hints (gltf-validator ${report.validatorVersion})`);
  for (const m of i.messages) {
    if (m.severity <= 1) {
      console.log(`  ${m.severity === 0 ? 'error' : 'warning'} ${m.code}: ${m.message} ` +
                  `(${m.pointer || m.offset || ''})`);
    }
  }
  return i.numErrors === 0;
}

(async () => {
  let ok = true;
  for (const file of files) {
    try {
      ok = (await validate(file)) && ok;
    } catch (e) {
      console.log(`${file}: cannot validate: ${e.message || e}`);
      ok = false;
    }
  }
  process.exit(ok ? 0 : 1);
})();
