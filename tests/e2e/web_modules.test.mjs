// Unit tests of the page's mesh readers and connectivity (clients/web), in Node without a browser:
// the same icosahedron written as OBJ, OFF, ascii and binary PLY, ascii and binary STL reads back
// to the same mesh; valences, boundary and irregular vertices on meshes with known answers.
// usage: node --test web_modules.test.mjs

import assert from 'node:assert/strict';
import test from 'node:test';
import { MeshFormatError, parseMesh, parseObj } from '../../clients/web/mesh_formats.js';
import { irregularVertices, triangulate, uniqueEdges, vertexValences } from '../../clients/web/mesh_topology.js';

const t = (1 + Math.sqrt(5)) / 2;
const kIcoVertices = [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t],
  [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]];
const kIcoFaces = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4],
  [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9],
  [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]];

const encode = (text) => new TextEncoder().encode(text).buffer;
const objText = () =>
  kIcoVertices.map((v) => `v ${v.join(' ')}`).join('\n') + '\n' +
  kIcoFaces.map((f) => `f ${f.map((i) => i + 1).join(' ')}`).join('\n') + '\n';
const offText = () =>
  `OFF\n# icosahedron\n${kIcoVertices.length} ${kIcoFaces.length} 30\n` +
  kIcoVertices.map((v) => v.join(' ')).join('\n') + '\n' +
  kIcoFaces.map((f) => `3 ${f.join(' ')}`).join('\n') + '\n';
const plyHeader = (format) =>
  `ply\nformat ${format} 1.0\ncomment test\nelement vertex ${kIcoVertices.length}\nproperty float x\n` +
  `property float y\nproperty float z\nproperty uchar red\nelement face ${kIcoFaces.length}\n` +
  'property list uchar int vertex_indices\nend_header\n';

function binaryPly() {
  const header = new TextEncoder().encode(plyHeader('binary_little_endian'));
  const body = new DataView(new ArrayBuffer(kIcoVertices.length * 13 + kIcoFaces.length * 13));
  let at = 0;
  for (const v of kIcoVertices) {
    for (const c of v) { body.setFloat32(at, c, true); at += 4; }
    body.setUint8(at++, 200);
  }
  for (const f of kIcoFaces) {
    body.setUint8(at++, 3);
    for (const i of f) { body.setInt32(at, i, true); at += 4; }
  }
  const bytes = new Uint8Array(header.length + body.byteLength);
  bytes.set(header);
  bytes.set(new Uint8Array(body.buffer), header.length);
  return bytes.buffer;
}

function binaryStl() {
  const view = new DataView(new ArrayBuffer(84 + 50 * kIcoFaces.length));
  view.setUint32(80, kIcoFaces.length, true);
  kIcoFaces.forEach((f, k) => {
    f.forEach((i, c) => kIcoVertices[i].forEach((x, a) => view.setFloat32(84 + 50 * k + 12 + 12 * c + 4 * a, x, true)));
  });
  return view.buffer;
}
const asciiStl = () =>
  'solid ico\n' + kIcoFaces.map((f) => 'facet normal 0 0 0\nouter loop\n' +
    f.map((i) => `vertex ${kIcoVertices[i].join(' ')}`).join('\n') + '\nendloop\nendfacet').join('\n') + '\nendsolid ico\n';

/** The mesh as a set of faces given by their corner coordinates (rounded), rotation-invariant. */
function faceSet(mesh) {
  const key = (v) => Array.from(mesh.positions.subarray(3 * v, 3 * v + 3), (x) => x.toFixed(4)).join(',');
  const faces = [];
  for (let f = 0; f + 1 < mesh.faceOffsets.length; ++f) {
    const corners = Array.from(mesh.faceVertices.subarray(mesh.faceOffsets[f], mesh.faceOffsets[f + 1]), key);
    const first = corners.indexOf([...corners].sort()[0]);
    faces.push([...corners.slice(first), ...corners.slice(0, first)].join(' | '));
  }
  return faces.sort();
}

