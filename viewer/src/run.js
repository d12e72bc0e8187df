// A recorded run read from the files of a `linx run` output folder (docs/scene-format.md,
// "Outputs"): scene.json and the CSV files, given as texts by name. Frames are stored in flat
// typed arrays indexed [frame][body][component].

export const RUN_FILES = ['scene.json', 'bodies.csv', 'joints.csv', 'world.csv', 'contacts.csv'];

export class RunFormatError extends Error {}

function fail(file, where, problem) {
  throw new RunFormatError(`${file}: ${where}: ${problem}`);
}

// Rows of a CSV text (RFC 4180: fields may be double-quoted, with "" for a quote and line breaks
// inside quotes). Returns arrays of strings; the fast path splits lines without quotes.
export function parseCsv(text) {
  const rows = [];
  if (!text.includes('"')) {
    for (const line of text.split('\n')) {
      const l = line.endsWith('\r') ? line.slice(0, -1) : line;
      if (l.length) rows.push(l.split(','));
    }
    return rows;
  }
  let row = [];
  let field = '';
  let i = 0;
  const n = text.length;
  while (i < n) {
    const c = text[i];
    if (c === '"' && field === '') {
      let j = i + 1;
      for (;;) {
        const q = text.indexOf('"', j);
        if (q < 0) throw new RunFormatError('unterminated quoted field');
        field += text.slice(j, q);
        if (text[q + 1] === '"') {
          field += '"';
          j = q + 2;
        } else {
          i = q + 1;
          break;
        }
      }
    } else if (c === ',') {
      row.push(field);
      field = '';
      i++;
    } else if (c === '\n' || c === '\r') {
      row.push(field);
      field = '';
      if (row.length > 1 || row[0] !== '') rows.push(row);
      row = [];
      i += c === '\r' && text[i + 1] === '\n' ? 2 : 1;
    } else {
      const next = text.slice(i).search(/[,\r\n]/);
      const end = next < 0 ? n : i + next;
      field += text.slice(i, end);
      i = end;
    }
  }
  if (field !== '' || row.length) {
    row.push(field);
    rows.push(row);
  }
  return rows;
}

function columns(file, header, names) {
  const idx = {};
  for (const name of names) {
    const k = header.indexOf(name);
    if (k < 0) fail(file, 'line 1', `no column "${name}"`);
    idx[name] = k;
  }
  return idx;
}

function number(file, line, text) {
  const v = Number(text);
  if (text === '' || !Number.isFinite(v)) fail(file, `line ${line}`, `not a number: "${text}"`);
  return v;
}

function vec(v, fallback = [0, 0, 0]) {
  return Array.isArray(v) && v.length === 3 ? v.map(Number) : fallback;
}

