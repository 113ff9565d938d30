// Mesh file readers for the viewer: OBJ, OFF, PLY (ascii and binary) and STL (ascii and binary).
//
// Every reader returns a PolygonMesh:
//   positions      Float64Array, 3·V   vertex coordinates (doubles: a georeferenced scan, ~10^6
//                                      units from the origin, keeps its detail; the viewer
//                                      draws floats relative to the model's centre)
//   faceOffsets    Uint32Array,  F+1   face f has corners faceOffsets[f] .. faceOffsets[f+1]-1
//   faceVertices   Uint32Array,  C     vertex index of each corner (C = total number of corners)
//   texcoords      Float32Array, 2·T   texture coordinates (OBJ `vt`), or null
//   faceTexcoords  Uint32Array,  C     texcoord index of each corner, or null
// Faces are kept as polygons (the hexagonal dual has 6-gons); mesh_topology.js triangulates them.

/** Thrown for a file the viewer cannot read; the message says what is wrong. */
export class MeshFormatError extends Error {}

class PolygonBuilder {
  constructor() {
    this.positions = [];
    this.texcoords = [];
    this.faceOffsets = [0];
    this.faceVertices = [];
    this.faceTexcoords = [];
  }

  addFace(vertices, texcoords) {
    if (vertices.length < 3) return;
    for (let i = 0; i < vertices.length; ++i) {
      this.faceVertices.push(vertices[i]);
      if (texcoords) this.faceTexcoords.push(texcoords[i]);
    }
    this.faceOffsets.push(this.faceVertices.length);
  }

  build(what) {
    const vertexCount = this.positions.length / 3;
    if (vertexCount === 0) throw new MeshFormatError(`${what}: no vertices`);
    for (const v of this.faceVertices) {
      if (!(v >= 0 && v < vertexCount)) {
        throw new MeshFormatError(`${what}: face refers to vertex ${v + 1} of ${vertexCount}`);
      }
    }
    const hasTexcoords =
      this.texcoords.length > 0 && this.faceTexcoords.length === this.faceVertices.length;
    return {
      positions: Float64Array.from(this.positions),
      faceOffsets: Uint32Array.from(this.faceOffsets),
      faceVertices: Uint32Array.from(this.faceVertices),
      texcoords: hasTexcoords ? Float32Array.from(this.texcoords) : null,
      faceTexcoords: hasTexcoords ? Uint32Array.from(this.faceTexcoords) : null,
    };
  }
}

/** Wavefront OBJ: `v`, `vt` and `f` records (1-based or negative indices, v/vt/vn corners). */
export function parseObj(text) {
  const builder = new PolygonBuilder();
  const lines = text.split('\n');
  for (let lineNo = 0; lineNo < lines.length; ++lineNo) {
    const line = lines[lineNo].trim();
    if (line.length < 2) continue;
    const fields = line.split(/\s+/);
    switch (fields[0]) {
      case 'v':
        builder.positions.push(+fields[1], +fields[2], +fields[3]);
        break;
      case 'vt':
        builder.texcoords.push(+fields[1], +fields[2]);
        break;
      case 'f': {
        const vertexCount = builder.positions.length / 3;
        const texcoordCount = builder.texcoords.length / 2;
        const vertices = [];
        const texcoords = [];
        for (let i = 1; i < fields.length; ++i) {
          const [v, vt] = fields[i].split('/');
          const vi = parseInt(v, 10);
          if (Number.isNaN(vi)) throw new MeshFormatError(`OBJ line ${lineNo + 1}: bad face "${line}"`);
          vertices.push(vi < 0 ? vertexCount + vi : vi - 1);
          const ti = parseInt(vt, 10);
          texcoords.push(Number.isNaN(ti) ? -1 : ti < 0 ? texcoordCount + ti : ti - 1);
        }
        builder.addFace(vertices, texcoords.every((t) => t >= 0) ? texcoords : null);
        break;
      }
      default:
        break;
    }
  }
  return builder.build('OBJ');
}

