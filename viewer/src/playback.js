// Machine playback: the program's frames (each G-code block's end pose as the controller reads it,
// data.playback) move the machine. The head is drawn as the nozzle's cone and cylinder; on a
// table-table machine the table turns the part under a vertical head (LinuxCNC's trt-kins), on a
// head-head machine the head tilts and turns over the fixed part (5axiskins), on a 3-axis machine
// the head only moves. Between frames the joints are interpolated linearly, as the controller does.
import {
  BoxGeometry, BufferGeometry, Color, CylinderGeometry, Group, Line, LineBasicMaterial, Matrix4, Mesh, MeshStandardMaterial, Vector3,
} from 'three';
import { buildArm } from './robot.js';

const DEG = Math.PI / 180;

// The frame index I with time[i] <= t < time[i + 1] (the last frame at or after the end).
export function frameAt(time, t) {
  let lo = 0, hi = time.length - 1;
  if (hi < 0) return -1;
  if (t >= time[hi]) return hi;
  while (lo < hi) {
    const mid = (lo + hi + 1) >> 1;
    if (time[mid] <= t) lo = mid; else hi = mid - 1;
  }
  return lo;
}

// The part's placement in the machine frame for joints J (x y z tilt c, degrees) on a table-table
// machine: machine(P) = rp + d + Rt(−s·T)·(Rz(−s·C)·(P − rp) − d) (kinematics.h).
function tableMatrix(pb, j, out) {
  const [rx, ry, rz] = pb.rotPoint, [dx, dy, dz] = pb.offset;
  const t = -pb.sense * j[3] * DEG, c = -pb.sense * j[4] * DEG;
  const tilt = pb.kinematics.startsWith('xyzac') ? new Matrix4().makeRotationX(t) : new Matrix4().makeRotationY(t);
  out.makeTranslation(rx + dx, ry + dy, rz + dz)
    .multiply(tilt)
    .multiply(new Matrix4().makeTranslation(-dx, -dy, -dz))
    .multiply(new Matrix4().makeRotationZ(c))
    .multiply(new Matrix4().makeTranslation(-rx, -ry, -rz));
  return out;
}

// The head-head tool axis at tilt T and turn C (degrees): (−sinB cosC, −sinB sinC, cosB) for B/C,
// Rz(C)·Rx(A)·ẑ for A/C.
function headAxis(pb, tDeg, cDeg) {
  const t = tDeg * DEG, c = cDeg * DEG;
  if (pb.kinematics.startsWith('xyzac')) return new Vector3(Math.sin(t) * Math.sin(c), -Math.sin(t) * Math.cos(c), Math.cos(t));
  return new Vector3(-Math.sin(t) * Math.cos(c), -Math.sin(t) * Math.sin(c), Math.cos(t));
}

function buildHead(nozzle) {
  const head = new Group();
  const material = new MeshStandardMaterial({ color: new Color(0x5b6773), metalness: 0.3, roughness: 0.5 });
  const coneTop = nozzle.coneHeight * Math.tan(nozzle.halfAngle * DEG);
  // Three's cone and cylinder stand on Y: turned to stand on Z, the tip at the origin.
  const cone = new Mesh(new CylinderGeometry(coneTop, 0, nozzle.coneHeight, 32, 1), material);
  cone.rotation.x = Math.PI / 2;
  cone.position.z = nozzle.coneHeight / 2;
  head.add(cone);
  if (nozzle.cylinderHeight > 0) {
    const body = new Mesh(new CylinderGeometry(nozzle.cylinderRadius, nozzle.cylinderRadius, nozzle.cylinderHeight, 32, 1), material);
    body.rotation.x = Math.PI / 2;
    body.position.z = nozzle.coneHeight + nozzle.cylinderHeight / 2;
    head.add(body);
  }
  head.name = 'head';
  return { head, material };
}

function buildTable(pb) {
  const group = new Group();
  // The table's rim as a line: it is large next to most parts, and a filled, blended disc over the
  // whole window would double the cost of a frame in software WebGL.
  const rim = [];
  for (let k = 0; k <= 96; k++) {
    const a = (2 * Math.PI * k) / 96;
    rim.push(new Vector3(pb.table.centre[0] + pb.table.radius * Math.cos(a), pb.table.centre[1] + pb.table.radius * Math.sin(a), pb.table.top));
  }
  group.add(new Line(new BufferGeometry().setFromPoints(rim), new LineBasicMaterial({ color: new Color(0x7b8794) })));
  const [x0, x1] = pb.plate.x, [y0, y1] = pb.plate.y;
  if (Number.isFinite(x0) && Number.isFinite(x1) && Number.isFinite(y0) && Number.isFinite(y1) && x1 > x0 && y1 > y0) {
    const plate = new Mesh(new BoxGeometry(x1 - x0, y1 - y0, Math.max(pb.plate.thickness, 0.01)),
      new MeshStandardMaterial({ color: new Color(0xaab4be) }));
    plate.position.set((x0 + x1) / 2, (y0 + y1) / 2, pb.plate.top - pb.plate.thickness / 2 - 0.02);
    group.add(plate);
  }
  group.name = 'table';
  return group;
}

