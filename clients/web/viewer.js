// three.js viewer: the input and the remesh, alone or side by side, with one orbiting camera.
//
// Layers drawn for the remesh: surface, its wireframe, irregular vertices as spheres coloured by
// valence, the hexagonal dual's edges. For the input: surface, wireframe, or the textured result
// (the repaired input with the seamless parameterization) with the hexagonal tiling texture.

import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { drawHexTile } from './hex_texture.js';
import { irregularVertices, meanEdgeLength, triangulate, uniqueEdges } from './mesh_topology.js';

export const kValenceColours = { below: 0x1f6fd1, above: 0xd1361f };
const kBackground = 0xf4f5f7;

/** The centre of the bounding box of `positions` (model coordinates, doubles). */
function boxCentre(positions) {
  const low = [Infinity, Infinity, Infinity];
  const high = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < positions.length; ++i) {
    low[i % 3] = Math.min(low[i % 3], positions[i]);
    high[i % 3] = Math.max(high[i % 3], positions[i]);
  }
  return low.map((l, a) => 0.5 * (l + high[a]));
}

/** `mesh` with float positions relative to `origin`, as WebGL draws them: model coordinates may
 * be far from 0 (a georeferenced scan, ~10^6 units), where floats would round off its detail. */
function relativeTo(mesh, origin) {
  const positions = new Float32Array(mesh.positions.length);
  for (let i = 0; i < positions.length; ++i) positions[i] = mesh.positions[i] - origin[i % 3];
  return { ...mesh, positions };
}

function surfaceGeometry(mesh) {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(mesh.positions, 3));
  geometry.setIndex(new THREE.BufferAttribute(triangulate(mesh), 1));
  geometry.computeVertexNormals();
  return geometry;
}

/** One vertex per (position, texcoord) corner pair, so that seams keep both texcoords. */
function texturedGeometry(mesh) {
  const { positions, texcoords, faceVertices, faceTexcoords } = mesh;
  const cornerIds = new Map();
  const outPositions = [];
  const outUvs = [];
  const corner = new Uint32Array(faceVertices.length);
  for (let c = 0; c < faceVertices.length; ++c) {
    const key = `${faceVertices[c]}/${faceTexcoords[c]}`;
    let id = cornerIds.get(key);
    if (id === undefined) {
      id = cornerIds.size;
      cornerIds.set(key, id);
      const v = 3 * faceVertices[c];
      outPositions.push(positions[v], positions[v + 1], positions[v + 2]);
      outUvs.push(texcoords[2 * faceTexcoords[c]], texcoords[2 * faceTexcoords[c] + 1]);
    }
    corner[c] = id;
  }
  const split = {
    positions: Float32Array.from(outPositions),
    faceOffsets: mesh.faceOffsets,
    faceVertices: corner,
  };
  const geometry = surfaceGeometry(split);
  geometry.setAttribute('uv', new THREE.BufferAttribute(Float32Array.from(outUvs), 2));
  return geometry;
}

function edgeLines(mesh, colour, opacity = 1) {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(mesh.positions, 3));
  geometry.setIndex(new THREE.BufferAttribute(uniqueEdges(mesh).edges, 1));
  const material = new THREE.LineBasicMaterial({ color: colour, transparent: opacity < 1, opacity });
  return new THREE.LineSegments(geometry, material);
}

function surfaceMaterial(colour) {
  // Pushed back a little so that edges drawn on the surface win the depth test.
  return new THREE.MeshStandardMaterial({
    color: colour, roughness: 0.8, metalness: 0.0, side: THREE.DoubleSide,
    polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
  });
}

function markerSpheres(mesh, vertices, radius, colour) {
  const sphere = new THREE.SphereGeometry(radius, 12, 8);
  const markers = new THREE.InstancedMesh(sphere, new THREE.MeshStandardMaterial({ color: colour }), vertices.length);
  const matrix = new THREE.Matrix4();
  vertices.forEach((v, i) => {
    matrix.makeTranslation(mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]);
    markers.setMatrixAt(i, matrix);
  });
  return markers;
}

function dispose(object) {
  object.traverse((node) => {
    node.geometry?.dispose();
    node.material?.map?.dispose();
    node.material?.dispose();
  });
}

