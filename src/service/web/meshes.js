// A preview of the mesh the user chose, read in the browser by three.js's loaders (and a few
// lines for OFF, which three.js does not read). Only a picture: the service's check, on the
// same bytes, is the verdict.
import * as THREE from 'three';
import { ThreeMFLoader } from 'three/examples/jsm/loaders/3MFLoader.js';
import { OBJLoader } from 'three/examples/jsm/loaders/OBJLoader.js';
import { PLYLoader } from 'three/examples/jsm/loaders/PLYLoader.js';
import { STLLoader } from 'three/examples/jsm/loaders/STLLoader.js';

async function gunzip(buffer) {
  const stream = new Blob([buffer]).stream().pipeThrough(new DecompressionStream('gzip'));
  return new Response(stream).arrayBuffer();
}

// OFF: "OFF" (or COFF, NOFF, ...), counts, vertex lines, then polygons as fans.
function parseOff(text) {
  const lines = text
    .split('\n')
    .map((line) => line.replace(/#.*/, '').trim())
    .filter((line) => line.length > 0);
  let header = lines.shift() ?? '';
  if (!/OFF$/i.test(header.split(/\s+/)[0])) throw new Error('not an OFF file');
  const rest = header.split(/\s+/).slice(1);
  const counts = (rest.length >= 2 ? rest : lines.shift().split(/\s+/)).map(Number);
  const [vertexCount, faceCount] = counts;
  const points = [];
  for (let i = 0; i < vertexCount; ++i) points.push(lines[i].split(/\s+/).slice(0, 3).map(Number));
  const positions = [];
  for (let f = 0; f < faceCount; ++f) {
    const numbers = lines[vertexCount + f].split(/\s+/).map(Number);
    const n = numbers[0];
    for (let k = 2; k < n; ++k)
      for (const index of [numbers[1], numbers[k], numbers[k + 1]]) positions.push(...points[index]);
  }
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.Float32BufferAttribute(positions, 3));
  return geometry;
}

// Every triangle of an object tree (OBJ and 3MF loaders give groups) in world coordinates.
function mergeTree(root) {
  root.updateMatrixWorld(true);
  const positions = [];
  const v = new THREE.Vector3();
  root.traverse((object) => {
    if (!object.isMesh) return;
    const geometry = object.geometry.index ? object.geometry.toNonIndexed() : object.geometry;
    const attribute = geometry.getAttribute('position');
    for (let i = 0; i < attribute.count; ++i) {
      v.fromBufferAttribute(attribute, i).applyMatrix4(object.matrixWorld);
      positions.push(v.x, v.y, v.z);
    }
  });
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.Float32BufferAttribute(positions, 3));
  return geometry;
}

/// A BufferGeometry of a mesh file's triangles, from its name's extension (".gz" allowed).
export async function readMeshFile(name, buffer) {
  let lower = name.toLowerCase();
  if (lower.endsWith('.gz')) {
    buffer = await gunzip(buffer);
    lower = lower.slice(0, -3);
  }
  const extension = lower.slice(lower.lastIndexOf('.') + 1);
  const text = () => new TextDecoder().decode(buffer);
  switch (extension) {
    case 'stl':
      return new STLLoader().parse(buffer);
    case 'ply':
      return new PLYLoader().parse(buffer);
    case 'obj':
      return mergeTree(new OBJLoader().parse(text()));
    case '3mf':
      return mergeTree(new ThreeMFLoader().parse(buffer));
    case 'off':
      return parseOff(text());
    default:
      throw new Error(`no preview for .${extension} files`);
  }
}
