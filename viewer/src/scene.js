// The three.js objects of a run: one group per body (its pose from bodies.csv), the shapes in the
// body frame, joint markers, contact points and force arrows, the ground, and the automatic camera
// (the same choice as src/viz/camera.cpp's chooseCamera for pictures).
import {
  BoxGeometry,
  BufferAttribute,
  BufferGeometry,
  CapsuleGeometry,
  Color,
  ConeGeometry,
  CylinderGeometry,
  DoubleSide,
  DynamicDrawUsage,
  EdgesGeometry,
  Group,
  InstancedMesh,
  LineBasicMaterial,
  LineSegments,
  Matrix4,
  Mesh,
  MeshBasicMaterial,
  MeshStandardMaterial,
  PlaneGeometry,
  Quaternion,
  SphereGeometry,
  Vector3,
} from 'three';

const PALETTE = [0x4e79a7, 0xf28e2b, 0xe15759, 0x76b7b2, 0x59a14f, 0xedc948, 0xb07aa1, 0xff9da7,
  0x9c755f, 0x5b8fd6];
const STATIC_COLOR = 0xaab3be;
const JOINT_COLOR = 0xff7a00;
const CONTACT_COLOR = 0xd7263d;

const toQuat = (q) => new Quaternion(q[1], q[2], q[3], q[0]);  // [w, x, y, z]
const toVec = (v) => new Vector3(v[0], v[1], v[2]);

function shapeRadius(s) {
  switch (s.type) {
    case 'sphere': return s.radius;
    case 'box': return Math.hypot(...s.size) / 2;
    case 'capsule': return s.length / 2 + s.radius;
    case 'cylinder': return Math.hypot(s.length / 2, s.radius);
    case 'ellipsoid': return Math.max(...s.radii);
    case 'convex':
    case 'mesh': return Math.max(0, ...(s.vertices || []).map((p) => Math.hypot(...p)));
    default: return 0;
  }
}

export function bodyPose(run, f, b, position, quaternion) {
  const o = f * run.nb + b;
  position.set(run.pos[o * 3], run.pos[o * 3 + 1], run.pos[o * 3 + 2]);
  quaternion.set(run.quat[o * 4 + 1], run.quat[o * 4 + 2], run.quat[o * 4 + 3], run.quat[o * 4]);
}

/// Bounds of all bounded shapes over all frames (planes excluded), as runBounds in camera.cpp.
export function runBounds(run) {
  const min = new Vector3(Infinity, Infinity, Infinity);
  const max = new Vector3(-Infinity, -Infinity, -Infinity);
  let any = false;
  const p = new Vector3();
  const q = new Quaternion();
  const w = new Vector3();
  const grow = (lo, hi) => {
    min.min(lo);
    max.max(hi);
    any = true;
  };
  const shapes = run.bodies.map((b) => b.shapes.map((s) => ({
    s, pos: toVec(s.position || [0, 0, 0]), rot: toQuat(s.orientation || [1, 0, 0, 0]), r: shapeRadius(s),
  })));
  // Every frame, as camera.cpp does; a sample of frames (and the last) for very long runs.
  const stride = Math.max(1, Math.floor((run.nf * run.nb) / 200000));
  const frames = [];
  for (let f = 0; f < run.nf; f += stride) frames.push(f);
  if (frames[frames.length - 1] !== run.nf - 1) frames.push(run.nf - 1);
  for (const f of frames) {
    for (let b = 0; b < run.nb; b++) {
      bodyPose(run, f, b, p, q);
      for (const { s, pos, rot, r } of shapes[b]) {
        if (s.type === 'plane') continue;
        if (s.type === 'mesh') {
          if (f !== 0 && run.bodies[b].isStatic) continue;
          for (const v of s.vertices || []) {
            w.set(v[0], v[1], v[2]).applyQuaternion(rot).add(pos).applyQuaternion(q).add(p);
            grow(w, w);
          }
          continue;
        }
        const c = pos.clone().applyQuaternion(q).add(p);
        grow(c.clone().subScalar(r), c.clone().addScalar(r));
      }
    }
  }
  if (!any) {
    for (let f = 0; f < run.nf; f++)
      for (let b = 0; b < run.nb; b++) {
        bodyPose(run, f, b, p, q);
        grow(p, p);
      }
  }
  if (!any) {
    min.set(0, 0, 0);
    max.set(0, 0, 0);
  }
  return { min, max, center: min.clone().add(max).multiplyScalar(0.5), radius: max.distanceTo(min) / 2 };
}