export class MeshViewer {
  /** Renders into `canvas`; call resize() when its box changes. */
  constructor(canvas) {
    this.canvas = canvas;
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: true });
    this.renderer.setPixelRatio(window.devicePixelRatio);
    this.renderer.setScissorTest(true);
    this.camera = new THREE.PerspectiveCamera(40, 1, 0.01, 100);
    this.camera.position.set(0, 0, 3);
    this.controls = new OrbitControls(this.camera, canvas);
    this.controls.enableDamping = true;

    // Two scenes that share lights and camera: left/only = input, right/only = remesh.
    this.scenes = { input: new THREE.Scene(), remesh: new THREE.Scene() };
    for (const scene of Object.values(this.scenes)) {
      scene.background = new THREE.Color(kBackground);
      scene.add(new THREE.HemisphereLight(0xffffff, 0x667788, 1.6));
      const sun = new THREE.DirectionalLight(0xffffff, 1.8);
      sun.position.set(2, 3, 4);
      scene.add(sun);
    }
    this.layers = {}; // name -> Object3D
    this.origin = [0, 0, 0]; // model coordinates drawn at the scene's 0: the input's centre
    this.options = { mode: 'side', wireframe: true, singularities: true, dual: false, texture: false };
    this.irregular = { below: [], above: [] };
    this.hexTile = new THREE.CanvasTexture(drawHexTile(document.createElement('canvas')));
    this.hexTile.wrapS = this.hexTile.wrapT = THREE.RepeatWrapping;
    this.hexTile.colorSpace = THREE.SRGBColorSpace;
    this.hexTile.anisotropy = this.renderer.capabilities.getMaxAnisotropy();

    this.resize();
    this.renderer.setAnimationLoop(() => this.render());
  }

  resize() {
    const { clientWidth, clientHeight } = this.canvas;
    this.renderer.setSize(clientWidth, clientHeight, false);
  }

  setLayer(name, sceneName, object) {
    if (this.layers[name]) {
      this.layers[name].removeFromParent();
      dispose(this.layers[name]);
      delete this.layers[name];
    }
    if (object) {
      object.name = name;
      this.layers[name] = object;
      this.scenes[sceneName].add(object);
    }
    this.applyVisibility();
  }

  /** Shows the uploaded mesh and frames the camera on it. */
  setInput(model) {
    this.origin = boxCentre(model.positions);
    const mesh = relativeTo(model, this.origin);
    this.setLayer('inputSurface', 'input', new THREE.Mesh(surfaceGeometry(mesh), surfaceMaterial(0xb9c4cf)));
    this.setLayer('inputWireframe', 'input', edgeLines(mesh, 0x2b3440, 0.35));
    this.setLayer('remeshSurface', 'remesh', null);
    this.setLayer('remeshWireframe', 'remesh', null);
    this.setLayer('singularities', 'remesh', null);
    this.setLayer('dual', 'remesh', null);
    this.setLayer('textured', 'input', null);
    this.irregular = { below: [], above: [] };
    this.frame(this.layers.inputSurface.geometry);
  }

  /** Shows the remesh; `regularValence` is 6 for triangles, 4 for quads. Returns the irregular vertices. */
  setRemesh(model, regularValence) {
    if (!this.layers.inputSurface) this.origin = boxCentre(model.positions);
    const mesh = relativeTo(model, this.origin);
    this.setLayer('remeshSurface', 'remesh', new THREE.Mesh(surfaceGeometry(mesh), surfaceMaterial(0xc9d6c3)));
    this.setLayer('remeshWireframe', 'remesh', edgeLines(mesh, 0x1b2a1b, 0.6));
    this.irregular = irregularVertices(mesh, regularValence);
    const radius = 0.25 * meanEdgeLength(mesh);
    const markers = new THREE.Group();
    markers.add(markerSpheres(mesh, this.irregular.below, radius, kValenceColours.below));
    markers.add(markerSpheres(mesh, this.irregular.above, radius, kValenceColours.above));
    this.setLayer('singularities', 'remesh', markers);
    if (!this.layers.inputSurface) this.frame(this.layers.remeshSurface.geometry);
    return this.irregular;
  }

  /** The hexagonal dual of the remesh, drawn as its polygon edges over the remesh. */
  setDual(mesh) {
    this.setLayer('dual', 'remesh', edgeLines(relativeTo(mesh, this.origin), 0x7a1fa2));
  }

  /** The textured result (input geometry with per-corner texcoords), drawn with the hex tiling. */
  setTextured(mesh) {
    if (!mesh.texcoords) throw new Error('the textured result has no texture coordinates');
    const material = surfaceMaterial(0xffffff);
    material.map = this.hexTile;
    this.setLayer('textured', 'input', new THREE.Mesh(texturedGeometry(relativeTo(mesh, this.origin)), material));
  }

  /** mode: 'input' | 'remesh' | 'side'; flags: wireframe, singularities, dual, texture. */
  setOptions(options) {
    Object.assign(this.options, options);
    this.applyVisibility();
  }

  applyVisibility() {
    const { wireframe, singularities, dual, texture } = this.options;
    const showTexture = texture && !!this.layers.textured;
    const visible = {
      inputSurface: !showTexture,
      inputWireframe: wireframe && !showTexture,
      textured: showTexture,
      remeshSurface: true,
      remeshWireframe: wireframe,
      singularities,
      dual,
    };
    for (const [name, object] of Object.entries(this.layers)) object.visible = visible[name];
  }

  frame(geometry) {
    geometry.computeBoundingSphere();
    const { center, radius } = geometry.boundingSphere;
    this.controls.target.copy(center);
    const distance = radius / Math.sin(THREE.MathUtils.degToRad(this.camera.fov / 2));
    // A three-quarter view: the side and the front of the model are both visible.
    const direction = new THREE.Vector3(0.6, 0.35, 1).normalize();
    this.camera.position.copy(center).addScaledVector(direction, distance * 1.05);
    this.camera.near = distance / 100;
    this.camera.far = distance * 10;
    this.camera.updateProjectionMatrix();
    this.controls.update();
  }

  render() {
    this.controls.update();
    const width = this.canvas.clientWidth;
    const height = this.canvas.clientHeight;
    if (this.canvas.width !== Math.floor(width * this.renderer.getPixelRatio())) this.resize();
    const views =
      this.options.mode === 'side'
        ? [['input', 0, width / 2], ['remesh', width / 2, width / 2]]
        : [[this.options.mode, 0, width]];
    for (const [sceneName, left, viewWidth] of views) {
      this.camera.aspect = viewWidth / height;
      this.camera.updateProjectionMatrix();
      this.renderer.setViewport(left, 0, viewWidth, height);
      this.renderer.setScissor(left, 0, viewWidth, height);
      this.renderer.render(this.scenes[sceneName], this.camera);
    }
  }
}
