// The 3D view: one body and one garment, lit for judging fit rather than for looks.
// Renders on demand (camera moves, new geometry, new colours) instead of every frame: the view
// is still most of the time, and a still page keeps a shopper's laptop cool.
import {
  BufferAttribute,
  Color,
  DirectionalLight,
  DoubleSide,
  HemisphereLight,
  Mesh,
  MeshStandardMaterial,
  PerspectiveCamera,
  Raycaster,
  Scene,
  SphereGeometry,
  Vector2,
  Vector3,
  WebGLRenderer,
} from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

export const BACKGROUND = '#eef1f5';
const SKIN = '#d9a58a';
const FOV_DEG = 30;
// A pointer that moves less than this between press and release clicked (rather than dragged).
const CLICK_SLOP_PX = 5;

export class Viewer {
  constructor(container, { onPick }) {
    this.container = container;
    // preserveDrawingBuffer: screenshots and pixel reads of the canvas (the tests) see the
    // last frame even between renders.
    this.renderer = new WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
    container.append(this.renderer.domElement);

    this.scene = new Scene();
    this.scene.background = new Color(BACKGROUND);
    this.camera = new PerspectiveCamera(FOV_DEG, 1, 0.05, 50);
    this.camera.position.set(0, 1, 4);

    // Soft sky/ground fill plus a key light from the front, high and to the left, and a weaker
    // one from behind right, so folds read as shading without hiding the map colours.
    this.scene.add(new HemisphereLight(0xffffff, 0xb8b0a8, 1.4));
    const key = new DirectionalLight(0xffffff, 2.0);
    key.position.set(-1.5, 3, 4);
    this.scene.add(key);
    const rim = new DirectionalLight(0xffffff, 0.8);
    rim.position.set(2, 2, -3);
    this.scene.add(rim);

    this.bodyMaterial = new MeshStandardMaterial({ color: SKIN, roughness: 0.75 });
    // DoubleSide: open garments show their inside at the hem and the neckline. The polygon
    // offset keeps cloth that lies on the skin (ease near 0) from flickering through it.
    this.garmentMaterial = new MeshStandardMaterial({
      vertexColors: true,
      side: DoubleSide,
      roughness: 0.9,
      polygonOffset: true,
      polygonOffsetFactor: -1,
      polygonOffsetUnits: -1,
    });
    this.body = null;
    this.garment = null;
    this.marker = new Mesh(
      new SphereGeometry(0.009, 16, 12),
      new MeshStandardMaterial({ color: '#000000', roughness: 0.4 }),
    );
    this.marker.visible = false;
    this.scene.add(this.marker);

    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.minDistance = 0.4;
    this.controls.maxDistance = 8;
    this.controls.addEventListener('change', () => this.render());

    this.raycaster = new Raycaster();
    this.listenForClicks(onPick);
    new ResizeObserver(() => this.resize()).observe(container);
    this.resize();
  }

  resize() {
    const width = Math.max(1, this.container.clientWidth);
    const height = Math.max(1, this.container.clientHeight);
    this.renderer.setSize(width, height);
    this.camera.aspect = width / height;
    this.camera.updateProjectionMatrix();
    this.render();
  }

  render() {
    this.renderer.render(this.scene, this.camera);
  }

  setBody(geometry) {
    this.clearBody();
    this.body = new Mesh(geometry, this.bodyMaterial);
    this.scene.add(this.body);
    this.frame();
  }

  clearBody() {
    this.clearGarment();
    if (!this.body) return;
    this.scene.remove(this.body);
    this.body.geometry.dispose();
    this.body = null;
    this.render();
  }

  // geometry is owned by the caller (one per size, kept while the shopper compares sizes).
  setGarment(geometry, colors) {
    if (!this.garment) {
      this.garment = new Mesh(geometry, this.garmentMaterial);
      this.scene.add(this.garment);
    }
    this.garment.geometry = geometry;
    this.setGarmentColors(colors);
  }

  setGarmentColors(colors) {
    this.garment.geometry.setAttribute('color', new BufferAttribute(colors, 3));
    this.render();
  }

  clearGarment() {
    this.hideMarker();
    if (!this.garment) return;
    this.scene.remove(this.garment);
    this.garment = null;
    this.render();
  }

  // Front-on (bodies face +z, +y up), the whole body in view with a little air around it.
  frame() {
    const box = this.body.geometry.boundingBox;
    const center = box.getCenter(new Vector3());
    const size = box.getSize(new Vector3());
    const halfFov = (FOV_DEG * Math.PI) / 360;
    const fitHeight = (size.y * 0.56) / Math.tan(halfFov);
    const fitWidth = (size.x * 0.56) / (Math.tan(halfFov) * this.camera.aspect);
    const distance = Math.max(fitHeight, fitWidth) + size.z / 2;
    this.camera.position.set(center.x, center.y, center.z + distance);
    this.controls.target.copy(center);
    this.controls.update();
    this.render();
  }

  showMarker(vertex) {
    const position = this.garment.geometry.getAttribute('position');
    this.marker.position.fromBufferAttribute(position, vertex);
    this.marker.visible = true;
    this.render();
  }

  hideMarker() {
    this.marker.visible = false;
  }

  // The garment vertex nearest to where a ray through a client (CSS) pixel first meets the
  // garment, or null.
  pickGarmentVertex(clientX, clientY) {
    if (!this.garment) return null;
    const rect = this.renderer.domElement.getBoundingClientRect();
    const ndc = new Vector2(((clientX - rect.left) / rect.width) * 2 - 1, -((clientY - rect.top) / rect.height) * 2 + 1);
    this.raycaster.setFromCamera(ndc, this.camera);
    const targets = this.body ? [this.garment, this.body] : [this.garment];
    const [hit] = this.raycaster.intersectObjects(targets, false);
    if (!hit || hit.object !== this.garment) return null;
    const position = this.garment.geometry.getAttribute('position');
    const corner = new Vector3();
    let best = null;
    let bestDistance = Infinity;
    for (const v of [hit.face.a, hit.face.b, hit.face.c]) {
      const d = corner.fromBufferAttribute(position, v).distanceToSquared(hit.point);
      if (d < bestDistance) {
        bestDistance = d;
        best = v;
      }
    }
    return best;
  }

  // Where a garment vertex lies on the page, in client (CSS) pixels.
  garmentVertexClientPoint(vertex) {
    const point = new Vector3().fromBufferAttribute(this.garment.geometry.getAttribute('position'), vertex);
    const ndc = point.project(this.camera);
    const rect = this.renderer.domElement.getBoundingClientRect();
    return { x: rect.left + ((ndc.x + 1) / 2) * rect.width, y: rect.top + ((1 - ndc.y) / 2) * rect.height };
  }

  listenForClicks(onPick) {
    const canvas = this.renderer.domElement;
    let down = null;
    canvas.addEventListener('pointerdown', (e) => {
      down = { x: e.clientX, y: e.clientY };
    });
    canvas.addEventListener('pointerup', (e) => {
      if (!down || Math.hypot(e.clientX - down.x, e.clientY - down.y) > CLICK_SLOP_PX) return;
      down = null;
      onPick(this.pickGarmentVertex(e.clientX, e.clientY));
    });
  }
}
