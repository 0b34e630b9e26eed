// Prints one line describing each sample file from its header, so that data/fetch.sh can check
// and summarize what it fetched: a PLY's vertex and face counts, an OpenEXR image's size and
// channels. A file that is neither, or whose header is broken, is an error.
//
// Usage: node describe.js FILE...
'use strict';
const fs = require('fs');

function fail(file, problem) {
  process.stderr.write(`${file}: ${problem}\n`);
  process.exit(1);
}

function describePly(file, bytes) {
  const end = bytes.indexOf('end_header\n');
  if (end < 0) fail(file, 'PLY header has no end_header');
  const header = bytes.subarray(0, end).toString('latin1');
  const format = /^format (\S+) /m.exec(header);
  const vertices = /^element vertex (\d+)$/m.exec(header);
  const faces = /^element face (\d+)$/m.exec(header);
  if (!format || !vertices || !faces) fail(file, 'PLY header lacks format, vertex or face count');
  return `${vertices[1]} vertices, ${faces[1]} faces, PLY ${format[1]}`;
}

// OpenEXR header: magic, version, then attributes (name\0 type\0 int32 size, value) up to an
// empty name. dataWindow (box2i) gives the size, channels (chlist) the channel names and types.
function describeExr(file, bytes) {
  let at = 8;
  const cstring = () => {
    const end = bytes.indexOf(0, at);
    if (end < 0) fail(file, 'EXR header is truncated');
    const s = bytes.subarray(at, end).toString('latin1');
    at = end + 1;
    return s;
  };
  let size, channels;
  for (;;) {
    const name = cstring();
    if (name === '') break;
    cstring();  // attribute type
    if (at + 4 > bytes.length) fail(file, 'EXR header is truncated');
    const length = bytes.readInt32LE(at);
    at += 4;
    const value = bytes.subarray(at, at + length);
    if (name === 'dataWindow') {
      const [x0, y0, x1, y1] = [0, 4, 8, 12].map((o) => value.readInt32LE(o));
      size = `${x1 - x0 + 1}x${y1 - y0 + 1}`;
    } else if (name === 'channels') {
      const names = [], types = new Set();
      for (let c = 0; value[c] !== 0 && c < value.length;) {
        const end = value.indexOf(0, c);
        names.push(value.subarray(c, end).toString('latin1'));
        types.add(['uint', 'half', 'float'][value.readInt32LE(end + 1)]);
        c = end + 1 + 16;
      }
      channels = `${names.join(',')} ${[...types].join('/')}`;
    }
    at += length;
  }
  if (!size || !channels) fail(file, 'EXR header lacks dataWindow or channels');
  return `${size}, ${channels}, OpenEXR`;
}

for (const file of process.argv.slice(2)) {
  let bytes;
  try {
    bytes = fs.readFileSync(file);
  } catch (e) {
    fail(file, e.code === 'ENOENT' ? 'missing' : e.message);
  }
  let line;
  if (bytes.subarray(0, 4).toString('latin1') === 'ply\n')
    line = describePly(file, bytes);
  else if (bytes.length >= 8 && bytes.readUInt32LE(0) === 20000630)
    line = describeExr(file, bytes);
  else
    fail(file, 'neither PLY nor OpenEXR');
  process.stdout.write(`${file}\t${line}\n`);
}
