// mbcosim replay viewer: statements inlined into the page's module script, after its loader
// has defined THREE (three.js), OrbitControls and DATA (the frames, see frames.rs).
// World frame z up; SI units. Shapes are matched across frames by name; a frame's `g` replaces
// the geometry of its shape from that frame on.
const frames = DATA.frames;
const roles = DATA.roles;
const names = Object.keys(roles);
const n = frames.length;
if (n === 0) throw new Error('the run has no frames');

// Colours and materials by role.
const STYLE = {
  satellite: { color: 0xb8bec8 },
  yoke: { color: 0x8c6a3c },
  panel: { color: 0x284f9e },
  hinge: { color: 0xe0a020 },
  block: { color: 0x9aa6b2, opacity: 0.85 },
  rope: { color: 0x303840 },
  contact_node: { color: 0xd02828 },
  hook: { color: 0xf08010 },
  load: { color: 0x7a3cb0 },
  ground: { color: 0xc8cfb8 },
};
const materialFor = (role) => {
  const s = STYLE[role] || { color: 0x888888 };
  return new THREE.MeshStandardMaterial({
    color: s.color, roughness: 0.6, metalness: 0.1, side: THREE.DoubleSide,
    transparent: s.opacity !== undefined, opacity: s.opacity === undefined ? 1 : s.opacity,
  });
};
const edgeMaterial = new THREE.LineBasicMaterial({ color: 0x101820 });

// For each name and frame: the index of the frame whose `g` is in effect (-1: none yet).
const geomFrame = {};
for (const name of names) {
  const at = new Int32Array(n);
  let last = -1;
  for (let i = 0; i < n; i++) {
    const e = frames[i].s[name];
    if (e && e.g) last = i;
    at[i] = last;
  }
  geomFrame[name] = at;
}

const withEdges = (geometry, material, angle) => {
  const group = new THREE.Group();
  group.add(new THREE.Mesh(geometry, material));
  group.add(new THREE.LineSegments(new THREE.EdgesGeometry(geometry, angle), edgeMaterial));
  return group;
};

// A three.js object for geometry `g` in the shape frame.
const build = (g, role) => {
  const material = materialFor(role);
  switch (g.kind) {
    case 'box':
      return withEdges(new THREE.BoxGeometry(g.size[0], g.size[1], g.size[2]), material, 1);
    case 'cylinder':
      return new THREE.Mesh(
        new THREE.CylinderGeometry(g.radius, g.radius, g.length, 24).rotateX(Math.PI / 2),
        material);
    case 'sphere':
      return new THREE.Mesh(new THREE.SphereGeometry(g.radius, 20, 14), material);
    case 'points': {
      const count = g.points.length / 3;
      const mesh = new THREE.InstancedMesh(
        new THREE.SphereGeometry(g.radius, 10, 8), material, Math.max(count, 1));
      mesh.count = count;
      const m = new THREE.Matrix4();
      for (let k = 0; k < count; k++) {
        m.makeTranslation(g.points[3 * k], g.points[3 * k + 1], g.points[3 * k + 2]);
        mesh.setMatrixAt(k, m);
      }
      mesh.frustumCulled = false;
      return mesh;
    }
    case 'polyline': {
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute('position', new THREE.Float32BufferAttribute(g.points, 3));
      const s = STYLE[role] || { color: 0x000000 };
      const line = new THREE.Line(geometry, new THREE.LineBasicMaterial({ color: s.color }));
      if (!(g.node_radius > 0) || g.points.length < 9) return line;
      const group = new THREE.Group();
      group.add(line);
      group.add(build({ kind: 'points', radius: g.node_radius, points: g.points.slice(3, -3) }, role));
      return group;
    }
    case 'mesh': {
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute('position', new THREE.Float32BufferAttribute(g.vertices, 3));
      geometry.setIndex(g.triangles);
      geometry.computeVertexNormals();
      return withEdges(geometry, material, 20);
    }
    default:
      throw new Error('unknown geometry kind ' + g.kind);
  }
};

const dispose = (obj) => obj.traverse((o) => {
  if (o.geometry) o.geometry.dispose();
  if (o.material && o.material !== edgeMaterial) o.material.dispose();
});

// Renderer, scene, camera.
const view = document.getElementById('view');
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio || 1);
view.appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0xeef1f5);
scene.add(new THREE.HemisphereLight(0xffffff, 0x8090a0, 1.6));
const sun = new THREE.DirectionalLight(0xffffff, 1.8);
sun.position.set(0.4, -0.6, 1.0);
scene.add(sun);
const camera = new THREE.PerspectiveCamera(40, 1, 0.01, 1000);
camera.up.set(0, 0, 1);
const controls = new OrbitControls(camera, renderer.domElement);

