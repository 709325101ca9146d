// Renderer, camera, controls, lights, table grid and axes; renders on demand.
import {
  AxesHelper, Box3, Color, DirectionalLight, GridHelper, HemisphereLight, PerspectiveCamera, Scene, Vector3,
  WebGLRenderer,
} from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import { BACKGROUND, COLORS } from './colors.js';

function niceStep(x) {
  const p = Math.pow(10, Math.floor(Math.log10(x)));
  const m = x / p;
  return (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10) * p;
}

// Grows box by the points of a flat xyz array.
export function expandBox(box, xyz) {
  const n = xyz.length;
  let x0 = box.min.x, y0 = box.min.y, z0 = box.min.z, x1 = box.max.x, y1 = box.max.y, z1 = box.max.z;
  for (let i = 0; i < n; i += 3) {
    const x = xyz[i], y = xyz[i + 1], z = xyz[i + 2];
    if (!(Number.isFinite(x) && Number.isFinite(y) && Number.isFinite(z))) continue;
    if (x < x0) x0 = x; if (x > x1) x1 = x;
    if (y < y0) y0 = y; if (y > y1) y1 = y;
    if (z < z0) z0 = z; if (z > z1) z1 = z;
  }
  box.min.set(x0, y0, z0);
  box.max.set(x1, y1, z1);
  return box;
}

export function createView(container) {
  const canvas = document.createElement('canvas');
  canvas.className = 'px-canvas';
  container.appendChild(canvas);

  let renderer;
  try {
    renderer = new WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
  } catch (e) {
    throw new Error(`WebGL is not available in this browser (${e.message})`);
  }
  renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
  renderer.setSize(window.innerWidth, window.innerHeight, false);
  renderer.setClearColor(new Color(BACKGROUND), 1);

  const scene = new Scene();
  const camera = new PerspectiveCamera(40, window.innerWidth / Math.max(1, window.innerHeight), 0.1, 1e5);
  camera.up.set(0, 0, 1);
  scene.add(camera);
  scene.add(new HemisphereLight(0xffffff, 0x8090a0, 1.6));
  const key = new DirectionalLight(0xffffff, 1.6);
  key.position.set(0.5, 0.3, 1); // relative to the camera: lighting follows the view
  camera.add(key);

  const controls = new OrbitControls(camera, canvas);
  controls.enableDamping = false;
  controls.screenSpacePanning = true;

  // At most one frame per animation frame; a synchronous render() cancels the pending one
  // (a frame of a million segments is slow on software GL).
  let pending = false;
  const render = () => {
    pending = false;
    renderer.render(scene, camera);
  };
  const onFrame = () => {
    if (pending) render();
  };
  const requestRender = () => {
    if (!pending) {
      pending = true;
      requestAnimationFrame(onFrame);
    }
  };
  controls.addEventListener('change', requestRender);
  window.addEventListener('resize', () => {
    renderer.setSize(window.innerWidth, window.innerHeight, false);
    camera.aspect = window.innerWidth / Math.max(1, window.innerHeight);
    camera.updateProjectionMatrix();
    requestRender();
  });

  // Frames the camera on box (Z up), adds the table grid at z = 0 and the axes helper.
  // points: optional flat xyz arrays of the shown geometry, to fit tighter than the box corners.
  function frame(box, points = []) {
    if (box.isEmpty()) box = new Box3(new Vector3(-10, -10, 0), new Vector3(10, 10, 10));
    const center = box.getCenter(new Vector3());
    const size = box.getSize(new Vector3());
    const diag = Math.max(size.length(), 1e-3);
    // View from the front-right, above; distance so that all 8 box corners fit the free part of the
    // window (between the side panels when the window is wide).
    const dir = new Vector3(1.0, -1.35, 0.9).normalize();
    const right = new Vector3().crossVectors(new Vector3(0, 0, 1), dir).normalize();
    const up = new Vector3().crossVectors(dir, right);
    const W = window.innerWidth, H = Math.max(1, window.innerHeight);
    const freeW = W >= 900 ? W - 2 * 310 : W;
    const tanV = Math.tan((camera.fov * Math.PI) / 360) * 0.92;
    const tanH = tanV * (freeW / H);
    let dist = 0;
    const c = new Vector3();
    const fit = () => {
      c.sub(center);
      const depth = c.dot(dir); // towards the camera
      dist = Math.max(dist, depth + Math.abs(c.dot(right)) / tanH, depth + Math.abs(c.dot(up)) / tanV);
    };
    const total = points.reduce((n, a) => n + a.length / 3, 0);
    if (total > 0) {
      const stride = Math.max(1, Math.floor(total / 50000)); // a sample is enough
      for (const a of points) {
        for (let i = 0; i < a.length; i += 3 * stride) {
          if (Number.isFinite(a[i]) && Number.isFinite(a[i + 1]) && Number.isFinite(a[i + 2])) {
            c.set(a[i], a[i + 1], a[i + 2]);
            fit();
          }
        }
      }
    } else {
      for (let k = 0; k < 8; k++) {
        c.set(k & 1 ? box.max.x : box.min.x, k & 2 ? box.max.y : box.min.y, k & 4 ? box.max.z : box.min.z);
        fit();
      }
    }
    dist = Math.max(dist, diag * 0.3);
    camera.position.copy(center).addScaledVector(dir, dist);
    camera.near = Math.max(dist / 1000, 1e-3);
    camera.far = dist * 100;
    camera.updateProjectionMatrix();
    controls.target.copy(center);
    controls.update();

    const extent = Math.max(size.x, size.y, diag * 0.5) * 1.6;
    const step = niceStep(extent / 20);
    const divisions = Math.max(2, Math.ceil(extent / step / 2) * 2);
    const grid = new GridHelper(divisions * step, divisions, new Color(COLORS.gridCenter), new Color(COLORS.grid));
    grid.rotation.x = Math.PI / 2; // GridHelper lies in XZ; the table plane is XY
    grid.position.set(Math.round(center.x / step) * step, Math.round(center.y / step) * step, 0);
    grid.renderOrder = -1;
    scene.add(grid);
    const axes = new AxesHelper(niceStep(diag * 0.2));
    axes.renderOrder = 1;
    scene.add(axes);
    return { center, size, diag, gridStep: step };
  }

  return { canvas, renderer, scene, camera, controls, render, requestRender, frame };
}