// PB: data.playback. PART: the group holding everything fixed to the part (moved on a table-table
// machine). SCENE: where the head and the table go. COLLISIONS: data.collisions (their lines).
// ON_LAYER(k): called when the current frame's layer changes. Returns the controls' model.
export function buildPlayback(pb, part, scene, collisions, onLayer) {
  const { head, material } = buildHead(pb.nozzle);
  const table = buildTable(pb);
  part.add(table); // the table turns with the part on a table-table machine
  head.visible = false;
  table.visible = false;
  scene.add(head);
  part.matrixAutoUpdate = false;
  const turnsTable = pb.kinematics.endsWith('-trt');
  const tiltsHead = pb.kinematics.endsWith('-head');
  const collisionLines = collisions.map((c) => c.line).filter((l) => l > 0).sort((a, b) => a - b);
  const normal = new Color(0x5b6773), struck = new Color(0xe02020);
  const j = new Float64Array(5);
  const q = [0, 0, 0, 0, 0, 0];
  const m = new Matrix4();
  // A robot cell: the arm carries the head; its joints are interpolated as the positioner's.
  const arm = pb.robot ? buildArm(pb.robot) : null;
  if (arm) {
    arm.group.visible = false;
    scene.add(arm.group);
  }
  let active = false, current = -1, lastLayer = null;

  // Joints at time t: the frame ending at or before t and the next, interpolated.
  function jointsAt(t) {
    const i = frameAt(pb.time, t);
    const k = Math.min(pb.n - 1, i + 1);
    const t0 = pb.time[i], t1 = pb.time[k];
    const u = k === i || t1 <= t0 ? 0 : Math.min(1, Math.max(0, (t - t0) / (t1 - t0)));
    for (let a = 0; a < 5; a++) j[a] = pb.joints[5 * i + a] + (pb.joints[5 * k + a] - pb.joints[5 * i + a]) * u;
    if (arm) for (let a = 0; a < 6; a++) q[a] = pb.robot.arm[6 * i + a] + (pb.robot.arm[6 * k + a] - pb.robot.arm[6 * i + a]) * u;
    return u > 0 ? k : i; // the block being run
  }

  // A collision whose line lies in the blocks from frame A (exclusive) to B (inclusive).
  function strikesBetween(a, b) {
    if (!collisionLines.length || b < 0) return null;
    const lo = a >= 0 ? pb.line[a] : 0, hi = pb.line[b];
    for (const l of collisionLines) if (l > lo && l <= hi) return l;
    return null;
  }

  function show(t) {
    if (pb.n === 0) return null;
    const previous = current;
    current = jointsAt(Math.max(0, Math.min(pb.duration, t)));
    let armTcp = null;
    if (turnsTable) {
      part.matrix.copy(tableMatrix(pb, j, m));
      head.position.set(j[0], j[1], j[2]);
      head.quaternion.identity();
      if (arm) {
        // The torch where the arm holds it: at its TCP, along the TCP's −z (the tool axis).
        const pose = arm.update(q);
        armTcp = pose.points[5];
        head.position.copy(armTcp);
        head.quaternion.setFromUnitVectors(new Vector3(0, 0, 1), new Vector3(0, 0, -1).applyMatrix4(pose.tcpRotation).normalize());
      }
    } else if (tiltsHead) {
      part.matrix.identity();
      const axis = headAxis(pb, j[3], j[4]);
      head.position.set(j[0], j[1], j[2]).addScaledVector(new Vector3(0, 0, 1).sub(axis), pb.pivotLength);
      head.quaternion.setFromUnitVectors(new Vector3(0, 0, 1), axis);
    } else {
      part.matrix.identity();
      head.position.set(j[0], j[1], j[2]);
      head.quaternion.identity();
    }
    part.matrixWorldNeedsUpdate = true;
    // Played forwards: the blocks run since the last picture; else the block being run.
    const hit = strikesBetween(previous >= 0 && previous < current ? previous : current - 1, current);
    material.color.copy(hit !== null ? struck : normal);
    const layer = pb.layer[current];
    if (layer >= 0 && layer !== lastLayer) {
      lastLayer = layer;
      onLayer(layer);
    }
    return { frame: current, line: pb.line[current], layer, processOn: (pb.flags[current] & 1) !== 0, rapid: (pb.flags[current] & 2) !== 0,
      joints: Array.from(j), struck: hit, arm: arm ? q.slice() : null, armTcp: armTcp ? armTcp.toArray() : null };
  }

  function setActive(on) {
    active = on;
    head.visible = on;
    table.visible = on;
    if (arm) arm.group.visible = on;
    if (!on) {
      part.matrix.identity();
      part.matrixWorldNeedsUpdate = true;
      lastLayer = null;
    }
  }

  return { show, setActive, isActive: () => active, duration: pb.duration, frames: pb.n, totalFrames: pb.totalFrames };
}