const objects = {};
let shown = -1;
const show = (i) => {
  const f = frames[i];
  for (const name of names) {
    const e = f.s[name];
    const gi = geomFrame[name][i];
    let o = objects[name];
    if (!e || gi < 0) {
      if (o) o.obj.visible = false;
      continue;
    }
    if (!o || o.gi !== gi) {
      if (o) { scene.remove(o.obj); dispose(o.obj); }
      o = objects[name] = { obj: build(frames[gi].s[name].g, roles[name]), gi };
      scene.add(o.obj);
    }
    const p = e.p;
    o.obj.visible = true;
    o.obj.position.set(p[0], p[1], p[2]);
    o.obj.quaternion.set(p[4], p[5], p[6], p[3]);
  }
  shown = i;
};

// Camera: looking at the box that holds the scene at a few times, from the front-right, above.
const bounds = new THREE.Box3();
for (const i of [0, n >> 2, n >> 1, (3 * n) >> 2, n - 1]) {
  show(i);
  for (const name of names) {
    const o = objects[name];
    if (o && o.obj.visible && roles[name] !== 'ground') bounds.expandByObject(o.obj);
  }
}
const centre = bounds.getCenter(new THREE.Vector3());
const radius = Math.max(bounds.getSize(new THREE.Vector3()).length() / 2, 1e-3);
const fitCamera = () => {
  const dir = new THREE.Vector3(0.5, -0.9, 1.0).normalize();
  const fov = THREE.MathUtils.degToRad(camera.fov);
  const fit = Math.min(fov, 2 * Math.atan(Math.tan(fov / 2) * camera.aspect));
  const dist = 1.05 * radius / Math.sin(fit / 2);
  camera.position.copy(centre).addScaledVector(dir, dist);
  camera.near = dist / 100;
  camera.far = dist * 100;
  camera.updateProjectionMatrix();
  controls.target.copy(centre);
  controls.update();
};
const resize = () => {
  const w = Math.max(view.clientWidth, 1);
  const h = Math.max(view.clientHeight, 1);
  renderer.setSize(w, h, false);
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
};
resize();
fitCamera();
window.addEventListener('resize', () => { resize(); render(); });

// Controls: play/pause, scrub, speed, time display; URL hash #t=SECONDS shows a time, paused.
const playButton = document.getElementById('play');
const scrub = document.getElementById('scrub');
const speed = document.getElementById('speed');
const timeText = document.getElementById('time');
document.getElementById('title').textContent =
  DATA.model + ': ' + n + ' frames, t = ' + frames[0].t.toFixed(3) + ' to ' +
  frames[n - 1].t.toFixed(3) + ' s';
scrub.max = String(n - 1);
const t0 = frames[0].t;
const tEnd = frames[n - 1].t;
// last frame with time <= t (frames are in time order)
const frameAt = (t) => {
  let lo = 0;
  let hi = n - 1;
  if (t >= frames[hi].t) return hi;
  while (lo < hi) {
    const mid = (lo + hi + 1) >> 1;
    if (frames[mid].t <= t + 1e-12 * Math.max(1, Math.abs(t))) lo = mid; else hi = mid - 1;
  }
  return lo;
};
const nearestFrame = (t) => {
  const i = frameAt(t);
  if (i + 1 < n && Math.abs(frames[i + 1].t - t) < Math.abs(frames[i].t - t)) return i + 1;
  return i;
};

let playing = false;
let current = 0;
let simTime = t0;
let lastWall = null;
const render = () => {
  if (current !== shown) show(current);
  scrub.value = String(current);
  timeText.textContent = 't = ' + frames[current].t.toFixed(3) + ' s / ' + tEnd.toFixed(3) + ' s';
  playButton.textContent = playing ? 'Pause' : 'Play';
  renderer.render(scene, camera);
};
const seek = (i) => {
  current = Math.min(Math.max(i, 0), n - 1);
  simTime = frames[current].t;
};
const fromHash = () => {
  const m = /(?:^#|&)t=([-+0-9.eE]+)/.exec(window.location.hash);
  if (!m) return false;
  playing = false;
  seek(nearestFrame(parseFloat(m[1])));
  return true;
};
playButton.addEventListener('click', () => {
  if (!playing && current === n - 1) seek(0);
  playing = !playing;
  lastWall = null;
  render();
});
scrub.addEventListener('input', () => {
  playing = false;
  seek(parseInt(scrub.value, 10));
  render();
});
window.addEventListener('hashchange', () => { if (fromHash()) render(); });
controls.addEventListener('change', () => { if (!playing) renderer.render(scene, camera); });

const tick = (now) => {
  if (playing) {
    if (lastWall !== null) simTime += (now - lastWall) / 1000 * parseFloat(speed.value);
    lastWall = now;
    if (simTime >= tEnd) {
      simTime = tEnd;
      playing = false;
    }
    current = frameAt(simTime);
    render();
  } else {
    lastWall = null;
  }
  requestAnimationFrame(tick);
};
if (!fromHash()) {
  seek(0);
  playing = true;
}
render();
document.body.dataset.ready = '1';
requestAnimationFrame(tick);
