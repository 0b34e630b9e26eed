// Converts a CommonJS mesh module (`exports.positions=[[x,y,z],...]; exports.cells=[[i,j,k],...]`,
// the layout of the npm `bunny` and `teapot` packages) to a binary little-endian PLY: float x y z,
// faces as `list uchar int`. Polygons with more than three corners are fan-triangulated.
// The module is parsed as data, never executed.
//
// Usage: node mesh-js-to-ply.js INPUT.js OUTPUT.ply
'use strict';
const fs = require('fs');

function fail(file, problem) {
  process.stderr.write(`${file}: ${problem}\n`);
  process.exit(1);
}

// Returns the JSON array literal assigned to exports.<name>, found by bracket matching.
function exportedArray(text, name, file) {
  const m = new RegExp(`exports\\.${name}\\s*=\\s*\\[`).exec(text);
  if (!m) fail(file, `no exports.${name} array`);
  const start = m.index + m[0].length - 1;
  let depth = 0;
  for (let i = start; i < text.length; ++i) {
    if (text[i] === '[')
      ++depth;
    else if (text[i] === ']' && --depth === 0) {
      try {
        return JSON.parse(text.slice(start, i + 1));
      } catch (e) {
        fail(file, `exports.${name} is not a plain numeric array (${e.message})`);
      }
    }
  }
  fail(file, `exports.${name} array is not closed`);
}

const [input, output] = process.argv.slice(2);
if (!input || !output)
  fail('mesh-js-to-ply.js', 'usage: node mesh-js-to-ply.js INPUT.js OUTPUT.ply');
const text = fs.readFileSync(input, 'utf8');
const positions = exportedArray(text, 'positions', input);
const cells = exportedArray(text, 'cells', input);

positions.forEach((p, i) => {
  if (!Array.isArray(p) || p.length !== 3 || !p.every(Number.isFinite))
    fail(input, `position ${i} is not three finite numbers`);
});
const triangles = [];
cells.forEach((c, i) => {
  if (!Array.isArray(c) || c.length < 3) fail(input, `cell ${i} has fewer than three corners`);
  if (!c.every((v) => Number.isInteger(v) && v >= 0 && v < positions.length))
    fail(input, `cell ${i} indexes outside the ${positions.length} positions`);
  for (let k = 1; k + 1 < c.length; ++k) triangles.push([c[0], c[k], c[k + 1]]);
});

const header = Buffer.from(
    'ply\nformat binary_little_endian 1.0\n' +
        `element vertex ${positions.length}\n` +
        'property float x\nproperty float y\nproperty float z\n' +
        `element face ${triangles.length}\n` +
        'property list uchar int vertex_indices\nend_header\n',
    'ascii');
const body = Buffer.alloc(positions.length * 12 + triangles.length * 13);
let at = 0;
for (const p of positions) {
  for (const x of p) at = body.writeFloatLE(x, at);
}
for (const t of triangles) {
  at = body.writeUInt8(3, at);
  for (const v of t) at = body.writeInt32LE(v, at);
}
fs.writeFileSync(output, Buffer.concat([header, body]));
