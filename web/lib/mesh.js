// Positions and faces as the API sends them (proto/fitbase/v1/mesh.proto) into three.js
// geometry. Topology travels once; every body and fitted garment then comes as positions only.
import { BufferAttribute, BufferGeometry } from 'three';
import { DRACOLoader } from 'three/addons/loaders/DRACOLoader.js';

// The decoder ships inside the three npm package, served by fitbase itself: no CDN.
const draco = new DRACOLoader().setDecoderPath('/vendor/three/examples/jsm/libs/draco/');

// The protobuf JSON mapping lets a printer use either base64 alphabet; atob knows one.
function base64ToArrayBuffer(base64) {
  const binary = atob(base64.replace(/-/g, '+').replace(/_/g, '/'));
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; i++) bytes[i] = binary.charCodeAt(i);
  return bytes.buffer;
}

function decodeDraco(buffer) {
  return new Promise((resolve, reject) => draco.parse(buffer, resolve, reject));
}

// EncodedPositions → Float32Array of 3·V floats in vertex order. wireOrder (garments only) says
// which vertex each Draco point is: the server sends garments in a spatial order that
// compresses better. Raw positions are always in vertex order.
export async function decodePositions(encoded, wireOrder = null) {
  const count = encoded?.vertex_count ?? 0;
  if (encoded?.raw) {
    // Number() also reads the JSON mapping's "NaN"/"Infinity" strings.
    const xyz = Float32Array.from(encoded.raw.xyz ?? [], Number);
    if (xyz.length !== 3 * count) {
      throw new Error(`Positions hold ${xyz.length} numbers for ${count} vertices.`);
    }
    return xyz;
  }
  if (!encoded?.draco) throw new Error('Positions are neither raw nor Draco-encoded.');

  const geometry = await decodeDraco(base64ToArrayBuffer(encoded.draco.data ?? ''));
  const points = geometry.getAttribute('position');
  geometry.dispose();
  if (!points || points.count !== count) {
    throw new Error(`Draco positions hold ${points?.count ?? 0} points for ${count} vertices.`);
  }
  const order = wireOrder && wireOrder.length ? wireOrder : null;
  if (order && order.length !== count) {
    throw new Error(`The garment's wire order lists ${order.length} of its ${count} vertices.`);
  }
  const xyz = new Float32Array(3 * count);
  for (let i = 0; i < count; i++) {
    const v = order ? order[i] : i;
    xyz[3 * v] = points.getX(i);
    xyz[3 * v + 1] = points.getY(i);
    xyz[3 * v + 2] = points.getZ(i);
  }
  return xyz;
}

// Mesh (polygons in face_sizes / face_indices) → triangle index, each polygon as a fan: the
// faces of hm08 and the MakeHuman garments are quads, convex enough for fans.
export function triangulate(mesh) {
  const sizes = mesh?.face_sizes ?? [];
  const corners = mesh?.face_indices ?? [];
  let triangleCount = 0;
  for (const n of sizes) triangleCount += Math.max(0, n - 2);

  const index = new Uint32Array(3 * triangleCount);
  let k = 0;
  let t = 0;
  for (const n of sizes) {
    if (k + n > corners.length) throw new Error('The faces list fewer corners than their sizes say.');
    for (let j = 1; j + 1 < n; j++) {
      index[t++] = corners[k];
      index[t++] = corners[k + j];
      index[t++] = corners[k + j + 1];
    }
    k += n;
  }
  return index;
}

export function buildGeometry(positions, triangles) {
  const vertexCount = positions.length / 3;
  for (const v of triangles) {
    if (v >= vertexCount) throw new Error(`A face names vertex ${v} of a ${vertexCount}-vertex mesh.`);
  }
  const geometry = new BufferGeometry();
  geometry.setAttribute('position', new BufferAttribute(positions, 3));
  geometry.setIndex(new BufferAttribute(triangles, 1));
  geometry.computeVertexNormals();
  geometry.computeBoundingBox();
  geometry.computeBoundingSphere();
  return geometry;
}