test('every format reads back the same icosahedron', () => {
  const reference = faceSet(parseObj(objText()));
  assert.equal(reference.length, 20);
  const inputs = {
    off: encode(offText()),
    plyAscii: encode(plyHeader('ascii') + kIcoVertices.map((v) => `${v.join(' ')} 200`).join('\n') + '\n' +
      kIcoFaces.map((f) => `3 ${f.join(' ')}`).join('\n') + '\n'),
    plyBinary: binaryPly(),
    stlAscii: encode(asciiStl()),
    stlBinary: binaryStl(),
  };
  for (const [name, buffer] of Object.entries(inputs)) {
    const mesh = parseMesh(buffer);
    assert.equal(mesh.positions.length / 3, 12, `${name}: vertices (STL corners welded)`);
    assert.deepEqual(faceSet(mesh), reference, name);
  }
});

test('OBJ texture coordinates per corner, negative indices, polygons', () => {
  const mesh = parseObj('v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf -4/1 -3/2 -2/3 -1/4\n');
  assert.deepEqual(Array.from(mesh.faceOffsets), [0, 4]);
  assert.deepEqual(Array.from(mesh.faceVertices), [0, 1, 2, 3]);
  assert.deepEqual(Array.from(mesh.faceTexcoords), [0, 1, 2, 3]);
  assert.deepEqual(Array.from(triangulate(mesh)), [0, 1, 2, 0, 2, 3]);
  assert.throws(() => parseObj('v 0 0 0\nf 1 2 3\n'), MeshFormatError);
});

test('coordinates far from the origin keep their detail (a georeferenced scan)', () => {
  // As floats, 4123456.789 would round to 4123456.75 and the 1 mm triangle would collapse.
  const mesh = parseObj('v 512345.001 4123456.789 87.5\nv 512345.002 4123456.789 87.5\n' +
    'v 512345.001 4123456.790 87.5\nf 1 2 3\n');
  assert.deepEqual(Array.from(mesh.positions.subarray(0, 3)), [512345.001, 4123456.789, 87.5]);
  assert.notEqual(mesh.positions[1], mesh.positions[7]);
});

test('icosahedron: 30 edges, every vertex of valence 5, all 12 irregular (index +1/6 each)', () => {
  const mesh = parseObj(objText());
  const { edges, faceCounts } = uniqueEdges(mesh);
  assert.equal(edges.length / 2, 30);
  assert.ok(faceCounts.every((n) => n === 2));
  const { valence, onBoundary } = vertexValences(mesh);
  assert.ok(valence.every((n) => n === 5));
  assert.ok(onBoundary.every((b) => b === 0));
  const irregular = irregularVertices(mesh, 6);
  assert.equal(irregular.below.length, 12); // Poincaré–Hopf: 12 · (6 − 5)/6 = χ = 2
  assert.equal(irregular.above.length, 0);
});

test('boundary vertices are not counted as irregular', () => {
  // A hexagon fan: the centre is interior with valence 6, the rim is boundary.
  const rim = Array.from({ length: 6 }, (_, k) => `v ${Math.cos((k * Math.PI) / 3)} ${Math.sin((k * Math.PI) / 3)} 0`);
  const faces = Array.from({ length: 6 }, (_, k) => `f 7 ${k + 1} ${((k + 1) % 6) + 1}`);
  const mesh = parseObj(`${rim.join('\n')}\nv 0 0 0\n${faces.join('\n')}\n`);
  const { valence, onBoundary } = vertexValences(mesh);
  assert.equal(valence[6], 6);
  assert.equal(onBoundary[6], 0);
  assert.ok(Array.from(onBoundary.subarray(0, 6)).every((b) => b === 1));
  assert.deepEqual(irregularVertices(mesh, 6), { below: [], above: [] });
  // With the centre's valence 6 against quads' regular 4, it is irregular (above).
  assert.deepEqual(irregularVertices(mesh, 4), { below: [], above: [6] });
});