/** Object File Format: "OFF", counts, vertex lines, then face lines "n i0 ... i(n-1) [colour]". */
export function parseOff(text) {
  const lines = text
    .split('\n')
    .map((line) => line.replace(/#.*/, '').trim())
    .filter((line) => line.length > 0);
  const header = lines[0] ? lines[0].split(/\s+/) : [];
  if (!/^[CN]*OFF$/.test(header[0] ?? '')) throw new MeshFormatError('OFF: missing "OFF" header');
  // The counts follow the keyword, on the same line or on the next one.
  let at = 1;
  const counts = header.length > 1 ? header.slice(1) : (lines[at++] ?? '').split(/\s+/);
  const vertexCount = parseInt(counts[0], 10);
  const faceCount = parseInt(counts[1], 10);
  if (!(vertexCount >= 0 && faceCount >= 0)) throw new MeshFormatError('OFF: bad counts line');
  if (lines.length < at + vertexCount + faceCount) throw new MeshFormatError('OFF: file is truncated');
  const builder = new PolygonBuilder();
  for (let v = 0; v < vertexCount; ++v) {
    const f = lines[at++].split(/\s+/);
    builder.positions.push(+f[0], +f[1], +f[2]);
  }
  for (let face = 0; face < faceCount; ++face) {
    const f = lines[at++].split(/\s+/);
    const n = parseInt(f[0], 10);
    if (!(n >= 0) || f.length < n + 1) throw new MeshFormatError(`OFF: face ${face} is truncated`);
    builder.addFace(f.slice(1, n + 1).map((i) => parseInt(i, 10)), null);
  }
  return builder.build('OFF');
}

const kPlyTypes = {
  char: ['getInt8', 1], int8: ['getInt8', 1], uchar: ['getUint8', 1], uint8: ['getUint8', 1],
  short: ['getInt16', 2], int16: ['getInt16', 2], ushort: ['getUint16', 2], uint16: ['getUint16', 2],
  int: ['getInt32', 4], int32: ['getInt32', 4], uint: ['getUint32', 4], uint32: ['getUint32', 4],
  float: ['getFloat32', 4], float32: ['getFloat32', 4], double: ['getFloat64', 8], float64: ['getFloat64', 8],
};

/** Stanford PLY, ascii or binary (either endianness): vertex x/y/z and face vertex_indices. */
export function parsePly(buffer) {
  const bytes = new Uint8Array(buffer);
  const headerText = new TextDecoder('latin1').decode(bytes.subarray(0, Math.min(bytes.length, 65536)));
  const headerEnd = headerText.search(/end_header\r?\n/);
  if (!headerText.startsWith('ply') || headerEnd < 0) throw new MeshFormatError('PLY: bad header');
  const bodyStart = headerEnd + headerText.slice(headerEnd).indexOf('\n') + 1;
  let format = null;
  const elements = [];
  for (const line of headerText.slice(0, headerEnd).split(/\r?\n/)) {
    const f = line.trim().split(/\s+/);
    if (f[0] === 'format') format = f[1];
    else if (f[0] === 'element') elements.push({ name: f[1], count: parseInt(f[2], 10), properties: [] });
    else if (f[0] === 'property' && elements.length) {
      const props = elements[elements.length - 1].properties;
      if (f[1] === 'list') props.push({ name: f[4], countType: f[2], type: f[3] });
      else props.push({ name: f[2], type: f[1] });
    }
  }
  for (const element of elements) {
    for (const p of element.properties) {
      if (!kPlyTypes[p.type] || (p.countType && !kPlyTypes[p.countType])) {
        throw new MeshFormatError(`PLY: unknown property type in "${element.name}.${p.name}"`);
      }
    }
  }

  // A reader yields one scalar at a time, from text tokens or from a DataView.
  let next;
  if (format === 'ascii') {
    const tokens = new TextDecoder().decode(bytes.subarray(bodyStart)).trim().split(/\s+/);
    let at = 0;
    next = () => {
      if (at >= tokens.length) throw new MeshFormatError('PLY: file is truncated');
      return +tokens[at++];
    };
  } else if (format === 'binary_little_endian' || format === 'binary_big_endian') {
    const view = new DataView(buffer);
    const little = format === 'binary_little_endian';
    let at = bodyStart;
    next = (type) => {
      const [getter, size] = kPlyTypes[type];
      if (at + size > view.byteLength) throw new MeshFormatError('PLY: file is truncated');
      const value = view[getter](at, little);
      at += size;
      return value;
    };
  } else {
    throw new MeshFormatError(`PLY: unknown format "${format}"`);
  }

  const builder = new PolygonBuilder();
  for (const element of elements) {
    for (let i = 0; i < element.count; ++i) {
      const xyz = [0, 0, 0];
      let corners = null;
      for (const p of element.properties) {
        if (p.countType) {
          const n = next(p.countType);
          const list = [];
          for (let k = 0; k < n; ++k) list.push(next(p.type));
          if (p.name === 'vertex_indices' || p.name === 'vertex_index') corners = list;
        } else {
          const value = next(p.type);
          const axis = ['x', 'y', 'z'].indexOf(p.name);
          if (axis >= 0) xyz[axis] = value;
        }
      }
      if (element.name === 'vertex') builder.positions.push(...xyz);
      else if (element.name === 'face' && corners) builder.addFace(corners, null);
    }
  }
  return builder.build('PLY');
}

/** STL, binary or ascii; corners with identical coordinates become one vertex. */
export function parseStl(buffer) {
  const builder = new PolygonBuilder();
  const vertexIds = new Map();
  const vertexId = (x, y, z) => {
    const key = `${x},${y},${z}`;
    let id = vertexIds.get(key);
    if (id === undefined) {
      id = vertexIds.size;
      vertexIds.set(key, id);
      builder.positions.push(x, y, z);
    }
    return id;
  };
  const view = new DataView(buffer);
  const triangleCount = buffer.byteLength >= 84 ? view.getUint32(80, true) : -1;
  if (triangleCount >= 0 && buffer.byteLength === 84 + 50 * triangleCount) {
    for (let t = 0; t < triangleCount; ++t) {
      const base = 84 + 50 * t + 12; // skip the facet normal
      const corners = [];
      for (let k = 0; k < 3; ++k) {
        const o = base + 12 * k;
        corners.push(vertexId(view.getFloat32(o, true), view.getFloat32(o + 4, true), view.getFloat32(o + 8, true)));
      }
      builder.addFace(corners, null);
    }
    return builder.build('STL');
  }
  const text = new TextDecoder().decode(buffer);
  const vertexPattern = /vertex\s+(\S+)\s+(\S+)\s+(\S+)/g;
  let corners = [];
  for (let match = vertexPattern.exec(text); match; match = vertexPattern.exec(text)) {
    corners.push(vertexId(+match[1], +match[2], +match[3]));
    if (corners.length === 3) {
      builder.addFace(corners, null);
      corners = [];
    }
  }
  return builder.build('STL');
}

/** Reads a mesh file, detecting its format from the bytes (as the server does). */
export function parseMesh(buffer) {
  const start = new TextDecoder('latin1').decode(new Uint8Array(buffer, 0, Math.min(buffer.byteLength, 256)));
  if (start.startsWith('ply')) return parsePly(buffer);
  if (/^\s*[CN]*OFF\b/.test(start)) return parseOff(new TextDecoder().decode(buffer));
  if (buffer.byteLength >= 84) {
    const triangles = new DataView(buffer).getUint32(80, true);
    if (buffer.byteLength === 84 + 50 * triangles || /^\s*solid\b/.test(start)) return parseStl(buffer);
  }
  return parseObj(new TextDecoder().decode(buffer));
}
