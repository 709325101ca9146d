// The robot of a robot cell's playback (post abb-rapid), drawn as simple bodies: the base, the
// lower and upper arms, the wrist and the torch, posed from the controller's joints q1..q6 by the
// ortho-parallel arm's forward kinematics (machine/robot.h: θi = signi·qi + zeroi; wrist centre
// Rz(θ1)·(c2·sinθ2 + k·sin(θ2+θ3+ψ) + a1, b, 0) + (0, 0, c1 + c2·cosθ2 + k·cos(θ2+θ3+ψ)),
// k = √(a2² + c3²), ψ = atan2(a2, c3); flange orientation Rz(θ1)·Ry(θ2+θ3)·Rz(θ4)·Ry(θ5)·Rz(θ6),
// the flange c4 along its z; the TCP the tooldata's frame on the flange). Everything is in the
// playback's frame (the positioner's fixed frame): the arm's base is placed there by ROBOT.base.
import { Color, CylinderGeometry, Group, Matrix4, Mesh, MeshStandardMaterial, Quaternion, SphereGeometry, Vector3 } from 'three';

const DEG = Math.PI / 180;

// The arm's points (base, shoulder, elbow, wrist centre, flange, TCP) and the TCP's rotation, in
// the playback's frame, for joints Q (degrees).
export function armPose(robot, q) {
  const [a1, a2, b, c1, c2, c3, c4] = robot.geometry;
  const th = q.map((v, i) => (robot.sign[i] * v + robot.zero[i]) * DEG);
  const k = Math.hypot(a2, c3), psi = Math.atan2(a2, c3);
  const r1 = new Matrix4().makeRotationZ(th[0]);
  const inBase = (x, y, z) => new Vector3(x, y, 0).applyMatrix4(r1).add(new Vector3(0, 0, z));
  const shoulder = inBase(a1, b, c1);
  const elbow = inBase(a1 + c2 * Math.sin(th[1]), b, c1 + c2 * Math.cos(th[1]));
  const wrist = inBase(c2 * Math.sin(th[1]) + k * Math.sin(th[1] + th[2] + psi) + a1, b, c1 + c2 * Math.cos(th[1]) + k * Math.cos(th[1] + th[2] + psi));
  const rot = new Matrix4().makeRotationZ(th[0]).multiply(new Matrix4().makeRotationY(th[1] + th[2])).multiply(new Matrix4().makeRotationZ(th[3]))
    .multiply(new Matrix4().makeRotationY(th[4])).multiply(new Matrix4().makeRotationZ(th[5]));
  const flange = wrist.clone().add(new Vector3(0, 0, c4).applyMatrix4(rot));
  const [tx, ty, tz, qw, qx, qy, qz] = robot.tcp;
  const tcp = flange.clone().add(new Vector3(tx, ty, tz).applyMatrix4(rot));
  const tcpRot = new Matrix4().extractRotation(rot).multiply(new Matrix4().makeRotationFromQuaternion(new Quaternion(qx, qy, qz, qw).normalize()));
  // The base frame in the playback's frame: a turn about Z and a translation.
  const [bx, by, bz, brz] = robot.base;
  const place = new Matrix4().makeRotationZ(brz * DEG).setPosition(bx, by, bz);
  const points = [new Vector3(0, 0, 0), shoulder, elbow, wrist, flange, tcp].map((p) => p.applyMatrix4(place));
  return { points, tcpRotation: new Matrix4().extractRotation(place).multiply(tcpRot) };
}

// Cylinders between consecutive arm points (the last, flange to TCP, is the torch) and spheres
// at the joints; update(q) poses them and returns armPose's result.
export function buildArm(robot) {
  const group = new Group();
  group.name = 'robot';
  const material = new MeshStandardMaterial({ color: new Color(0xe0a030), metalness: 0.2, roughness: 0.6 });
  const torchMaterial = new MeshStandardMaterial({ color: new Color(0x5b6773), metalness: 0.3, roughness: 0.5 });
  const reach = Math.max(100, robot.geometry[4] + Math.hypot(robot.geometry[1], robot.geometry[5]));
  // Base, lower arm, upper arm and wrist in proportion to the arm; the torch (flange to TCP) thin,
  // as the nozzle drawn at its tip.
  const radii = [0.09, 0.07, 0.06, 0.045].map((f) => f * reach * 0.5).concat([Math.max(2, 0.01 * reach)]);
  const links = radii.map((r, i) => {
    const link = new Mesh(new CylinderGeometry(r, r, 1, 20, 1), i === 4 ? torchMaterial : material);
    group.add(link);
    return link;
  });
  const joints = radii.slice(0, 4).map((r) => {
    const s = new Mesh(new SphereGeometry(r * 1.25, 16, 12), material);
    group.add(s);
    return s;
  });
  const up = new Vector3(0, 1, 0);
  function update(q) {
    const pose = armPose(robot, q);
    const p = pose.points;
    for (let i = 0; i < links.length; i++) {
      const d = p[i + 1].clone().sub(p[i]);
      const len = d.length();
      links[i].visible = len > 1e-6;
      if (!links[i].visible) continue;
      links[i].position.copy(p[i]).addScaledVector(d, 0.5);
      links[i].quaternion.setFromUnitVectors(up, d.divideScalar(len));
      links[i].scale.set(1, len, 1);
    }
    for (let i = 0; i < joints.length; i++) joints[i].position.copy(p[i + 1]);
    return pose;
  }
  return { group, update };
}