/// The automatic camera of camera.cpp (chooseCamera): the scene's view where given, otherwise the
/// bounds' centre seen from in front, a little to the side and above, the bounds' sphere fitting.
export function chooseCamera(run, bounds, aspect) {
  const view = run.view || {};
  const g = toVec(run.gravity);
  const up = view.up ? toVec(view.up).normalize()
    : g.length() > 0 ? g.clone().negate().normalize() : new Vector3(0, 0, 1);
  const fov = Number(view.fov) > 0 ? Number(view.fov) : 40;
  const target = view.target ? toVec(view.target) : bounds.center.clone();
  let eye;
  if (view.eye) {
    eye = toVec(view.eye);
  } else {
    let front = new Vector3(0, -1, 0).addScaledVector(up, up.y);
    if (front.length() < 0.5) front = new Vector3(-1, 0, 0).addScaledVector(up, up.x);
    front.normalize();
    const side = up.clone().cross(front);
    const extent = bounds.max.clone().sub(bounds.min);
    const height = Math.abs(extent.dot(up));
    const flat = extent.clone().addScaledVector(up, -extent.dot(up)).length();
    const elevation = height < 0.3 * flat ? 1.2 : 0.45;
    const dir = front.clone().addScaledVector(side, 0.35).addScaledVector(up, elevation).normalize();
    const half = (fov * Math.PI) / 360;
    const halfMin = Math.min(half, Math.atan(Math.tan(half) * aspect));
    const radius = Math.max(bounds.radius, 0.05);
    const distance = (1.08 * radius) / Math.sin(halfMin) + (view.target ? bounds.center.distanceTo(target) : 0);
    eye = target.clone().addScaledVector(dir, distance);
  }
  const look = target.clone().sub(eye).normalize();
  let u = up.clone().addScaledVector(look, -look.dot(up));
  if (u.length() < 1e-9) u = new Vector3(1, 0, 0).addScaledVector(look, -look.x);
  return { eye, target, up: u.normalize(), fov, worldUp: up };
}

function flatGeometry(vertices, triangles) {
  const pos = new Float32Array(triangles.length * 9);
  let k = 0;
  for (const t of triangles)
    for (const i of t) {
      const v = vertices[i];
      pos[k++] = v[0];
      pos[k++] = v[1];
      pos[k++] = v[2];
    }
  const geom = new BufferGeometry();
  geom.setAttribute('position', new BufferAttribute(pos, 3));
  geom.computeVertexNormals();
  return geom;
}

function zAxisGeometry(geom) {
  geom.rotateX(Math.PI / 2);  // three's round shapes are along y, linx's along z
  return geom;
}

const niceStep = (x) => {
  const p = 10 ** Math.floor(Math.log10(x));
  const m = x / p;
  return (m < 2 ? 1 : m < 5 ? 2 : 5) * p;
};

