// Connectivity of a PolygonMesh (see mesh_formats.js) for drawing and for finding singular vertices.

/** Fan triangulation of every polygon: Uint32Array, 3·(C − 2F) vertex indices. */
export function triangulate(mesh) {
  const { faceOffsets, faceVertices } = mesh;
  const faceCount = faceOffsets.length - 1;
  const triangles = new Uint32Array(3 * (faceVertices.length - 2 * faceCount));
  let out = 0;
  for (let f = 0; f < faceCount; ++f) {
    const first = faceOffsets[f];
    for (let c = first + 1; c + 1 < faceOffsets[f + 1]; ++c) {
      triangles[out++] = faceVertices[first];
      triangles[out++] = faceVertices[c];
      triangles[out++] = faceVertices[c + 1];
    }
  }
  return triangles;
}

/**
 * The undirected edges of the polygons (not of their triangulation), each once, with the number
 * of faces around it. Returns { edges: Uint32Array 2·E (a < b), faceCounts: Uint32Array E }.
 */
export function uniqueEdges(mesh) {
  const { faceOffsets, faceVertices } = mesh;
  const vertexCount = mesh.positions.length / 3;
  const index = new Map(); // a·V + b -> edge id
  const edges = [];
  const faceCounts = [];
  for (let f = 0; f + 1 < faceOffsets.length; ++f) {
    const first = faceOffsets[f];
    const last = faceOffsets[f + 1];
    for (let c = first; c < last; ++c) {
      const u = faceVertices[c];
      const w = faceVertices[c + 1 < last ? c + 1 : first];
      const a = Math.min(u, w);
      const b = Math.max(u, w);
      const key = a * vertexCount + b;
      const id = index.get(key);
      if (id === undefined) {
        index.set(key, edges.length / 2);
        edges.push(a, b);
        faceCounts.push(1);
      } else {
        faceCounts[id] += 1;
      }
    }
  }
  return { edges: Uint32Array.from(edges), faceCounts: Uint32Array.from(faceCounts) };
}

/**
 * Valence (number of incident edges) of every vertex, and whether it lies on the boundary (on an
 * edge with a single face). Returns { valence: Uint32Array V, onBoundary: Uint8Array V }.
 */
export function vertexValences(mesh) {
  const vertexCount = mesh.positions.length / 3;
  const valence = new Uint32Array(vertexCount);
  const onBoundary = new Uint8Array(vertexCount);
  const { edges, faceCounts } = uniqueEdges(mesh);
  for (let e = 0; e < faceCounts.length; ++e) {
    const a = edges[2 * e];
    const b = edges[2 * e + 1];
    valence[a] += 1;
    valence[b] += 1;
    if (faceCounts[e] === 1) onBoundary[a] = onBoundary[b] = 1;
  }
  return { valence, onBoundary };
}

/**
 * Irregular interior vertices of a remesh whose regular valence is `regular` (6 for triangles,
 * 4 for quads): vertices with fewer edges (valence 5 for triangles: positive index, cone angle
 * deficit) and with more (valence 7: negative index). Boundary vertices are not counted.
 * Returns { below: number[], above: number[] } of vertex indices.
 */
export function irregularVertices(mesh, regular) {
  const { valence, onBoundary } = vertexValences(mesh);
  const below = [];
  const above = [];
  for (let v = 0; v < valence.length; ++v) {
    if (onBoundary[v] || valence[v] === 0) continue;
    if (valence[v] < regular) below.push(v);
    else if (valence[v] > regular) above.push(v);
  }
  return { below, above };
}

/** Mean length of the polygon edges (used to size the singularity markers). */
export function meanEdgeLength(mesh) {
  const { edges } = uniqueEdges(mesh);
  const p = mesh.positions;
  let sum = 0;
  for (let e = 0; e < edges.length; e += 2) {
    const a = 3 * edges[e];
    const b = 3 * edges[e + 1];
    sum += Math.hypot(p[a] - p[b], p[a + 1] - p[b + 1], p[a + 2] - p[b + 2]);
  }
  return edges.length ? sum / (edges.length / 2) : 0;
}
