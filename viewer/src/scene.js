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

  let pending = false;
  const render = () => {
    pending = false;
    renderer.render(scene, camera);
  };
  const requestRender = () => {
    if (!pending) {
      pending = true;
      requestAnimationFrame(render);
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
  function frame(box) {
    if (box.isEmpty()) box = new Box3(new Vector3(-10, -10, 0), new Vector3(10, 10, 10));
    const center = box.getCenter(new Vector3());
    const size = box.getSize(new Vector3());
    const diag = Math.max(size.length(), 1e-3);
    const dir = new Vector3(1.0, -1.35, 0.9).normalize();
    const fov = (camera.fov * Math.PI) / 180;
    const dist = (0.5 * diag) / Math.sin(fov / 2) * 1.05;
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