/// Builds everything drawn. Returns { root, bodies: [{group, meshes, materials}], pickables,
/// update(frame), setJointsVisible, setContactsVisible, dispose, ... }.
export function buildScene(run, bounds) {
  const root = new Group();
  const pickables = [];
  const R = Math.max(bounds.radius, 0.05);
  // Markers are sized by the scene and by its typical (median) body, so that they neither vanish
  // in a large scene nor swamp small bodies.
  const sizes = run.bodies.flatMap((b) => b.shapes.filter((s) => s.type !== 'plane' && s.type !== 'mesh').map(shapeRadius))
    .filter((r) => r > 0).sort((a, b) => a - b);
  const typical = sizes.length ? sizes[Math.floor(sizes.length / 2)] : R;
  const edgeMaterial = new LineBasicMaterial({ color: 0x1d2430, transparent: true, opacity: 0.35 });
  let colorIndex = 0;

  const bodies = run.bodies.map((body, bi) => {
    const group = new Group();
    group.name = body.name;
    group.userData.body = bi;
    const solid = body.shapes.some((s) => s.type !== 'plane');
    const color = body.isStatic ? STATIC_COLOR : PALETTE[solid ? colorIndex++ % PALETTE.length : 0];
    const material = new MeshStandardMaterial({ color, roughness: 0.55, metalness: 0.05, flatShading: false });
    const materials = [material];
    for (const s of body.shapes) {
      const holder = new Group();
      holder.position.copy(toVec(s.position || [0, 0, 0]));
      holder.quaternion.copy(toQuat(s.orientation || [1, 0, 0, 0]));
      let geom = null;
      let edges = false;
      switch (s.type) {
        case 'sphere':
          geom = new SphereGeometry(s.radius, 40, 20);
          break;
        case 'box':
          geom = new BoxGeometry(s.size[0], s.size[1], s.size[2]);
          edges = true;
          break;
        case 'ellipsoid':  // a unit sphere stretched by the semi-axes (normals recomputed)
          geom = new SphereGeometry(1, 40, 20);
          geom.scale(s.radii[0], s.radii[1], s.radii[2]);
          geom.computeVertexNormals();
          break;
        case 'capsule':
          geom = zAxisGeometry(new CapsuleGeometry(s.radius, s.length, 10, 32));
          break;
        case 'cylinder':
          geom = zAxisGeometry(new CylinderGeometry(s.radius, s.radius, s.length, 40));
          edges = true;
          break;
        case 'convex':
        case 'mesh':
          if (Array.isArray(s.vertices) && Array.isArray(s.triangles) && s.triangles.length) {
            geom = flatGeometry(s.vertices, s.triangles);
            edges = s.type === 'convex' || s.triangles.length < 5000;
          }
          break;
        case 'plane': {
          // A large finite ground: a plane and a grid around the scene's centre, seen from both sides.
          const n = toVec(s.normal || [0, 0, 1]).normalize();
          const d = Number(s.offset) || 0;
          const size = niceStep(Math.max(8 * R, 2)) * 2;
          const cell = niceStep(Math.max(size / 40, R / 4));
          // The scene centre, in the shape frame at frame 0, projected onto the plane.
          const p = new Vector3();
          const q = new Quaternion();
          bodyPose(run, 0, bi, p, q);
          const c = bounds.center.clone().sub(p).applyQuaternion(q.clone().invert())
            .sub(holder.position).applyQuaternion(holder.quaternion.clone().invert());
          c.addScaledVector(n, d - c.dot(n));
          // Snap to the grid so the lines stay put.
          const rot = new Quaternion().setFromUnitVectors(new Vector3(0, 0, 1), n);
          const local = c.clone().applyQuaternion(rot.clone().invert());
          local.x = Math.round(local.x / cell) * cell;
          local.y = Math.round(local.y / cell) * cell;
          const centre = local.applyQuaternion(rot);
          const groundMaterial = new MeshStandardMaterial({
            color: 0xf4f6f8, roughness: 0.95, metalness: 0, side: DoubleSide,
            polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
          });
          materials.push(groundMaterial);
          const plane = new Mesh(new PlaneGeometry(size, size), groundMaterial);
          plane.quaternion.copy(rot);
          plane.position.copy(centre);
          plane.receiveShadow = true;
          plane.userData.body = bi;
          plane.userData.ground = true;
          holder.add(plane);
          pickables.push(plane);
          // The grid's lines, in the plane's own xy coordinates (then turned like the plane).
          const half = Math.round(size / cell / 2);
          const lines = [];
          for (let i = -half; i <= half; i++) {
            const u = i * cell;
            lines.push(u, -half * cell, 0, u, half * cell, 0, -half * cell, u, 0, half * cell, u, 0);
          }
          const gridGeometry = new BufferGeometry();
          gridGeometry.setAttribute('position', new BufferAttribute(new Float32Array(lines), 3));
          const grid = new LineSegments(gridGeometry, new LineBasicMaterial({ color: 0xa9b4c1, transparent: true, opacity: 0.7 }));
          grid.quaternion.copy(rot);
          grid.position.copy(centre);
          holder.add(grid);
          break;
        }
        default:
          break;
      }
      if (geom) {
        const mesh = new Mesh(geom, material);
        mesh.castShadow = true;
        mesh.receiveShadow = true;
        mesh.userData.body = bi;
        holder.add(mesh);
        pickables.push(mesh);
        if (edges) holder.add(new LineSegments(new EdgesGeometry(geom, 25), edgeMaterial));
      }
      group.add(holder);
    }
    root.add(group);
    return { group, materials };
  });

  // Joint markers: a ball at each anchor and a short line along the axis of hinges and sliders.
  const joints = new Group();
  joints.name = 'joints';
  const jointSize = Math.min(R * 0.018, typical * 0.22);
  const jointMaterial = new MeshBasicMaterial({ color: JOINT_COLOR, depthTest: false, transparent: true, opacity: 0.9 });
  const jointBalls = new InstancedMesh(new SphereGeometry(jointSize, 16, 8), jointMaterial, Math.max(1, run.joints.length * 2));
  jointBalls.renderOrder = 10;
  jointBalls.frustumCulled = false;
  joints.add(jointBalls);
  const axisPositions = new Float32Array(Math.max(1, run.joints.length) * 6);
  const axisGeometry = new BufferGeometry();
  axisGeometry.setAttribute('position', new BufferAttribute(axisPositions, 3).setUsage(DynamicDrawUsage));
  const axisLines = new LineSegments(axisGeometry, new LineBasicMaterial({ color: JOINT_COLOR, depthTest: false }));
  axisLines.renderOrder = 10;
  axisLines.frustumCulled = false;
  joints.add(axisLines);
  root.add(joints);

  // Contacts: a dot at each point and an arrow along the normal, its length the force
  // (normal_impulse / timestep) scaled so the largest force of the run is 0.3 R long.
  const contacts = new Group();
  contacts.name = 'contacts';
  let maxContacts = 0;
  let maxForce = 0;
  if (run.contacts) {
    const { start, values } = run.contacts;
    for (let f = 0; f < run.nf; f++) maxContacts = Math.max(maxContacts, start[f + 1] - start[f]);
    for (let k = 0; k < start[run.nf]; k++) maxForce = Math.max(maxForce, Math.abs(values[k * 8 + 7]) / run.timestep);
  }
  const contactCapacity = Math.max(1, maxContacts);
  const dotSize = Math.min(R * 0.008, typical * 0.06);
  const contactMaterial = new MeshBasicMaterial({ color: CONTACT_COLOR, depthTest: false, transparent: true, opacity: 0.85 });
  const dots = new InstancedMesh(new SphereGeometry(dotSize, 12, 6), contactMaterial, contactCapacity);
  const heads = new InstancedMesh(new ConeGeometry(dotSize * 1.5, dotSize * 4, 12), contactMaterial, contactCapacity);
  const shaftPositions = new Float32Array(contactCapacity * 6);
  const shaftGeometry = new BufferGeometry();
  shaftGeometry.setAttribute('position', new BufferAttribute(shaftPositions, 3).setUsage(DynamicDrawUsage));
  const shafts = new LineSegments(shaftGeometry, new LineBasicMaterial({ color: CONTACT_COLOR, depthTest: false }));
  for (const o of [dots, heads, shafts]) {
    o.renderOrder = 11;
    o.frustumCulled = false;
    contacts.add(o);
  }
  contacts.visible = !!run.contacts;
  root.add(contacts);
  const forceScale = maxForce > 0 ? Math.min(0.3 * R, 2 * typical) / maxForce : 0;

  const p = new Vector3();
  const q = new Quaternion();
  const m = new Matrix4();
  const a1 = new Vector3();
  const a2 = new Vector3();
  const axis = new Vector3();
  const one = new Vector3(1, 1, 1);
  const yAxis = new Vector3(0, 1, 0);
  const world = (f, b, local, out) => {
    out.set(local[0], local[1], local[2]);
    if (b < 0) return out;
    bodyPose(run, f, b, p, q);
    return out.applyQuaternion(q).add(p);
  };
  let contactsDrawn = 0;

  function update(f) {
    for (let b = 0; b < run.nb; b++) {
      const { group } = bodies[b];
      bodyPose(run, f, b, group.position, group.quaternion);
    }
    // Joints.
    let n = 0;
    run.joints.forEach((j, k) => {
      world(f, j.body1, j.anchor1, a1);
      world(f, j.body2, j.anchor2, a2);
      jointBalls.setMatrixAt(n++, m.makeTranslation(a1.x, a1.y, a1.z));
      jointBalls.setMatrixAt(n++, m.makeTranslation(a2.x, a2.y, a2.z));
      if (j.axis1) {
        axis.set(j.axis1[0], j.axis1[1], j.axis1[2]).normalize();
        if (j.body1 >= 0) {
          bodyPose(run, f, j.body1, p, q);
          axis.applyQuaternion(q);
        }
        axis.multiplyScalar(jointSize * 4);
        axisPositions.set([a1.x - axis.x, a1.y - axis.y, a1.z - axis.z, a1.x + axis.x, a1.y + axis.y, a1.z + axis.z], k * 6);
      } else {
        axisPositions.fill(0, k * 6, k * 6 + 6);
      }
    });
    jointBalls.count = n;
    jointBalls.instanceMatrix.needsUpdate = true;
    axisGeometry.attributes.position.needsUpdate = true;
    axisGeometry.setDrawRange(0, run.joints.length * 2);
    // Contacts.
    contactsDrawn = 0;
    if (run.contacts) {
      const { start, values } = run.contacts;
      let c = 0;
      for (let k = start[f]; k < start[f + 1]; k++, c++) {
        const v = values.subarray(k * 8, k * 8 + 8);
        a1.set(v[0], v[1], v[2]);
        dots.setMatrixAt(c, m.makeTranslation(v[0], v[1], v[2]));
        axis.set(v[3], v[4], v[5]).normalize();
        const length = (v[7] / run.timestep) * forceScale;
        a2.copy(a1).addScaledVector(axis, length);
        shaftPositions.set([a1.x, a1.y, a1.z, a2.x, a2.y, a2.z], c * 6);
        if (Math.abs(length) > dotSize * 2) {
          q.setFromUnitVectors(yAxis, length >= 0 ? axis : axis.clone().negate());
          heads.setMatrixAt(c, m.compose(a2.clone().addScaledVector(axis, -Math.sign(length) * dotSize * 2.5), q, one));
        } else {
          heads.setMatrixAt(c, m.makeScale(0, 0, 0));
        }
      }
      contactsDrawn = c;
      dots.count = c;
      heads.count = c;
      dots.instanceMatrix.needsUpdate = true;
      heads.instanceMatrix.needsUpdate = true;
      shaftGeometry.attributes.position.needsUpdate = true;
      shaftGeometry.setDrawRange(0, c * 2);
    }
  }

  function dispose() {
    root.traverse((o) => {
      if (o.geometry) o.geometry.dispose();
      if (o.material) (Array.isArray(o.material) ? o.material : [o.material]).forEach((x) => x.dispose());
    });
  }

  return {
    root,
    bodies,
    pickables,
    joints,
    contacts,
    update,
    dispose,
    contactsDrawn: () => contactsDrawn,
    jointMarkers: () => jointBalls.count,
    highlight(bi, on) {
      for (const mat of bodies[bi].materials) mat.emissive = new Color(on ? 0x3a4a6a : 0x000000);
    },
  };
}