/// files: { 'scene.json': text, 'bodies.csv': text, ... }; name: what to call the run.
export function parseRun(files, name) {
  if (files['scene.json'] === undefined)
    throw new RunFormatError('scene.json: missing (rerun the scene with a linx that writes it)');
  if (files['bodies.csv'] === undefined) throw new RunFormatError('bodies.csv: missing');
  let scene;
  try {
    scene = JSON.parse(files['scene.json']);
  } catch (e) {
    throw new RunFormatError(`scene.json: not JSON (${e.message})`);
  }
  if (scene.format !== 'linx-run' || !Array.isArray(scene.bodies))
    throw new RunFormatError('scene.json: not the scene.json of a linx run (format "linx-run")');

  const bodies = scene.bodies.map((b, i) => ({
    index: i,
    name: String(b.name),
    isStatic: !!b.static,
    mass: b.mass,
    shapes: Array.isArray(b.shapes) ? b.shapes : [],
  }));
  const bodyIndex = new Map(bodies.map((b) => [b.name, b.index]));
  const joints = (Array.isArray(scene.joints) ? scene.joints : []).map((j) => ({
    name: String(j.name),
    type: j.type,
    body1: j.body1 === 'world' ? -1 : bodyIndex.get(j.body1) ?? -1,
    body2: j.body2 === 'world' ? -1 : bodyIndex.get(j.body2) ?? -1,
    anchor1: vec(j.anchor1),
    anchor2: vec(j.anchor2),
    axis1: j.axis1 ? vec(j.axis1) : null,
    axis2: j.axis2 ? vec(j.axis2) : null,
  }));
  const nb = bodies.length;

  // bodies.csv: one block of nb rows per frame.
  const rows = parseCsv(files['bodies.csv']);
  if (!rows.length) fail('bodies.csv', 'line 1', 'empty file');
  const cols = ['time', 'body', 'x', 'y', 'z', 'qw', 'qx', 'qy', 'qz', 'vx', 'vy', 'vz', 'wx', 'wy', 'wz'];
  const c = columns('bodies.csv', rows[0], cols);
  const data = rows.length - 1;
  if (nb === 0 || data % nb !== 0 || data === 0)
    fail('bodies.csv', `line ${rows.length}`, `${data} rows is not a whole number of frames of ${nb} bodies`);
  const nf = data / nb;
  const times = new Float64Array(nf);
  const pos = new Float64Array(nf * nb * 3);
  const quat = new Float64Array(nf * nb * 4);
  const vel = new Float64Array(nf * nb * 3);
  const omega = new Float64Array(nf * nb * 3);
  for (let f = 0; f < nf; f++) {
    for (let k = 0; k < nb; k++) {
      const line = 2 + f * nb + k;
      const r = rows[line - 1];
      const bi = bodyIndex.get(r[c.body]);
      if (bi === undefined) fail('bodies.csv', `line ${line}`, `unknown body "${r[c.body]}"`);
      const t = number('bodies.csv', line, r[c.time]);
      if (k === 0) times[f] = t;
      else if (t !== times[f]) fail('bodies.csv', `line ${line}`, `time ${t} within the frame at ${times[f]}`);
      const o = f * nb + bi;
      pos[o * 3] = number('bodies.csv', line, r[c.x]);
      pos[o * 3 + 1] = number('bodies.csv', line, r[c.y]);
      pos[o * 3 + 2] = number('bodies.csv', line, r[c.z]);
      quat[o * 4] = number('bodies.csv', line, r[c.qw]);
      quat[o * 4 + 1] = number('bodies.csv', line, r[c.qx]);
      quat[o * 4 + 2] = number('bodies.csv', line, r[c.qy]);
      quat[o * 4 + 3] = number('bodies.csv', line, r[c.qz]);
      vel[o * 3] = number('bodies.csv', line, r[c.vx]);
      vel[o * 3 + 1] = number('bodies.csv', line, r[c.vy]);
      vel[o * 3 + 2] = number('bodies.csv', line, r[c.vz]);
      omega[o * 3] = number('bodies.csv', line, r[c.wx]);
      omega[o * 3 + 1] = number('bodies.csv', line, r[c.wy]);
      omega[o * 3 + 2] = number('bodies.csv', line, r[c.wz]);
    }
  }
  const frameOfTime = new Map();
  times.forEach((t, f) => frameOfTime.set(t, f));

  // joints.csv (optional for drawing): coordinate and error per joint per frame.
  const nj = joints.length;
  const jointCoord = new Float64Array(nf * nj).fill(NaN);
  const jointError = new Float64Array(nf * nj).fill(NaN);
  if (files['joints.csv'] !== undefined && nj) {
    const jr = parseCsv(files['joints.csv']);
    const jc = columns('joints.csv', jr[0] || [], ['time', 'joint', 'coordinate', 'error']);
    const jointIndex = new Map(joints.map((j, i) => [j.name, i]));
    for (let i = 1; i < jr.length; i++) {
      const f = frameOfTime.get(Number(jr[i][jc.time]));
      const ji = jointIndex.get(jr[i][jc.joint]);
      if (f === undefined || ji === undefined) continue;
      if (jr[i][jc.coordinate] !== '') jointCoord[f * nj + ji] = Number(jr[i][jc.coordinate]);
      jointError[f * nj + ji] = Number(jr[i][jc.error]);
    }
  }

  // world.csv (optional): energies per frame.
  const world = { kinetic: new Float64Array(nf).fill(NaN), potential: new Float64Array(nf).fill(NaN) };
  if (files['world.csv'] !== undefined) {
    const wr = parseCsv(files['world.csv']);
    const wc = columns('world.csv', wr[0] || [], ['time', 'kinetic_energy', 'potential_energy']);
    for (let i = 1; i < wr.length; i++) {
      const f = frameOfTime.get(Number(wr[i][wc.time]));
      if (f === undefined) continue;
      world.kinetic[f] = Number(wr[i][wc.kinetic_energy]);
      world.potential[f] = Number(wr[i][wc.potential_energy]);
    }
  }

  // contacts.csv (with --contacts): rows grouped by frame.
  let contacts = null;
  if (files['contacts.csv'] !== undefined) {
    const cr = parseCsv(files['contacts.csv']);
    const cc = columns('contacts.csv', cr[0] || [],
      ['time', 'body1', 'body2', 'x', 'y', 'z', 'nx', 'ny', 'nz', 'depth', 'normal_impulse']);
    const perFrame = Array.from({ length: nf }, () => []);
    for (let i = 1; i < cr.length; i++) {
      const r = cr[i];
      const f = frameOfTime.get(number('contacts.csv', i + 1, r[cc.time]));
      if (f === undefined) continue;  // a frame not recorded in bodies.csv
      perFrame[f].push(i);
    }
    const start = new Int32Array(nf + 1);
    for (let f = 0; f < nf; f++) start[f + 1] = start[f] + perFrame[f].length;
    const n = start[nf];
    const values = new Float64Array(n * 8);
    const pair = new Int32Array(n * 2);
    let k = 0;
    for (let f = 0; f < nf; f++) {
      for (const i of perFrame[f]) {
        const r = cr[i];
        const line = i + 1;
        const v = [r[cc.x], r[cc.y], r[cc.z], r[cc.nx], r[cc.ny], r[cc.nz], r[cc.depth], r[cc.normal_impulse]];
        for (let m = 0; m < 8; m++) values[k * 8 + m] = number('contacts.csv', line, v[m]);
        pair[k * 2] = bodyIndex.get(r[cc.body1]) ?? -1;
        pair[k * 2 + 1] = bodyIndex.get(r[cc.body2]) ?? -1;
        k++;
      }
    }
    contacts = { start, values, pair };
  }

  const g = vec(scene.gravity, [0, 0, -9.81]);
  return {
    name,
    source: scene.source || '',
    timestep: Number(scene.timestep) > 0 ? Number(scene.timestep) : 0.001,
    gravity: g,
    view: scene.view || null,
    bodies,
    joints,
    nb,
    nf,
    times,
    pos,
    quat,
    vel,
    omega,
    jointCoord,
    jointError,
    world,
    contacts,
  };
}
